"""lever.derivatives and lever.mujoco's mjd_transitionFD (analytic, docs/derivatives.md) through
contacts: against MuJoCo's own Python package (the pinned version, whose physics on box_drop and
the gripper agrees with MuJoCo 2.2.2's, test_mujoco_oracle.py) differenced at tolerance 0, and
against the C++ command bit for bit.

The states are those of tests/derivatives/contacts.cpp: box_drop resting on a face and pressed
into the table, the gripper in the air and squeezing the box, each with pyramidal, frictionless
(condim 1) and elliptic cones (inside the cone), under Euler and implicit (mjd_transitionFD,
centred) and RK4 (the pinned mjd_transitionFD refuses RK4: mj_step differenced here, qpos moved with
mj_integratePos and read back with mj_differentiatePos, as mjd_transitionFD does). Bound: 1e-6 of
the matrix's scale max(1, max |MuJoCo's entry|), at eps 1e-6 and 1e-5; where a contact is within
solimp's width the impedance makes aref cubic in the distance, and the 1e-5 differences are
Richardson-extrapolated with 2e-5 (as the C++ test does, docs/derivatives.md)."""
import json
import subprocess
import warnings

import numpy as np
import pytest

import lever
import lever.mujoco as ours
from conftest import REPO

real = pytest.importorskip("mujoco")

BOUND = 1e-6
EULER, RK4, IMPLICIT = 0, 1, 2  # mjtIntegrator
CONES = ("pyramidal", "frictionless", "elliptic")


def model_text(name, cone):
    text = (REPO / "models" / name).read_text()
    if cone == "elliptic":  # the models' <option> gets MuJoCo's cone attribute
        if "<option " in text:
            text = text.replace("<option ", '<option cone="elliptic" ', 1)
        else:
            text = text.replace("<worldbody>", '<option cone="elliptic"/>\n<worldbody>', 1)
    return text


def pair(name, cone, integrator):
    """MuJoCo's model (solver to convergence) and lever.mujoco's, the same cone and integrator."""
    text = model_text(name, cone)
    rm = real.MjModel.from_xml_string(text)
    rm.opt.tolerance = 0
    rm.opt.iterations = 1000
    om = ours.MjModel.from_xml_string(text)
    for m in (rm, om):
        if cone == "frictionless":
            m.geom_condim[:] = 1
        m.opt.integrator = integrator
    return rm, om


def settle(rm, rd, steps):
    for _ in range(steps):
        real.mj_step(rm, rd)


# scene -> (model file, how the state is reached in MuJoCo, whether a contact sits within
# solimp's width, where the impedance is curved)
def box_resting(rm, rd, cone):
    settle(rm, rd, 600)
    rd.qvel[:] = [0.02, -0.01, 0.01, 0.1, -0.2, 0.05]


def box_pressed(rm, rd, cone):
    rd.qpos[:] = [0.01, -0.02, 0.028, np.cos(0.005), np.sin(0.005), 0, 0]
    rd.qvel[:] = [0.05, -0.02, 0.01, 0.1, -0.2, 0.05]


def gripper_in_air(rm, rd, cone):
    q = np.array([-0.1, 0.01, 0.02, 0.15, 0.1, 0.12, 0.9, 0.1, 0.3, 0.2])
    q[6:] /= np.linalg.norm(q[6:])
    rd.qpos[:] = q
    rd.qvel[:] = [0.1, -0.05, 0.05, 0.2, -0.1, 0.3, 1.0, -0.5, 0.2]
    rd.ctrl[:] = [-0.05, 0.02, 0.03]


def gripper_grasping(rm, rd, cone):
    real.mj_resetDataKeyframe(rm, rd, 0)
    rd.ctrl[:] = [-0.235, 0.045, 0.045]
    settle(rm, rd, 400)
    if cone != "frictionless":  # lifted: friction holds the box up
        rd.ctrl[0] = -0.2
        settle(rm, rd, 200)


SCENES = {
    "box_drop resting": ("box_drop.xml", box_resting, True),
    "box_drop pressed in": ("box_drop.xml", box_pressed, False),
    "gripper in the air": ("gripper.xml", gripper_in_air, False),
    "gripper grasping": ("gripper.xml", gripper_grasping, True),
}


