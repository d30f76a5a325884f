"""lever.identify: the estimate, its standard errors and the identified model, from a CSV file
(the same numbers as `lever identify --json` on it) and from arrays a Python loop logged."""
import json
import subprocess

import numpy as np
import pytest

import lever
from conftest import REPO

ARM2 = REPO / "models" / "arm2.xml"


def heavy_arm2_text() -> str:
    """arm2.xml with link 2 twice as heavy (mass, inertia) and its centre of mass further out."""
    text = ARM2.read_text(encoding="utf-8")
    old = ('<inertial pos="0.2 0 0" mass="0.8" '
           'diaginertia="0.0001 0.0106666666666667 0.0106666666666667"/>')
    assert old in text
    return text.replace(old, '<inertial pos="0.25 0 0" mass="1.6" '
                             'diaginertia="0.0002 0.0213333333333334 0.0213333333333334"/>')


def worst_inverse_difference(a, b, states=30):
    """The largest difference of qfrc_inverse between two models at random states, relative to
    max(1, |qfrc_inverse|)."""
    rng = np.random.default_rng(7)
    da, db = lever.Data(a), lever.Data(b)
    worst = 0.0
    for _ in range(states):
        qpos = rng.uniform(a.jnt_range[:, 0], a.jnt_range[:, 1])
        qvel, qacc = rng.normal(0, 1, a.nv), rng.normal(0, 5, a.nv)
        for model, data in ((a, da), (b, db)):
            data.qpos[:], data.qvel[:], data.qacc[:] = qpos, qvel, qacc
            lever.inverse(model, data)
        worst = max(worst, np.max(np.abs(da.qfrc_inverse - db.qfrc_inverse))
                    / max(1.0, np.max(np.abs(da.qfrc_inverse))))
    return worst


def test_identify_a_csv_as_the_command_does(lever_cli, tmp_path):
    truth_file, csv, written = tmp_path / "truth.xml", tmp_path / "run.csv", tmp_path / "out.xml"
    truth_file.write_text(heavy_arm2_text(), encoding="utf-8")
    subprocess.run([lever_cli, "simulate", str(truth_file), "--excite", "0.8", "--duration", "4",
                    "--csv", str(csv)], check=True, capture_output=True, timeout=120)
    result = lever.identify(str(ARM2), csv, write_model=written)
    out = subprocess.run([lever_cli, "identify", str(ARM2), str(csv), "--json"],
                         capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    command = json.loads(out.stdout)
    assert result["names"] == [p["name"] for p in command["base"]]
    # the same library on the same file: the same numbers (the JSON's 17 digits round-trip)
    assert list(result["estimate"]) == [p["estimate"] for p in command["base"]]
    assert list(result["standard_error"]) == [p["standard_error"] for p in command["base"]]
    assert list(result["physical_estimate"]) == [p["physical"] for p in command["base"]]
    assert result["estimate_physical"] is True and command["estimate_physical"] is True
    assert result["residual_rms"] == command["residual_rms"]
    assert result["not_physical"] is None
    # the written model and the returned one are the truth on held-out states (noise-free:
    # the 1e-8 target)
    assert result["written"] == str(written)
    truth = lever.load(str(truth_file))
    assert worst_inverse_difference(truth, lever.load(str(written))) < 1e-8
    assert worst_inverse_difference(truth, result["model"]) < 1e-8


def test_identify_arrays_a_python_loop_logged():
    prior = lever.load(str(ARM2))
    truth = lever.copy_model(prior)
    truth.body_mass[2] = 1.6
    truth.body_inertia[2] *= 2
    lever.set_const(truth)
    data = lever.Data(truth)
    log = {key: [] for key in ("time", "qpos", "qvel", "qacc", "qfrc", "ctrl", "actuator_force")}
    for step in range(3000):
        time = data.time
        ref = 0.4 * np.sin(2 * np.pi * np.array([0.5, 0.8]) * time + np.array([0.0, 1.0]))
        data.ctrl[:] = 60 * (ref - data.qpos) - 8 * data.qvel
        lever.forward(truth, data)
        log["time"].append(time)
        log["qpos"].append(data.qpos.copy())
        log["qvel"].append(data.qvel.copy())
        log["qacc"].append(data.qacc.copy())
        log["qfrc"].append(data.qfrc_actuator + data.qfrc_constraint)
        log["ctrl"].append(data.ctrl.copy())
        log["actuator_force"].append(data.actuator_force.copy())
        lever.step(truth, data)
    arrays = {key: np.array(rows) for key, rows in log.items()}
    trajectory = {key: arrays[key] for key in ("time", "qpos", "qvel", "qacc", "qfrc")}
    result = lever.identify(prior, trajectory)
    k = len(result["names"])
    assert result["estimate"].shape == result["standard_error"].shape == (k,)
    assert np.all(result["standard_error"] >= 0)
    assert result["residual_rms"] < 1e-9
    assert result["estimate_physical"]
    assert worst_inverse_difference(truth, result["model"]) < 1e-8
    assert result["written"] is None
    # the motors' forces and commands instead of the joint force: the same estimate
    by_motor = {key: arrays[key] for key in ("time", "qpos", "qvel", "qacc", "ctrl",
                                             "actuator_force")}
    np.testing.assert_allclose(lever.identify(prior, by_motor)["estimate"], result["estimate"],
                               rtol=0, atol=1e-9)  # other rows, same least squares: rounding
    # every gain estimated and nothing absolute: refused with the reason
    with pytest.raises(lever.Error, match="scale together"):
        lever.identify(prior, by_motor, gains="all")
    with pytest.raises(lever.Error, match="needs the trajectory's ctrl"):
        lever.identify(prior, trajectory, gains="all")
    with pytest.raises(lever.Error, match="no body 'link9'"):
        lever.identify(prior, trajectory, known_masses={"link9": 1.0})
