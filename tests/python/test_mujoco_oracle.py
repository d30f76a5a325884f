"""lever.mujoco against MuJoCo's own Python package from pip (the version tests/python/
requirements.txt pins, whose physics on models/*.xml agrees with MuJoCo 2.2.2's to 1e-12), on the
same model at the same state: every name lever.mujoco offers (MjModel and MjData arrays and
sizes, model.opt, the named accessors model.body(...) / data.geom(...) / data.joint(i) / ...,
data.contact with its indexing, slicing and member arrays, the enums, the functions of __all__,
from_xml_path / from_xml_string, keyframes) is compared for type, shape, dtype, writability and
value (|lever - mujoco| <= 1e-12 max(1, |mujoco|)); every MuJoCo 2.2.2 name lever lacks raises
NotImplementedError. The few places where the pinned MuJoCo lays a name out differently from 2.2.2
(and so from lever) are listed in LAYOUT with the reason, and checked to still differ."""
import numpy as np
import pytest

import lever.mujoco as ours
from lever import _mujoco_names
from conftest import REPO

real = pytest.importorskip("mujoco")  # MuJoCo's package (make test installs it: requirements.txt)

MODELS = sorted(REPO.glob("models/*.xml"))
CONTACT_MODELS = [REPO / "models" / "box_drop.xml", REPO / "models" / "gripper.xml"]
TOLERANCE = 1e-12

# names the pinned MuJoCo shows otherwise than MuJoCo 2.2.2 (whose layout lever keeps): name ->
# (what differs, why); each is still compared for value
LAYOUT = {
    "efc_J": ("MuJoCo 3.x shows the dense rows flattened, (nefc * nv,); 2.2.2 (njmax, nv); lever "
              "(nefc, nv)", "reshape"),
    "dof_Madr": ("lever computes it from dof_parentid: read-only", "writable"),
    "qM": ("lever keeps M dense; qM is read from it on each access: read-only", "writable"),
    "nconmax": ("MuJoCo 3.x sizes contacts on the fly (-1); 2.2.2 and lever hold nconmax", "value"),
    "njmax": ("MuJoCo 3.x sizes constraint rows on the fly (-1); 2.2.2 and lever hold njmax",
              "value"),
    "body_inertia": ("MuJoCo 3.x keeps an axis-aligned inertia's axes in the body's order; 2.2.2 "
                     "sorts the principal moments (the same tensor, axes permuted)", "principal"),
    "body_iquat": ("the principal axes of body_inertia, permuted with it", "principal"),
    "ximat": ("the principal axes of body_inertia in the world, permuted with it",
              "principal in the world"),
    "tendon_lengthspring": ("MuJoCo 3.x holds a dead band, (ntendon, 2), low and high equal for a "
                            "2.2.2 file; 2.2.2 and lever one length (ntendon,)", "deadband"),
    "qacc_warmstart": ("MuJoCo 3.x saves it when a step ends; 2.2.2 and lever in each forward's "
                       "constraint solve (mj_fwdConstraint): the forward's qacc", "warmstart"),
    "actuator_moment": ("MuJoCo 3.x keeps it sparse (moment_rownnz, moment_rowadr, moment_colind); "
                        "2.2.2 and lever dense (nu, nv)", "sparse"),
}
# names the pinned MuJoCo gave another name: lever's (2.2.2's) name -> the pinned MuJoCo's
RENAMED = {
    "eq_active": "eq_active0",  # MuJoCo 3 keeps the compiled value as eq_active0 (data.eq_active
                                # is its run-time switch)
}
# MuJoCo 3.4's data.joint(i).cdof and .cdof_dot read the (nv, 6) array at offset dof, not at row
# dof (a window of the flattened array): compared with MuJoCo's own rows instead
ACCESSOR_ROWS = {("data", "joint", "cdof"), ("data", "joint", "cdof_dot")}


def world_inertia_tensors(inertia, ximat):
    """Each body's inertia about its centre of mass in the world frame, ximat diag(I) ximat^T."""
    return np.array([r @ np.diag(moments) @ r.T for moments, r in
                     zip(np.reshape(inertia, (-1, 3)), np.reshape(ximat, (-1, 3, 3)))])


def inertia_tensors(inertia, iquat):
    """Each body's inertia about its centre of mass in the body frame, R diag(I) R^T."""
    out = []
    for moments, (w, x, y, z) in zip(np.reshape(inertia, (-1, 3)), np.reshape(iquat, (-1, 4))):
        r = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                      [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                      [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])
        out.append(r @ np.diag(moments) @ r.T)
    return np.array(out)


