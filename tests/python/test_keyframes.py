"""Keyframes from Python: the model's key_* arrays, lever.reset_keyframe and lever.mujoco's
mj_resetDataKeyframe against the file's numbers, lever.check(key=...), and lesson 5.2's program."""
import re
import subprocess
import sys
import os
import xml.etree.ElementTree as ET

import numpy as np
import pytest

import lever
import lever.mujoco as mujoco

from conftest import REPO

PANDA = REPO / "models" / "panda7.xml"


def file_keyframe():
    key = ET.parse(PANDA).getroot().find("keyframe").find("key")
    return key.get("name"), np.array(key.get("qpos").split(), float), np.array(key.get("ctrl").split(), float)


def test_keyframe_arrays_are_the_files():
    name, qpos, ctrl = file_keyframe()
    model = lever.load(str(PANDA))
    assert model.nkey == 1 and model.key_name == [name]
    assert model.key_qpos.shape == (1, model.nq) and model.key_ctrl.shape == (1, model.nu)
    np.testing.assert_array_equal(model.key_qpos[0], qpos)
    np.testing.assert_array_equal(model.key_ctrl[0], ctrl)
    np.testing.assert_array_equal(model.key_qvel[0], np.zeros(model.nv))


def test_reset_keyframe_by_name_and_index():
    name, qpos, ctrl = file_keyframe()
    model = lever.load(str(PANDA))
    data = lever.Data(model)
    lever.reset_keyframe(model, data, name)
    np.testing.assert_array_equal(data.qpos, qpos)
    np.testing.assert_array_equal(data.ctrl, ctrl)
    data.qpos[:] = 0
    lever.reset_keyframe(model, data, 0)
    np.testing.assert_array_equal(data.qpos, qpos)
    with pytest.raises(lever.StateError, match="'home'"):
        lever.reset_keyframe(model, data, "nosuch")


def test_mujoco_reset_data_keyframe():
    _, qpos, ctrl = file_keyframe()
    m = mujoco.MjModel.from_xml_path(str(PANDA))
    d = mujoco.MjData(m)
    assert m.nkey == 1
    mujoco.mj_resetDataKeyframe(m, d, 0)
    np.testing.assert_array_equal(d.qpos, qpos)
    np.testing.assert_array_equal(d.ctrl, ctrl)
    np.testing.assert_array_equal(m.key_qpos[0], qpos)
    with pytest.raises(ValueError):
        mujoco.mj_resetDataKeyframe(m, d, 1)


def test_check_at_a_keyframe():
    report = lever.check(lever.load(str(PANDA)), key="home")
    assert report["step_stability"]["states"][0]["where"] == "keyframe home"
    assert [s["where"] for s in report["singular_poses"]["sites"][0]["states"]] == [
        "qpos0", "keyframe home"]
    with pytest.raises(lever.StateError):
        lever.check(lever.load(str(PANDA)), key="nosuch")


def test_lesson_5_2_program():
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(
        [str(REPO / "examples" / "python"), env.get("PYTHONPATH", "")])
    result = subprocess.run([sys.executable, str(REPO / "examples" / "python" / "l5_2_seven_dof.py")],
                            capture_output=True, text=True, env=env, timeout=300)
    assert result.returncode == 0, result.stderr
    line = next(l for l in result.stdout.splitlines() if "spectral radius of the step" in l)
    implicit, euler = (float(x) for x in re.findall(r"(?:implicit|Euler) ([0-9.]+)", line))
    assert implicit < 1 < euler
