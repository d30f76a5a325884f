"""MuJoCo 3's implicitfast integrator: lever against the real MuJoCo 3 package (pip's `mujoco`).

The Panda (models/panda7.xml, its integrator switched to implicitfast in text made here) runs
1 s from its `home` keyframe, thrown at 1 rad/s on every joint under its position servos, in
lever and in MuJoCo 3. The yardstick is MuJoCo 3's own sensitivity: the same MuJoCo run with its
initial qpos nudged by 1e-15 (as tests/diff/free_run.cpp measures it for 2.2.2). lever's implicit
against MuJoCo 3's implicit shows the two agree on this model otherwise; lever's implicit against
MuJoCo 3's implicitfast shows that the test could fail (the Coriolis terms matter here).

Needs `mujoco` 3.x importable beside the built lever package (a venv: pip install mujoco==3.1.6
"numpy<2"; lever's array views need numpy 1.x); skipped where it is absent (CI's Debian Python has
only MuJoCo 2.2.2's C library).
"""
import pathlib

import pytest

mujoco = pytest.importorskip("mujoco")
if int(mujoco.__version__.split(".")[0]) < 3:
    pytest.skip(f"mujoco {mujoco.__version__} is not MuJoCo 3", allow_module_level=True)

import lever  # noqa: E402
import numpy as np  # noqa: E402

REPO = pathlib.Path(__file__).resolve().parents[2]
PANDA = REPO / "models" / "panda7.xml"
STEPS = 500  # 1 s at the file's 2 ms
NUDGE = 1e-15
GENEROSITY = 100.0  # as tests/diff/free_run.cpp: a wrong term shows as O(1), far beyond it


def panda_text(integrator: str) -> str:
    text = PANDA.read_text(encoding="utf-8")
    assert 'integrator="implicit"' in text
    return text.replace('integrator="implicit"', f'integrator="{integrator}"')


def start(qpos0, nq):
    qvel = np.ones(nq)
    ctrl = np.array(qpos0[:7])  # the servos hold home
    return qvel, ctrl


def run_mujoco(integrator: str, nudge: float = 0.0) -> np.ndarray:
    m = mujoco.MjModel.from_xml_string(panda_text(integrator))
    d = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, d, 0)
    d.qvel[:], d.ctrl[:] = start(d.qpos, m.nv)
    d.qpos[0] += nudge
    for _ in range(STEPS):
        mujoco.mj_step(m, d)
    return np.concatenate([d.qpos, d.qvel])


def run_lever(integrator: str) -> np.ndarray:
    model = lever.load_string(panda_text(integrator), str(PANDA))
    data = lever.Data(model)
    # the keyframe as MuJoCo reads it from the same text (its qvel and ctrl are zero)
    m = mujoco.MjModel.from_xml_string(panda_text(integrator))
    qvel, ctrl = start(m.key_qpos[0], model.nv)
    data.qpos[:] = [float(x) for x in m.key_qpos[0]]
    data.qvel[:] = [float(x) for x in qvel]
    data.ctrl[:] = [float(x) for x in ctrl]
    for _ in range(STEPS):
        lever.step(model, data)
    return np.array([*data.qpos, *data.qvel], dtype=float)


def bound(reference: np.ndarray, sensitivity: float) -> float:
    return GENEROSITY * sensitivity + 1e-12 * max(1.0, float(np.abs(reference).max()))


def test_implicitfast_follows_mujoco_3():
    theirs = run_mujoco("implicitfast")
    sensitivity = float(np.abs(run_mujoco("implicitfast", NUDGE) - theirs).max())
    ours = run_lever("implicitfast")
    error = float(np.abs(ours - theirs).max())
    print(f"implicitfast: lever vs MuJoCo {mujoco.__version__} {error:.3g}, "
          f"MuJoCo's own sensitivity {sensitivity:.3g}")
    assert error <= bound(theirs, sensitivity)


def test_implicit_agrees_with_mujoco_3_on_this_model():
    theirs = run_mujoco("implicit")
    sensitivity = float(np.abs(run_mujoco("implicit", NUDGE) - theirs).max())
    error = float(np.abs(run_lever("implicit") - theirs).max())
    print(f"implicit: lever vs MuJoCo {mujoco.__version__} {error:.3g}, sensitivity {sensitivity:.3g}")
    assert error <= bound(theirs, sensitivity)


def test_implicitfast_is_not_implicit():
    theirs = run_mujoco("implicitfast")
    sensitivity = float(np.abs(run_mujoco("implicitfast", NUDGE) - theirs).max())
    error = float(np.abs(run_lever("implicit") - theirs).max())
    assert error > bound(theirs, sensitivity)