def state(path, seed=3, steps=60):
    """Both packages' model and data at one state: MuJoCo steps from the first keyframe (or
    qpos0) under seeded random controls, then both take that qpos, qvel, ctrl and time and run
    forward; MuJoCo's solver runs to convergence (tolerance 0), as lever's does."""
    rm = real.MjModel.from_xml_path(str(path))
    rm.opt.tolerance = 0
    rm.opt.iterations = 1000
    rd = real.MjData(rm)
    if rm.nkey:
        real.mj_resetDataKeyframe(rm, rd, 0)
    rng = np.random.default_rng(seed)
    lo, hi = rm.actuator_ctrlrange.T if rm.nu else (np.zeros(0), np.zeros(0))
    for _ in range(steps):
        rd.ctrl[:] = rng.uniform(lo, hi) * 0.5
        real.mj_step(rm, rd)
    rd.qvel[:] += rng.normal(0, 0.2, rm.nv)
    om = ours.MjModel.from_xml_path(str(path))
    od = ours.MjData(om)
    od.qpos[:], od.qvel[:], od.ctrl[:], od.time = rd.qpos, rd.qvel, rd.ctrl, rd.time
    real.mj_forward(rm, rd)
    ours.mj_forward(om, od)
    return om, od, rm, rd


def close(a, b, what):
    a, b = np.asarray(a), np.asarray(b)
    assert a.shape == b.shape, f"{what}: shape {a.shape} != MuJoCo's {b.shape}"
    if a.dtype.kind in "iub" and b.dtype.kind in "iub":
        assert np.array_equal(a, b), f"{what}: {a} != MuJoCo's {b}"
        return
    bad = np.abs(a - b) > TOLERANCE * np.maximum(1.0, np.abs(b))
    assert not bad.any(), f"{what}: {a[bad]} != MuJoCo's {b[bad]}"


def same(ours_value, real_value, what, layout=()):
    """type, shape, dtype, writability and value."""
    if isinstance(real_value, np.ndarray):
        assert isinstance(ours_value, np.ndarray), f"{what}: {type(ours_value)} is not an array"
        if "reshape" in layout:
            ours_value = ours_value.reshape(real_value.shape)
        if "deadband" in layout:
            assert np.array_equal(real_value[:, 0], real_value[:, 1]), what
            real_value = real_value[:, 0]
        assert ours_value.dtype == real_value.dtype, f"{what}: {ours_value.dtype}"
        if "writable" not in layout:
            assert ours_value.flags.writeable == real_value.flags.writeable, what
        close(ours_value, real_value, what)
    else:
        assert type(ours_value) is type(real_value), \
            f"{what}: {type(ours_value).__name__} is not MuJoCo's {type(real_value).__name__}"
        if "value" not in layout:
            close(ours_value, real_value, what)


def dense_moment(rm, rd):
    """MuJoCo 3.x's sparse actuator_moment as 2.2.2's dense (nu, nv) rows."""
    dense = np.zeros((rm.nu, rm.nv))
    for i in range(rm.nu):
        adr, nnz = rd.moment_rowadr[i], rd.moment_rownnz[i]
        dense[i, rd.moment_colind[adr:adr + nnz]] = rd.actuator_moment[adr:adr + nnz]
    return dense


def public(obj):
    return {n for n in dir(obj) if not n.startswith("_")}


def offered_model_names():
    return sorted(ours._MODEL_OFFERED | set(ours._SIZES) | set(ours._KEY_FIELDS) | {"nM"})


def offered_data_names():
    return sorted(ours._DATA_FIELDS | {"time", "ncon", "nefc", "efc_J", "qM"})


