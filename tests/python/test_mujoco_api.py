"""lever.mujoco against MuJoCo's documented Python API: names, shapes, dtypes, named access,
writes followed by mj_setConst, the split step, and what lever lacks raising NotImplementedError.
Shapes and dtypes are checked against MuJoCo 2.2.2's own mjxmacro.h when it is installed."""
import pathlib
import re

import numpy as np
import pytest

import lever
import lever.mujoco as mujoco
from lever import _mujoco_names
from conftest import MODEL_FILES, REPO

ARM2 = REPO / "models" / "arm2.xml"
MJXMACRO = pathlib.Path("/usr/include/mujoco/mjxmacro.h")


@pytest.fixture
def arm2():
    model = mujoco.MjModel.from_xml_path(str(ARM2))
    return model, mujoco.MjData(model)


def mujoco_shapes(macro: str) -> dict:
    text = MJXMACRO.read_text()
    start = text.index("#define " + macro + " ")
    block = text[start:text.index("\n\n", start)]
    out = {}
    for ctype, name, rows, cols in re.findall(
            r"X\w*\s*\(\s*(\w+)\s*,\s*(\w+)\s*,\s*(\w+)\s*,\s*(\w+|MJ_M\(\w+\))\s*\)", block):
        out[name] = (ctype, rows, re.sub(r"MJ_M\((\w+)\)", r"\1", cols))  # MJ_M(n): a model size
    return out


DTYPES = {"mjtNum": np.float64, "int": np.int32, "mjtByte": np.uint8}


@pytest.mark.skipif(not MJXMACRO.is_file(), reason="MuJoCo's headers (libmujoco-dev) not here")
@pytest.mark.parametrize("path", MODEL_FILES, ids=lambda p: p.name)
def test_shapes_and_dtypes_are_mujocos(path):
    model = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    sizes = {n: getattr(model, n)
             for n in ("nq", "nv", "nu", "nbody", "njnt", "ngeom", "nsite", "npair", "nexclude",
                       "nsensor", "nsensordata", "neq", "nmocap", "nmesh",
                       "nmeshvert", "nmeshgraph", "nmeshface", "ntendon", "nwrap", "nuser_body", "nuser_jnt",
                       "nuser_geom", "nuser_site", "nuser_tendon", "nuser_actuator", "nuser_sensor",
                       "na")}
    sizes["nefc"] = data.nefc
    # mjmodel.h's lengths of solref, solimp, gainprm, biasprm, dynprm and eq_data
    sizes.update(mjNREF=2, mjNIMP=5, mjNGAIN=10, mjNBIAS=10, mjNDYN=10, mjNEQDATA=11)
    sizes["njmax"] = data.nefc  # 2.2.2 sizes efc arrays njmax; its Python shows the live rows
    for macro, obj, names in (("MJMODEL_POINTERS", model, mujoco._MODEL_FIELDS),
                              ("MJDATA_POINTERS", data, mujoco._DATA_FIELDS)):
        table = mujoco_shapes(macro)
        table["energy"] = ("mjtNum", "1", "2")  # MJDATA_VECTOR: a flat (2,) array
        table["solver_fwdinv"] = ("mjtNum", "1", "2")
        for name in names:
            ctype, rows, cols = table[name]
            array = getattr(obj, name)
            n = sizes[rows] if rows in sizes else int(rows)
            c = sizes[cols] if not cols.isdigit() else int(cols)
            expected = (n,) if c == 1 else (c,) if rows == "1" else (n, c)
            assert array.shape == expected, name
            assert array.dtype == DTYPES[ctype], name


def test_the_name_list_is_mujocos():
    if not MJXMACRO.is_file():
        pytest.skip("MuJoCo's headers (libmujoco-dev) not here")
    for macro in ("MJMODEL_POINTERS",):
        assert {n: rows for n, (_, rows, _) in mujoco_shapes(macro).items()}.items() <= \
            _mujoco_names.MODEL.items()
    assert {n: rows for n, (_, rows, _) in mujoco_shapes("MJDATA_POINTERS").items()}.items() <= \
        _mujoco_names.DATA.items()