def step_differences(rm, rd, eps):
    """A and B by centred differences of MuJoCo's mj_step in tangent space."""
    nv, nu = rm.nv, rm.nu

    def stepped(dx, du):
        d = real.MjData(rm)
        d.qpos[:], d.qvel[:], d.ctrl[:], d.time = rd.qpos, rd.qvel, rd.ctrl, rd.time
        real.mj_integratePos(rm, d.qpos, dx[:nv], 1.0)
        d.qvel[:] += dx[nv:]
        d.ctrl[:] += du
        real.mj_step(rm, d)
        return d.qpos.copy(), d.qvel.copy()

    q0, _ = stepped(np.zeros(2 * nv), np.zeros(nu))

    def x_of(q, v):
        dq = np.zeros(nv)
        real.mj_differentiatePos(rm, dq, 1.0, q0, q)
        return np.concatenate([dq, v])

    def column(dx, du):
        plus, minus = x_of(*stepped(dx, du)), x_of(*stepped(-dx, -du))
        return (plus - minus) / (2 * eps)

    A = np.column_stack([column(eps * e, np.zeros(nu)) for e in np.eye(2 * nv)])
    B = np.zeros((2 * nv, nu))
    for u, e in enumerate(np.eye(nu)):
        B[:, u] = column(np.zeros(2 * nv), eps * e)
    return A, B


def mujoco_jacobians(rm, rd, eps):
    n = 2 * rm.nv
    if rm.opt.integrator == RK4:
        return step_differences(rm, rd, eps)
    A, B = np.zeros((n, n)), np.zeros((n, rm.nu))
    real.mjd_transitionFD(rm, rd, eps, 1, A, B, None, None)
    return A, B


def ratio_to_bound(ours_matrix, theirs):
    if theirs.size == 0:
        return 0.0
    return np.abs(ours_matrix - theirs).max() / (BOUND * max(1.0, np.abs(theirs).max()))


CASES = [(scene, cone, integrator) for scene in SCENES for cone in CONES
         for integrator in (EULER, RK4, IMPLICIT)
         if not (scene == "gripper in the air" and cone != "pyramidal")]


@pytest.mark.parametrize("scene,cone,integrator", CASES,
                         ids=[f"{s}-{c}-{('euler', 'rk4', 'implicit')[i]}" for s, c, i in CASES])
def test_mjd_transitionFD_against_mujoco_differenced(scene, cone, integrator):
    name, reach, curved = SCENES[scene]
    rm, om = pair(name, cone, integrator)
    rd = real.MjData(rm)
    reach(rm, rd, cone)
    od = ours.MjData(om)
    od.qpos[:], od.qvel[:], od.ctrl[:], od.time = rd.qpos, rd.qvel, rd.ctrl, rd.time
    n = 2 * om.nv
    A, B = np.full((n, n), np.nan), np.full((n, om.nu), np.nan)
    qpos = od.qpos.copy()
    with warnings.catch_warnings(record=True) as warned:
        warnings.simplefilter("always")
        ours.mjd_transitionFD(om, od, 1e-6, 1, A, B, None, None)
    # the box pressed in with pyramids: the rows' set at the step's end is not the start's (the
    # flag and its warning); the differences around the start still keep its set
    changes = [w for w in warned if "active set changes" in str(w.message)]
    assert len(changes) == (scene == "box_drop pressed in" and cone == "pyramidal")
    assert np.array_equal(od.qpos, qpos)  # the state is left as it was, bit for bit
    real.mj_forward(rm, rd)
    assert (rd.ncon > 0) == (scene != "gripper in the air")
    assert od.nefc == rd.nefc
    for eps in (1e-6, 1e-5):
        theirs_A, theirs_B = mujoco_jacobians(rm, rd, eps)
        if curved and eps > 1e-6:
            wide_A, wide_B = mujoco_jacobians(rm, rd, 2 * eps)
            theirs_A, theirs_B = (4 * theirs_A - wide_A) / 3, (4 * theirs_B - wide_B) / 3
        assert ratio_to_bound(A, theirs_A) <= 1, f"A, eps {eps}"
        assert ratio_to_bound(B, theirs_B) <= 1, f"B, eps {eps}"


def test_dqacc_dapplied_against_mujoco_forward_differenced():
    """d qacc / d qfrc_applied squeezing the box: MuJoCo's mj_forward differenced (qacc is affine in
    qfrc_applied while the active set holds, so the difference has no truncation)."""
    rm, om = pair("gripper.xml", "pyramidal", IMPLICIT)
    rd = real.MjData(rm)
    gripper_grasping(rm, rd, "pyramidal")
    data = lever.Data(om._native)
    data.qpos[:], data.qvel[:], data.ctrl[:] = rd.qpos, rd.qvel, rd.ctrl
    out = lever.derivatives(om._native, data)
    eps = 1e-6
    columns = []
    for i in range(rm.nv):
        acc = []
        for sign in (1, -1):
            rd.qfrc_applied[:] = 0
            rd.qfrc_applied[i] = sign * eps
            real.mj_forward(rm, rd)
            acc.append(rd.qacc.copy())
        columns.append((acc[0] - acc[1]) / (2 * eps))
    theirs = np.column_stack(columns)
    assert ratio_to_bound(out["dqacc_dapplied"], theirs) <= 1
    # with no row pushing it is M^-1
    free = lever.Data(om._native)
    free.qpos[:] = [0, 0, 0, 0.3, 0.2, 0.3, 1, 0, 0, 0]
    lever.forward(om._native, free)
    assert free.nefc == 0
    np.testing.assert_allclose(lever.derivatives(om._native, free)["dqacc_dapplied"] @ free.M,
                               np.eye(om.nv), atol=1e-12)