@pytest.mark.parametrize("path", MODELS, ids=lambda p: p.name)
def test_arrays_sizes_and_options_are_mujocos(path):
    om, od, rm, rd = state(path)
    ours.mj_energyPos(om, od), ours.mj_energyVel(om, od), ours.mj_inverse(om, od)
    real.mj_energyPos(rm, rd), real.mj_energyVel(rm, rd), real.mj_inverse(rm, rd)
    for name in offered_model_names():
        layout = LAYOUT.get(name, ("",))[-1]
        if layout == "principal":
            close(inertia_tensors(om.body_inertia, om.body_iquat),
                  inertia_tensors(rm.body_inertia, rm.body_iquat), "model." + name)
            continue
        same(getattr(om, name), getattr(rm, RENAMED.get(name, name)), "model." + name, layout)
    for name in offered_data_names():
        layout = LAYOUT.get(name, ("",))[-1]
        if layout == "principal in the world":
            close(world_inertia_tensors(om.body_inertia, od.ximat),
                  world_inertia_tensors(rm.body_inertia, rd.ximat), "data." + name)
            continue
        if layout == "sparse":
            close(od.actuator_moment, dense_moment(rm, rd), "data." + name)
            continue
        if layout == "warmstart":
            close(od.qacc_warmstart, rd.qacc, "data." + name)
            continue
        same(getattr(od, name), getattr(rd, name), "data." + name, layout)
    for name in ("timestep", "gravity", "integrator", "solver"):
        same(getattr(om.opt, name), getattr(rm.opt, name), "opt." + name)


def test_layout_differences_are_still_there():
    """LAYOUT's entries describe the pinned MuJoCo: were one to vanish, lever would follow it."""
    _, od, rm, rd = state(CONTACT_MODELS[0])
    assert rd.efc_J.shape != od.efc_J.shape and rd.efc_J.size == od.efc_J.size
    assert rm.nconmax == -1 and rm.njmax == -1
    assert rd.actuator_moment.shape != od.actuator_moment.shape
    # MuJoCo 3.x's forward leaves the warm start as the last step saved it
    _, _, _, gripped = state(CONTACT_MODELS[1])
    assert gripped.nefc > 0 and not np.array_equal(gripped.qacc_warmstart, gripped.qacc)


@pytest.mark.parametrize("path", MODELS, ids=lambda p: p.name)
def test_every_mujoco_2_2_2_name_lever_lacks_raises_not_implemented(path):
    om, od, rm, rd = state(path)
    for obj, mine, kind in ((rm, om, "MODEL"), (rd, od, "DATA")):
        for name in public(obj):
            try:
                getattr(mine, name)
            except NotImplementedError as refused:
                assert name in str(refused) and "lever" in str(refused)
            except AttributeError:
                # a name MuJoCo 2.2.2 does not have (3.x's, or a method): not lever.mujoco's
                assert name not in getattr(_mujoco_names, kind), f"{kind}: {name}"
    with pytest.raises(NotImplementedError, match="mj_collision"):
        ours.mj_collision(om, od)


@pytest.mark.parametrize("path", MODELS, ids=lambda p: p.name)
def test_named_accessors_are_mujocos(path):
    om, od, rm, rd = state(path)
    sizes = {"body": "nbody", "joint": "njnt", "geom": "ngeom", "site": "nsite",
             "actuator": "nu"}
    compared = refused = 0
    for kind, size in sizes.items():
        for i in range(getattr(rm, size)):
            name = real.mj_id2name(rm, getattr(real.mjtObj, "mjOBJ_" + kind.upper()), i)
            for mine, theirs, where in ((om, rm, "model"), (od, rd, "data")):
                keys = [i, name] if name else [i]
                for key in keys:
                    a, b = getattr(mine, kind)(key), getattr(theirs, kind)(key)
                    assert (a.id, a.name) == (b.id, b.name)
                    for attr in sorted(public(b) - {"id", "name"}):
                        what = f"{where}.{kind}({key!r}).{attr}"
                        try:
                            value = getattr(a, attr)
                        except NotImplementedError as e:
                            assert attr in str(e), what
                            refused += 1
                            continue
                        except AttributeError:  # MuJoCo 3.x's, not 2.2.2's
                            source = {"model": ours._MODEL_ACCESS,
                                      "data": ours._DATA_ACCESS}[where][kind]
                            assert attr not in source, what
                            continue
                        theirs_value = getattr(b, attr)
                        source = {"model": ours._MODEL_ACCESS,
                                  "data": ours._DATA_ACCESS}[where][kind][attr][0]
                        layout = LAYOUT.get(source, ("",))[-1]
                        if (where, kind, attr) in ACCESSOR_ROWS:
                            dof = rm.jnt_dofadr[b.id]
                            theirs_value = getattr(rd, attr)[dof:dof + len(value)]
                        if layout == "sparse":
                            theirs_value = dense_moment(rm, rd)[b.id]
                            layout = ("writable",)
                        if layout == "warmstart":  # a joint's dofs
                            dof = rm.jnt_dofadr[b.id]
                            theirs_value = rd.qacc[dof:dof + len(value)]
                        if layout == "principal":
                            value = inertia_tensors(a.inertia, a.iquat)
                            theirs_value = inertia_tensors(b.inertia, b.iquat)
                        elif layout == "principal in the world":
                            value = world_inertia_tensors(om.body(key).inertia, value)
                            theirs_value = world_inertia_tensors(rm.body(key).inertia, theirs_value)
                        same(value, theirs_value, what, layout)
                        compared += 1
    assert compared > 0