def test_named_access(arm2):
    model, data = arm2
    shoulder = model.joint("shoulder")
    assert shoulder.id == 0 and shoulder.name == "shoulder"
    assert model.joint(0).name == "shoulder"
    np.testing.assert_array_equal(shoulder.axis, model.jnt_axis[0])
    assert shoulder.range.shape == (2,)
    assert model.body("link2").mass.shape == (1,)
    assert model.body("link2").mass[0] == model.body_mass[model.body("link2").id]
    assert model.actuator("elbow").ctrlrange[1] == model.actuator_ctrlrange[1, 1]
    data.qpos[:] = [0.6, -1.2]
    mujoco.mj_forward(model, data)
    ee = data.site("ee")
    np.testing.assert_array_equal(ee.xpos, data.site_xpos[0])
    assert ee.xmat.shape == (9,)
    assert data.joint("elbow").qpos[0] == -1.2
    assert data.actuator("shoulder").force[0] == data.actuator_force[0]
    assert mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, "ee") == 0
    assert mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, "nope") == -1
    assert mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, 1) == "elbow"


def test_unknown_names_raise_keyerror_naming_them(arm2):
    model, data = arm2
    with pytest.raises(KeyError, match="wrist"):
        model.joint("wrist")
    with pytest.raises(KeyError, match="tip"):
        data.site("tip")
    with pytest.raises(IndexError):
        model.body(17)


def test_views_are_zero_copy_and_writable(arm2):
    model, data = arm2
    view = data.qpos
    view[:] = [0.3, 0.2]
    assert data.qpos[0] == 0.3 and np.shares_memory(view, data.qpos)
    data.qvel = [1.0, -1.0]  # assignment copies into lever's array, as MuJoCo's bindings do
    assert data.qvel[1] == -1.0


def test_write_mass_then_set_const_equals_a_model_written_so(arm2):
    model, data = arm2
    model.body_mass[2] = 1.6
    mujoco.mj_setConst(model, data)
    xml = ARM2.read_text().replace('mass="0.8"', 'mass="1.6"')
    assert 'mass="1.6"' in xml
    heavy = mujoco.MjModel.from_xml_string(xml)
    for name in ("dof_M0", "dof_invweight0", "body_subtreemass", "body_invweight0"):
        np.testing.assert_array_equal(getattr(model, name), getattr(heavy, name), err_msg=name)
    d2 = mujoco.MjData(heavy)
    data.qpos[:] = d2.qpos[:] = [0.1, 0.2]
    mujoco.mj_forward(model, data)
    mujoco.mj_forward(heavy, d2)
    np.testing.assert_array_equal(data.qfrc_bias, d2.qfrc_bias)


def test_step_leaves_what_mujoco_leaves(arm2):
    model, data = arm2
    data.qpos[:] = [0.6, -1.2]
    other = mujoco.MjData(model)
    other.qpos[:] = [0.6, -1.2]
    mujoco.mj_forward(model, other)
    mujoco.mj_step(model, data)
    # the forward quantities are those of the state before the step; the state is the new one
    np.testing.assert_array_equal(data.qfrc_bias, other.qfrc_bias)
    np.testing.assert_array_equal(data.qacc, other.qacc)
    assert data.time == model.opt.timestep
    assert not np.array_equal(data.qpos, other.qpos)


def test_split_step_equals_step(arm2):
    model, data = arm2
    split = mujoco.MjData(model)
    for d in (data, split):
        d.qpos[:] = [0.6, -1.2]
        d.ctrl[:] = [3.0, -1.0]
    for _ in range(50):
        mujoco.mj_step(model, data)
        mujoco.mj_step1(model, split)
        mujoco.mj_step2(model, split)
    np.testing.assert_array_equal(data.qpos, split.qpos)
    np.testing.assert_array_equal(data.qvel, split.qvel)