def test_derivatives_are_the_commands_bit_for_bit(lever_cli):
    """lever.derivatives at the gripper's grasp equals `lever derivatives --settle --json` (the C++
    library, each double written in the shortest form that reads back as itself)."""
    path = str(REPO / "models" / "gripper.xml")
    ctrl = [-0.235, 0.045, 0.045]
    out = subprocess.run([lever_cli, "derivatives", path, "--key", "open", "--ctrl",
                          ",".join(map(repr, ctrl)), "--settle", "300", "--json"],
                         capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    theirs = json.loads(out.stdout)
    model = lever.load(path)
    data = lever.Data(model)
    lever.reset_keyframe(model, data, "open")
    data.ctrl[:] = ctrl
    for _ in range(300):
        lever.step(model, data)
    assert np.array_equal(data.qpos, theirs["qpos"]) and np.array_equal(data.qvel, theirs["qvel"])
    mine = lever.derivatives(model, data)
    assert mine["nefc"] == theirs["nefc"] > 0
    assert mine["active_set_changes"] is theirs["active_set_changes"] is False
    for key in ("A", "B", "dqacc_dq", "dqacc_dv", "dqacc_du", "dqacc_dapplied"):
        assert np.array_equal(mine[key].ravel(), theirs[key]), key
    assert np.array_equal(mine["A"], lever.step_derivatives(model, data)[0])


def test_a_set_that_changes_is_flagged_and_warned():
    model = lever.load(str(REPO / "models" / "box_drop.xml"))
    data = lever.Data(model)
    data.qpos[:] = [0, 0, 0.0301, 1, 0, 0, 0]  # 0.1 mm above the table, falling at 1 m/s
    data.qvel[:] = [0, 0, -1, 0, 0, 0]
    with pytest.warns(RuntimeWarning, match="active set changes"):
        assert lever.derivatives(model, data)["active_set_changes"]


@pytest.mark.filterwarnings("ignore:lever.derivatives")  # qpos0: the box drops onto the table
def test_mjd_transitionFD_signature_and_refusals():
    om = ours.MjModel.from_xml_path(str(REPO / "models" / "gripper.xml"))
    od = ours.MjData(om)
    n = 2 * om.nv
    B = np.zeros((n, om.nu))
    ours.mjd_transitionFD(om, od, 1e-6, 0, None, B, None, None)  # None skips a matrix
    assert np.abs(B).max() > 0
    with pytest.raises(ValueError, match="A must be 18 x 18"):
        ours.mjd_transitionFD(om, od, 1e-6, 0, np.zeros((n, n + 1)), None, None, None)
    with pytest.raises(TypeError, match="C-contiguous float64"):
        ours.mjd_transitionFD(om, od, 1e-6, 0, np.zeros((n, n)).T, None, None, None)
    sensors = ours.MjModel.from_xml_path(str(REPO / "tests" / "models" / "sensors.xml"))
    sd = ours.MjData(sensors)
    ns, nv2, nu2 = sensors.nsensordata, 2 * sensors.nv, sensors.nu
    assert ns > 0
    with pytest.raises(NotImplementedError, match="C and D"):
        ours.mjd_transitionFD(sensors, sd, 1e-6, 0, None, None, np.zeros((ns, nv2)),
                              np.zeros((ns, nu2)))
    A = np.zeros((nv2, nv2))
    ours.mjd_transitionFD(sensors, sd, 1e-6, 0, A, None, None, None)
    assert "analytic" in ours.mjd_transitionFD.__doc__.lower()


def test_the_docs_worked_example_is_the_programs_output():
    """docs/derivatives.md's worked example shows what examples/python/gripper_grasp_sensitivity.py
    prints, whole, and the program's claims hold: a symmetric squeeze neither shifts nor turns the
    box, and the left finger pushes it towards -y."""
    import os
    import sys
    examples = REPO / "examples" / "python"
    env = dict(os.environ, LEVER_MODELS=str(REPO / "models"),
               PYTHONPATH=os.pathsep.join([str(examples), os.environ.get("PYTHONPATH", "")]))
    out = subprocess.run([sys.executable, str(examples / "gripper_grasp_sensitivity.py")],
                         capture_output=True, text=True, env=env, timeout=120)
    assert out.returncode == 0, out.stderr
    doc = (REPO / "docs" / "derivatives.md").read_text()
    assert "```\n" + out.stdout + "```\n" in doc
    rows = {line[:36].strip(): line[36:].split() for line in out.stdout.splitlines()[2:]}
    assert rows["box y, one step (mm)"][2] == rows["box roll about x, one step (mrad)"][2] == "0.0"
    assert float(rows["box y, one step (mm)"][0]) < 0 < float(rows["box y, one step (mm)"][1])
    assert "active set changes within the step: no" in out.stdout


SHAPES = {"box": 'type="box" size="0.05 0.05 0.05"', "cylinder": 'type="cylinder" size="0.03 0.03"',
          "ellipsoid": 'type="ellipsoid" size="0.03 0.04 0.03"'}


def resting_on(upper, lower):
    """The upper geom, free, come to rest on the lower one (centred above it)."""
    xml = (f'<mujoco><worldbody><geom {SHAPES[lower]}/><body pos="0 0 0.085"><freejoint/>'
           f'<geom {SHAPES[upper]} mass="1"/></body></worldbody></mujoco>')
    model = lever.load_string(xml)
    data = lever.Data(model)
    for _ in range(200):
        lever.step(model, data)
    return model, data


def test_mpr_contact_is_differentiated():
    """An ellipsoid resting on a box: a pair MuJoCo collides by MPR, its search replayed on dual
    numbers (tests/derivatives/mpr_pairs.cpp compares such pairs with MuJoCo's differences)."""
    model, data = resting_on("ellipsoid", "box")
    assert data.ncon == 1
    out = lever.derivatives(model, data)
    assert out["A"].shape == (2 * model.nv, 2 * model.nv)
    assert np.isfinite(out["A"]).all()


def test_mpr_contact_where_the_search_is_degenerate_is_refused_by_name():
    """A cylinder standing centred on a box: MPR's search ends on its first segment (the origin on
    the line of the centres), which any motion leaves; refused, naming the pair."""
    model = lever.load_string(f'<mujoco><worldbody><geom {SHAPES["box"]}/><body pos="0 0 0.079">'
                              f'<freejoint/><geom {SHAPES["cylinder"]}/></body></worldbody></mujoco>')
    data = lever.Data(model)
    lever.forward(model, data)
    assert data.ncon == 1
    with pytest.raises(lever.Error, match="contact 0 \\(cylinder-box, MPR\\) is where MPR's search"):
        lever.derivatives(model, data)


def test_dqacc_dact_is_forward_differenced_in_the_activations():
    """d qacc / d act on tests/models/actuators/muscles.xml (filters, an integrator, muscles; na 6)
    at its key "tense": lever.forward differenced in each activation (qacc is affine in act while
    no force is clamped, so the centred difference has rounding only). A model without stateful
    actuators gets an empty block."""
    model = lever.load(str(REPO / "tests" / "models" / "actuators" / "muscles.xml"))
    assert model.na == 6
    data = lever.Data(model)
    lever.reset_keyframe(model, data, "tense")
    act = data.act.copy()
    out = lever.derivatives(model, data)
    assert out["dqacc_dact"].shape == (model.nv, model.na)
    eps = 1e-6
    columns = []
    for i in range(model.na):
        acc = []
        for sign in (1, -1):
            data.act[:] = act
            data.act[i] += sign * eps
            lever.forward(model, data)
            acc.append(data.qacc.copy())
        columns.append((acc[0] - acc[1]) / (2 * eps))
    theirs = np.column_stack(columns)
    assert np.abs(theirs).max() > 1  # the activations move the arm
    assert ratio_to_bound(out["dqacc_dact"], theirs) <= 1e-3
    plain = lever.load(str(REPO / "models" / "arm2.xml"))
    assert lever.derivatives(plain, lever.Data(plain))["dqacc_dact"].shape == (plain.nv, 0)


def test_dqacc_dact_is_the_commands_bit_for_bit(lever_cli):
    """`lever derivatives --json` writes d qacc / d act (nv x na, row-major) as lever.derivatives
    returns it, at muscles.xml's key "tense"."""
    path = str(REPO / "tests" / "models" / "actuators" / "muscles.xml")
    out = subprocess.run([lever_cli, "derivatives", path, "--key", "tense", "--json"],
                         capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    theirs = json.loads(out.stdout)
    model = lever.load(path)
    data = lever.Data(model)
    lever.reset_keyframe(model, data, "tense")
    mine = lever.derivatives(model, data)["dqacc_dact"]
    assert mine.shape == (model.nv, model.na) and np.abs(mine).max() > 0
    assert np.array_equal(mine.ravel(), theirs["dqacc_dact"])