def test_data_geom_xpos_is_geom_xpos():
    om, od, rm, rd = state(CONTACT_MODELS[1])
    for g in range(om.ngeom):
        same(od.geom(g).xpos, rd.geom(g).xpos, f"data.geom({g}).xpos")
        assert np.shares_memory(od.geom(g).xpos, od.geom_xpos)


@pytest.mark.parametrize("path", CONTACT_MODELS, ids=lambda p: p.name)
def test_contacts_index_slice_and_member_arrays(path):
    om, od, rm, rd = state(path, steps=300)
    n = rd.ncon
    assert n >= 2 and od.ncon == n and len(od.contact) == len(rd.contact) == n
    members = sorted(public(rd.contact[0]) & (ours._CONTACT_MEMBERS | _mujoco_names.CONTACT))
    for name in members:
        whole = getattr(rd.contact, name)
        try:
            mine = getattr(od.contact, name)
        except NotImplementedError:
            assert name not in ours._CONTACT_MEMBERS
            continue
        same(mine, whole, f"contact.{name}")
        for i in range(n):
            same(getattr(od.contact[i], name), getattr(rd.contact[i], name),
                 f"contact[{i}].{name}")
        # slices: Python's meaning over the ncon contacts (MuJoCo 3.13's own _MjContactList slice
        # reads from its start to ncon whatever the stop, so it is compared with its arrays)
        for cut in (slice(None, n - 1), slice(1, 3), slice(None, None, 2), slice(None, None, -1)):
            picked = od.contact[cut]
            assert len(picked) == len(range(n)[cut])
            same(getattr(picked, name), whole[cut], f"contact[{cut}].{name}")
    with pytest.raises(IndexError):
        od.contact[n]
    for i in range(n):
        ours_force, real_force = np.zeros(6), np.zeros(6)
        ours.mj_contactForce(om, od, i, ours_force)
        real.mj_contactForce(rm, rd, i, real_force)
        same(ours_force, real_force, f"mj_contactForce({i})")


def test_enums_are_mujocos_where_2_2_2_and_the_pin_agree():
    for enum in (ours.mjtObj, ours.mjtConstraint, ours.mjtConstraintState, ours.mjtIntegrator):
        theirs = getattr(real, enum.__name__)
        for member in enum:
            assert hasattr(theirs, member.name), member.name
    # the ones lever.mujoco's functions take agree in number too (MuJoCo 3.x inserted
    # mjOBJ_FLEX after mjOBJ_LIGHT, renumbering mjOBJ_MESH onwards; lever keeps 2.2.2's numbers)
    for member in ours._OBJ_TYPES:
        if member < ours.mjtObj.mjOBJ_MESH:
            assert int(member) == int(getattr(real.mjtObj, member.name)), member.name
    for enum in (ours.mjtConstraint, ours.mjtConstraintState, ours.mjtIntegrator):
        for member in enum:
            assert int(member) == int(getattr(getattr(real, enum.__name__), member.name))


@pytest.mark.parametrize("path", MODELS, ids=lambda p: p.name)
def test_names_and_ids(path):
    om, _, rm, _ = state(path, steps=0)
    for member, kind in ours._OBJ_TYPES.items():
        theirs = getattr(real.mjtObj, member.name)
        count = getattr(rm, ours._OBJECTS[kind][1])
        for i in range(count):
            name = real.mj_id2name(rm, theirs, i)
            assert ours.mj_id2name(om, member, i) == name
            if name:
                assert ours.mj_name2id(om, member, name) == real.mj_name2id(rm, theirs, name) == i
        assert ours.mj_name2id(om, member, "no such name") == -1
        assert real.mj_name2id(rm, theirs, "no such name") == -1