def test_dynamics_functions_agree_with_each_other(arm2):
    model, data = arm2
    data.qpos[:] = [0.4, 0.9]
    data.qvel[:] = [0.3, -0.7]
    mujoco.mj_forward(model, data)
    M = np.zeros((2, 2))
    mujoco.mj_fullM(model, data, M)
    res = np.zeros(2)
    mujoco.mj_mulM(model, data, res, data.qacc)
    np.testing.assert_allclose(res, M @ data.qacc, rtol=0, atol=1e-15)
    x = np.zeros(2)
    mujoco.mj_solveM(model, data, x, res)
    np.testing.assert_allclose(x, data.qacc, rtol=1e-12, atol=1e-12)
    rne = np.zeros(2)
    mujoco.mj_rne(model, data, 0, rne)
    np.testing.assert_array_equal(rne, data.qfrc_bias)
    data.ctrl[:] = [2.0, -1.0]
    mujoco.mj_forward(model, data)
    mujoco.mj_inverse(model, data)  # at forward's own qacc: the force the motors apply
    np.testing.assert_allclose(data.qfrc_inverse, data.qfrc_actuator, rtol=0, atol=1e-12)
    jacp, jacr = np.zeros((3, 2)), np.zeros((3, 2))
    mujoco.mj_jacSite(model, data, jacp, jacr, 0)
    jp2 = np.zeros((3, 2))
    mujoco.mj_jac(model, data, jp2, None, data.site_xpos[0], model.site_bodyid[0])
    np.testing.assert_array_equal(jacp, jp2)
    mujoco.mj_energyPos(model, data)
    mujoco.mj_energyVel(model, data)
    np.testing.assert_allclose(data.energy[1], 0.5 * data.qvel @ M @ data.qvel, rtol=1e-12)


def test_joint_stop_rows(arm2):
    model, data = arm2
    data.qpos[:] = [-1.205, 0.0]
    mujoco.mj_forward(model, data)
    assert data.nefc == 1
    assert list(data.efc_type) == [mujoco.mjtConstraint.mjCNSTR_LIMIT_JOINT]
    assert data.efc_id[0] == 0 and data.qfrc_constraint[0] > 0


def test_what_lever_lacks_raises_not_implemented(arm2):
    model, data = arm2
    with pytest.raises(NotImplementedError, match="qLDiagSqrtInv"):
        data.qLDiagSqrtInv
    with pytest.raises(NotImplementedError, match="cam_fovy"):
        model.cam_fovy
    with pytest.raises(NotImplementedError, match="mj_collision"):
        mujoco.mj_collision(model, data)
    with pytest.raises(NotImplementedError, match="xfrc_applied"):
        data.body(0).xfrc_applied
    np.testing.assert_array_equal(data.geom(0).xpos, data.geom_xpos[0])  # lever computes it
    with pytest.raises(AttributeError):
        data.qpso
    with pytest.raises(ValueError, match="keyframe"):
        mujoco.mj_resetDataKeyframe(model, data, 0)


def test_bad_input_raises(arm2, tmp_path):
    model, data = arm2
    with pytest.raises(ValueError):
        data.qpos[:] = [1.0, 2.0, 3.0]
    bad = tmp_path / "bad.xml"
    bad.write_text('<mujoco>\n<worldbody>\n<body><joint rnage="0 1"/></body>\n</worldbody>\n</mujoco>\n')
    with pytest.raises(lever.ParseError) as err:
        mujoco.MjModel.from_xml_path(str(bad))
    assert err.value.line == 3 and "bad.xml:3" in str(err.value) and err.value.attribute == "rnage"
    with pytest.raises(lever.ParseError):
        mujoco.MjModel.from_xml_string("<mujoco><worldbody>")
    # MuJoCo's functions use the model they are given: another model of the same sizes is
    # taken, one of other sizes refused
    mujoco.mj_forward(mujoco.MjModel.from_xml_path(str(ARM2)), data)
    other = mujoco.MjModel.from_xml_path(str(ARM2.parent / "arm3.xml"))
    with pytest.raises(ValueError, match="another model"):
        mujoco.mj_forward(other, data)
    data.qpos[0] = np.nan
    mujoco.mj_step(model, data)  # a bad state is reset and recorded, as mj_step does
    assert data._native.warning_count == 1 and "qpos" in data._native.warnings
    assert data.time == model.opt.timestep  # reset to time 0, then the step from qpos0


def test_lever_api_data_from_another_model_is_refused():
    model = lever.load(str(ARM2))
    other = lever.load(str(ARM2))
    with pytest.raises(lever.StateError, match="another Model"):
        lever.forward(other, lever.Data(model))
    with pytest.raises(lever.StateError, match="qacc"):
        lever.rnea(model, lever.Data(model), np.zeros(3))


def test_check_report_is_structured():
    report = lever.check(lever.load(str(ARM2)))
    assert report["exit_status"] == 0 and report["findings"] == []
    joints = {j["joint"]: j for j in report["torque_budget"]["joints"]}
    model = lever.load(str(ARM2))
    data = lever.Data(model)
    data.qpos[:] = 0
    lever.forward(model, data)
    assert joints["shoulder"]["worst_gravity_torque"] == pytest.approx(data.qfrc_bias[0], abs=1e-12)


