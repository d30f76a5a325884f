"""The Python package is the C++ engine: on every model, at seeded random states, every array of
the field table after forward() and after a step equals what the `lever` command (C++, the same
library) prints for the same state, bit for bit (its JSON writes each double in the shortest
form that reads back as the same double)."""
import json
import subprocess

import numpy as np
import pytest

import lever
from conftest import MODEL_FILES


def random_state(model, rng):
    """Each joint's coordinates: a limited one near its range, a free one's position and any
    quaternion (not unit: forward normalizes it, in the state too), else U(-3, 3)."""
    qpos = rng.uniform(-3, 3, model.nq)
    for j in range(model.njnt):
        adr = model.jnt_qposadr[j]
        if model.jnt_limited[j]:
            lo, hi = model.jnt_range[j]
            qpos[adr] = rng.uniform(lo - 0.01, hi + 0.01)
    return qpos, rng.normal(0, 1, model.nv), rng.uniform(-2, 2, model.nu)


def as_arg(values) -> str:
    return ",".join(repr(float(x)) for x in values)


def cli_json(cli, args):
    out = subprocess.run([cli, *args], capture_output=True, text=True, timeout=120)
    assert out.returncode in (0, 1), out.stderr
    return [json.loads(line) for line in out.stdout.splitlines() if line.startswith("{")]


def compare_fields(model, data, theirs):
    compared = 0
    for field in lever.data_field_table():
        name = field["name"]
        if name not in theirs or field["stage"] in ("inverse",):
            continue
        ours = np.asarray(getattr(data, name), dtype=float).ravel()
        ref = np.array([np.nan if x is None else x for x in theirs[name]], dtype=float)
        assert ours.shape == ref.shape, name
        assert np.array_equal(ours, ref, equal_nan=True), (name, ours, ref)
        compared += 1
    assert compared >= 30


@pytest.mark.parametrize("path", MODEL_FILES, ids=lambda p: p.name)
def test_forward_bit_for_bit(path, lever_cli):
    model = lever.load(str(path))
    data = lever.Data(model)
    rng = np.random.default_rng(sum(path.name.encode()))
    for _ in range(5):
        qpos, qvel, ctrl = random_state(model, rng)
        lever.reset(model, data)
        data.qpos[:], data.qvel[:], data.ctrl[:] = qpos, qvel, ctrl
        lever.forward(model, data)
        lever.compute_energy(model, data)  # `lever forward` prints the energy too
        args = ["forward", str(path), "--json", "--qpos", as_arg(qpos), "--qvel", as_arg(qvel)]
        if model.nu:
            args += ["--ctrl", as_arg(ctrl)]
        (theirs,) = cli_json(lever_cli, args)
        compare_fields(model, data, theirs)


@pytest.mark.parametrize("path", MODEL_FILES, ids=lambda p: p.name)
def test_steps_bit_for_bit(path, lever_cli):
    model = lever.load(str(path))
    data = lever.Data(model)
    rng = np.random.default_rng(7 + sum(path.name.encode()))
    qpos, qvel, ctrl = random_state(model, rng)
    data.qpos[:], data.qvel[:], data.ctrl[:] = qpos, qvel, ctrl
    rows = []
    lever.lab_run(model, data, ctrl, False, 20,
                  lambda k, d: rows.append((d.qpos.copy(), d.qvel.copy(), d.qacc.copy())))
    args = ["simulate", str(path), "--steps", "20", "--json", "--qpos", as_arg(qpos),
            "--qvel", as_arg(qvel)]
    if model.nu:
        args += ["--ctrl", as_arg(ctrl)]
    theirs = cli_json(lever_cli, args)
    assert len(theirs) == len(rows) == 21
    for (q, v, a), row in zip(rows, theirs):
        assert np.array_equal(q, row["qpos"]) and np.array_equal(v, row["qvel"])
        assert np.array_equal(a, np.array(row["qacc"], dtype=float))