def call_each(module, m, d):
    """Every function of lever.mujoco's __all__, called as MuJoCo's documentation calls it, on a
    copy of the state; returns {what: output}."""
    nv, nq = m.nv, m.nq
    out = {}

    def fresh():
        copy = module.MjData(m)
        copy.qpos[:], copy.qvel[:], copy.ctrl[:], copy.time = d.qpos, d.qvel, d.ctrl, d.time
        return copy

    def after(fn, *fields):
        data = fresh()
        fn(m, data)
        for f in fields:
            out[f"{fn.__name__}: {f}"] = np.array(getattr(data, f))

    after(module.mj_forward, "qacc", "qfrc_constraint")
    after(module.mj_step, "qpos", "qvel", "time")
    data = fresh()
    module.mj_step1(m, data)
    out["mj_step1: xpos"] = np.array(data.xpos)
    module.mj_step2(m, data)
    out["mj_step2: qpos"], out["mj_step2: qvel"] = np.array(data.qpos), np.array(data.qvel)
    after(module.mj_kinematics, "xpos", "xquat", "xmat", "site_xpos", "xanchor", "xaxis")
    data = fresh()
    module.mj_kinematics(m, data)
    module.mj_comPos(m, data)
    out["mj_comPos: subtree_com"], out["mj_comPos: cdof"] = data.subtree_com.copy(), data.cdof.copy()
    module.mj_crb(m, data)
    if module is real:  # MuJoCo 3.x: mj_crb's body inertias, then mj_makeM's M from them
        module.mj_makeM(m, data)
    dense = np.zeros((nv, nv))
    module.mj_fullM(m, dense, data.qM)  # MuJoCo up to 3.9's form (lever.mujoco also takes 3.10's)
    out["mj_crb, mj_fullM"] = dense
    if module is ours:
        module.mj_fullM(m, data, dense)
        assert np.array_equal(dense, out["mj_crb, mj_fullM"])
    module.mj_factorM(m, data)
    out["mj_factorM: qLDiagInv"] = data.qLDiagInv.copy()
    data = fresh()
    module.mj_forward(m, data)
    for flg in (0, 1):
        result = np.zeros(nv)
        module.mj_rne(m, data, flg, result)
        out[f"mj_rne({flg})"] = result
    module.mj_inverse(m, data)
    out["mj_inverse"] = data.qfrc_inverse.copy()
    vec = np.linspace(-1, 1, nv)
    res = np.zeros(nv)
    module.mj_mulM(m, data, res, vec)
    out["mj_mulM"] = res
    x = np.zeros((1, nv))
    module.mj_solveM(m, data, x, vec.reshape(1, nv))
    out["mj_solveM"] = x
    for s in range(m.nsite):
        jp, jr = np.zeros((3, nv)), np.zeros((3, nv))
        module.mj_jacSite(m, data, jp, jr, s)
        out[f"mj_jacSite({s})"] = np.hstack([jp, jr])
    for b in range(m.nbody):
        jp, jr = np.zeros((3, nv)), np.zeros((3, nv))
        module.mj_jacBody(m, data, jp, jr, b)
        out[f"mj_jacBody({b})"] = np.hstack([jp, jr])
        module.mj_jac(m, data, jp, jr, data.xipos[b], b)
        out[f"mj_jac({b})"] = np.hstack([jp, jr])
    qpos = data.qpos.copy()
    module.mj_integratePos(m, qpos, vec, 0.01)
    out["mj_integratePos"] = qpos
    qvel = np.zeros(nv)
    module.mj_differentiatePos(m, qvel, 0.01, data.qpos, qpos)
    out["mj_differentiatePos"] = qvel
    module.mj_energyPos(m, data)
    module.mj_energyVel(m, data)
    out["mj_energyPos, mj_energyVel"] = data.energy.copy()
    for i in range(data.ncon):
        force = np.zeros(6)
        module.mj_contactForce(m, data, i, force)
        out[f"mj_contactForce({i})"] = force
    module.mj_resetData(m, data)
    out["mj_resetData: qpos"] = data.qpos.copy()
    if m.nkey:
        module.mj_resetDataKeyframe(m, data, m.nkey - 1)
        out["mj_resetDataKeyframe: qpos"] = data.qpos.copy()
        out["mj_resetDataKeyframe: ctrl"] = data.ctrl.copy()
    m.body_mass[-1] *= 1.25
    module.mj_setConst(m, data)
    out["mj_setConst: dof_invweight0"] = m.dof_invweight0.copy()
    out["mj_setConst: body_subtreemass"] = m.body_subtreemass.copy()
    return out