def test_derivatives_and_regressor_from_python():
    model = lever.load(str(ARM2))
    data = lever.Data(model)
    data.qpos[:] = [0.4, 0.9]
    data.qvel[:] = [0.3, -0.7]
    data.ctrl[:] = [1.0, 0.5]
    A, B = lever.step_derivatives(model, data)
    assert A.shape == (4, 4) and B.shape == (4, 2)
    # against central differences of the step itself (the error of a 1e-6 central difference of
    # a smooth step is ~1e-10 of its scale; the tolerance says that, not lever's agreement bound)
    eps = 1e-6
    for u in range(2):
        cols = []
        for sign in (1, -1):
            d = lever.Data(model)
            d.qpos[:], d.qvel[:], d.ctrl[:] = data.qpos, data.qvel, data.ctrl
            d.ctrl[u] += sign * eps
            lever.step(model, d)
            cols.append(np.concatenate([d.qpos, d.qvel]))
        np.testing.assert_allclose(B[:, u], (cols[0] - cols[1]) / (2 * eps), atol=1e-8)
    qacc = np.array([0.2, -1.0])
    Y = lever.regressor(model, data, qacc)
    pi = lever.model_parameters(model)
    assert len(lever.regressor_names(model)) == Y.shape[1] == pi.size
    # the gain columns move the motors' torque to the parameter side (no clamp binds here)
    lever.forward(model, data)
    tau = lever.rnea(model, data, qacc) + model.dof_damping * data.qvel - data.qfrc_actuator
    assert np.abs(data.qfrc_actuator).max() > 0.1
    np.testing.assert_allclose(Y @ pi, tau, rtol=0, atol=1e-12 * max(1, np.abs(tau).max()))


def test_ball_and_free_joints_named_access_and_position_calculus():
    """A ball's named qpos is its quaternion and its qvel three rates; a free joint's 7 and 6.
    mj_integratePos turns quaternions and keeps them unit; mj_differentiatePos undoes it."""
    model = mujoco.MjModel.from_xml_path(str(REPO / "tests" / "models" / "floating.xml"))
    data = mujoco.MjData(model)
    assert (model.nq, model.nv) == (20, 17)
    assert data.joint("shoulder").qpos.shape == (4,)
    assert data.joint("shoulder").qvel.shape == (3,)
    assert data.joint("float").qpos.shape == (7,)
    assert data.joint("float").qvel.shape == (6,)
    assert model.joint("spin").qpos0.shape == (7,)
    np.testing.assert_array_equal(model.joint("shoulder").qpos0, [1, 0, 0, 0])
    data.joint("shoulder").qvel[:] = [0.5, -1.0, 2.0]  # a view: writes reach the state
    assert data.qvel[model.jnt_dofadr[1] + 2] == 2.0

    rng = np.random.default_rng(5)
    qpos = data.qpos.copy()
    qvel = rng.normal(0, 1, model.nv)
    mujoco.mj_integratePos(model, qpos, qvel, 0.01)
    for j, adr in ((0, 3), (1, model.jnt_qposadr[1]), (4, model.jnt_qposadr[4] + 3)):
        assert abs(np.linalg.norm(qpos[adr:adr + 4]) - 1) < 1e-15
    back = np.zeros(model.nv)
    mujoco.mj_differentiatePos(model, back, 0.01, data.qpos, qpos)
    # the round trip loses the quaternion's rounding (~1e-16) divided by dt = 0.01, and the
    # angle's atan2: far below 1e-11; a wrong axis or sign would be O(1)
    np.testing.assert_allclose(back, qvel, rtol=0, atol=1e-11)


def test_the_generated_name_file_is_current():
    """python/lever/_mujoco_names.py is what python/scripts/mujoco_names.py writes from the
    installed MuJoCo 2.2.2 headers."""
    if not MJXMACRO.is_file():
        pytest.skip("MuJoCo's headers (libmujoco-dev) not here")
    import subprocess
    import sys
    script = REPO / "python" / "scripts" / "mujoco_names.py"
    out = subprocess.run([sys.executable, str(script), str(MJXMACRO.parent)], capture_output=True,
                         text=True, timeout=60, check=True).stdout
    assert out.strip() == pathlib.Path(_mujoco_names.__file__).read_text().strip()