CALLED = {"mj_forward", "mj_step", "mj_step1", "mj_step2", "mj_kinematics", "mj_comPos", "mj_crb",
          "mj_factorM", "mj_rne", "mj_inverse", "mj_fullM", "mj_mulM", "mj_solveM", "mj_jacSite",
          "mj_jacBody", "mj_jac", "mj_integratePos", "mj_differentiatePos", "mj_setConst",
          "mj_resetData", "mj_resetDataKeyframe", "mj_energyPos", "mj_energyVel",
          "mj_contactForce"}


def test_every_function_of_all_is_compared():
    functions = {n for n in ours.__all__ if n.startswith("mj_")}
    assert functions == CALLED | {"mj_name2id", "mj_id2name"}  # names: test_names_and_ids


@pytest.mark.parametrize("path", MODELS, ids=lambda p: p.name)
def test_functions_are_mujocos(path):
    om, od, rm, rd = state(path)
    mine, theirs = call_each(ours, om, od), call_each(real, rm, rd)
    assert mine.keys() == theirs.keys()
    for what in theirs:
        close(mine[what], theirs[what], f"{path.name}: {what}")


def test_from_xml_string_and_keyframes():
    path = REPO / "models" / "panda7.xml"
    text = path.read_text()
    om = ours.MjModel.from_xml_path(str(path))
    rm = real.MjModel.from_xml_path(str(path))
    assert om.nkey > 0 and om.nkey == rm.nkey
    for name in ours._KEY_FIELDS:
        same(getattr(om, name), getattr(rm, name), "model." + name)
    od, rd = ours.MjData(om), real.MjData(rm)
    for k in range(om.nkey):
        ours.mj_resetDataKeyframe(om, od, k)
        real.mj_resetDataKeyframe(rm, rd, k)
        for name in ("qpos", "qvel", "ctrl"):
            same(getattr(od, name), getattr(rd, name), f"key {k}: data.{name}")
        same(od.time, rd.time, f"key {k}: time")
    # from text (no file to resolve meshes against: the arm's kinematic chain alone)
    arm = (REPO / "models" / "arm2.xml").read_text()
    om, rm = ours.MjModel.from_xml_string(arm), real.MjModel.from_xml_string(arm)
    for name in ("body_mass", "body_pos", "jnt_range", "actuator_gear", "nq", "nv", "nu"):
        same(getattr(om, name), getattr(rm, name), "from_xml_string: " + name)
    assert "<mujoco" in text


@pytest.mark.parametrize("solver", ["PGS", "CG"])
def test_solver_iterations_are_mujocos(solver):
    """data.solver_iter against the pinned MuJoCo's solver_niter[0] (one island: the box on the
    floor) with both warm starts off (lever's CG starts cold, and the packages' flags differ:
    tests/diff/solver_pgs.cpp holds PGS's warm start to MuJoCo 2.2.2's): PGS's sweeps and CG's iterations
    at MuJoCo's default tolerance, and PGS's answer (CG's, stopped by a tolerance, is as near the
    minimizer as MuJoCo's but not within 1e-12 of it: tests/diff/solver_cg.cpp). Newton's count
    is lever's own (its exact solve), not MuJoCo's."""
    path = REPO / "models" / "box_drop.xml"
    rm = real.MjModel.from_xml_path(str(path))
    om = ours.MjModel.from_xml_path(str(path))
    code = getattr(real.mjtSolver, f"mjSOL_{solver}")
    rm.opt.solver = om.opt.solver = int(code)
    rm.opt.disableflags |= int(real.mjtDisableBit.mjDSBL_WARMSTART)
    om.opt.disableflags |= int(ours.mjtDisableBit.mjDSBL_WARMSTART)
    rd, od = real.MjData(rm), ours.MjData(om)
    if rm.nkey:
        real.mj_resetDataKeyframe(rm, rd, 0)
    counted = 0
    for _ in range(150):  # the box lands and rests
        od.qpos[:], od.qvel[:], od.time = rd.qpos, rd.qvel, rd.time
        real.mj_forward(rm, rd)
        ours.mj_forward(om, od)
        assert od.solver_iter == rd.solver_niter[0], f"{solver} at t={rd.time}"
        if solver == "PGS":
            close(od.qacc, rd.qacc, f"{solver} qacc at t={rd.time}")
        counted += rd.solver_niter[0]
        real.mj_step(rm, rd)
    assert counted > 0
