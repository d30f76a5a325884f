"""Contacts from Python: d.ncon, d.contact (MuJoCo's MjContact fields), the efc arrays
sized nefc and mj_contactForce, on the contact models at states taken from a run.

The reference is MuJoCo 2.2.2's own Python package when it is the one installed (its solver run to
convergence: tolerance 0, 1000 iterations; the 1e-12 bound, and 1e-10 relative for what the
solver decides, as tests/diff), otherwise the C++ `lever forward --json` of the same state, which
must agree bit for bit. mj_contactForce is also checked against the physics it stands for: a
contact's rows push the joints as its frame force does through the contact's own Jacobian."""
import json
import subprocess

import numpy as np
import pytest

import lever
import lever.mujoco as mujoco
from conftest import REPO

try:  # the real MuJoCo 2.2.2, when its Python package is there (later releases collide
    import mujoco as real_mujoco  # differently: 2.3.x and 3.x find other contacts in
    if real_mujoco.__version__ != "2.2.2":  # capsule_stack and arm_and_objects)
        real_mujoco = None
except ImportError:
    real_mujoco = None

CONTACT_MODELS = [REPO / "models" / "box_drop.xml", REPO / "models" / "gripper.xml",
                  *sorted((REPO / "tests" / "diff" / "contact_scenes").glob("*.xml"))]
MEMBERS = ("geom1", "geom2", "dim", "exclude", "efc_address", "dist", "pos", "frame",
           "friction", "solref", "solimp", "includemargin", "mu")
EXACT = ("geom1", "geom2", "dim", "exclude", "efc_address")
EFC = ("efc_type", "efc_id", "efc_J", "efc_pos", "efc_margin", "efc_R", "efc_D", "efc_aref",
       "efc_force", "efc_state")
SOLVED = ("efc_force", "efc_state")  # decided by the solver


def states_with_contacts(path, count=6, steps=400):
    """(qpos, qvel, ctrl) at `count` moments of a run from the model's start with the motors
    holding their first keyframe's command (or zero), among the moments with contacts."""
    model = lever.load(str(path))
    data = lever.Data(model)
    if model.nkey:
        lever.reset_keyframe(model, data, 0)
    ctrl = data.ctrl.copy()
    seen = []
    lever.lab_run(model, data, ctrl, False, steps,
                  lambda k, d: seen.append((d.qpos.copy(), d.qvel.copy(), d.ncon)))
    touching = [(q, v) for q, v, ncon in seen if ncon > 0]
    assert len(touching) >= count, f"{path.name}: only {len(touching)} moments with contacts"
    picks = np.linspace(0, len(touching) - 1, count).astype(int)
    return [(*touching[i], ctrl) for i in picks]


def lever_at(path, qpos, qvel, ctrl):
    m = mujoco.MjModel.from_xml_path(str(path))
    d = mujoco.MjData(m)
    d.qpos[:], d.qvel[:], d.ctrl[:] = qpos, qvel, ctrl
    mujoco.mj_forward(m, d)
    return m, d


def as_arg(values) -> str:
    return ",".join(repr(float(x)) for x in values)


def cli_forward(cli, path, qpos, qvel, ctrl):
    args = [cli, "forward", str(path), "--json", "--qpos", as_arg(qpos), "--qvel", as_arg(qvel)]
    if len(ctrl):
        args += ["--ctrl", as_arg(ctrl)]
    out = subprocess.run(args, capture_output=True, text=True, timeout=120)
    # 1: the engine warned (arm_and_objects.xml has pairs lever cannot collide), the JSON is whole
    assert out.returncode in (0, 1), out.stderr
    return json.loads(out.stdout)


def contact_forces(m, d, module):
    out = np.zeros((d.ncon, 6))
    for i in range(d.ncon):
        module.mj_contactForce(m, d, i, out[i])
    return out


@pytest.mark.parametrize("path", CONTACT_MODELS, ids=lambda p: p.name)
def test_contacts_agree_with_the_reference(path, lever_cli):
    for qpos, qvel, ctrl in states_with_contacts(path):
        m, d = lever_at(path, qpos, qvel, ctrl)
        assert d.ncon > 0 and len(d.contact) == d.ncon
        ours_force = contact_forces(m, d, mujoco)
        if real_mujoco is not None:
            compare_with_mujoco(path, qpos, qvel, ctrl, d, ours_force)
            continue
        theirs = cli_forward(lever_cli, path, qpos, qvel, ctrl)
        assert theirs["ncon"] == d.ncon and theirs["nefc"] == d.nefc
        for i, contact in enumerate(theirs["contact"]):
            for name in MEMBERS:
                ours = np.asarray(getattr(d.contact[i], name), dtype=float).ravel()
                assert np.array_equal(ours, np.asarray(contact[name], dtype=float).ravel()), \
                    (path.name, i, name)
                assert np.array_equal(getattr(d.contact, name)[i], getattr(d.contact[i], name))
            assert np.array_equal(ours_force[i], contact["force"]), (path.name, i)
            names = m._native.geom_name
            assert contact["geom1_name"] == names[contact["geom1"]]
        for name in EFC:
            ours = np.asarray(getattr(d, name), dtype=float).ravel()
            ref = np.asarray(theirs[name], dtype=float)
            assert np.array_equal(ours, ref), (path.name, name)


def compare_with_mujoco(path, qpos, qvel, ctrl, d, ours_force):
    """MuJoCo 2.2.2's Python package at the same state, its solver run to convergence."""
    m2 = real_mujoco.MjModel.from_xml_path(str(path))
    m2.opt.tolerance = 0
    m2.opt.iterations = 1000
    d2 = real_mujoco.MjData(m2)
    d2.qpos[:], d2.qvel[:], d2.ctrl[:] = qpos, qvel, ctrl
    real_mujoco.mj_forward(m2, d2)
    assert d2.ncon == d.ncon and d2.nefc == d.nefc
    for i in range(d.ncon):
        for name in MEMBERS:
            ours = np.asarray(getattr(d.contact[i], name), dtype=float).ravel()
            ref = np.asarray(getattr(d2.contact[i], name), dtype=float).ravel()
            if name in EXACT:
                assert np.array_equal(ours, ref), (path.name, i, name)
            else:
                assert np.all(np.abs(ours - ref) <= 1e-12 * np.maximum(1, np.abs(ref))), \
                    (path.name, i, name, ours, ref)
    theirs_force = contact_forces(m2, d2, real_mujoco)
    assert np.all(np.abs(ours_force - theirs_force)
                  <= 1e-10 * np.maximum(1, np.abs(theirs_force))), (path.name,)
    for name in EFC:
        ours = np.asarray(getattr(d, name), dtype=float).ravel()
        ref = np.asarray(getattr(d2, name), dtype=float).ravel()[:ours.size]
        if name in ("efc_type", "efc_id"):
            assert np.array_equal(ours, ref), (path.name, name)
        elif name not in SOLVED:
            assert np.all(np.abs(ours - ref) <= 1e-12 * np.maximum(1, np.abs(ref))), name
    ref = np.asarray(d2.efc_force)[:d.nefc]
    assert np.all(np.abs(d.efc_force - ref) <= 1e-10 * np.maximum(1, np.abs(ref)))


@pytest.mark.parametrize("path", CONTACT_MODELS, ids=lambda p: p.name)
def test_contact_force_pushes_as_its_rows(path):
    """The frame force of mj_contactForce, applied through the contact's Jacobian in its frame
    (translation rows n, t1, t2 at the contact point, rotation rows n, t1, t2 for torsion and
    rolling), moves the joints as the contact's rows' forces do: sum_r efc_J[r] efc_force[r]."""
    checked = pushing = 0
    for qpos, qvel, ctrl in states_with_contacts(path):
        m, d = lever_at(path, qpos, qvel, ctrl)
        forces = contact_forces(m, d, mujoco)
        for i in range(d.ncon):
            c = d.contact[i]
            if c.efc_address < 0:
                assert not forces[i].any()
                continue
            elliptic = d.efc_type[c.efc_address] == mujoco.mjtConstraint.mjCNSTR_CONTACT_ELLIPTIC
            rows = c.dim if c.dim == 1 or elliptic else 2 * (c.dim - 1)  # a pyramid's edges
            span = slice(c.efc_address, c.efc_address + rows)
            assert np.all(d.efc_id[span] == i)
            by_rows = d.efc_J[span].T @ d.efc_force[span]
            jac = []
            for geom in (c.geom1, c.geom2):
                jacp, jacr = np.zeros((3, m.nv)), np.zeros((3, m.nv))
                mujoco.mj_jac(m, d, jacp, jacr, c.pos, int(m.geom_bodyid[geom]))
                jac.append((jacp, jacr))
            frame = c.frame.reshape(3, 3)
            in_frame = np.vstack([frame @ (jac[1][0] - jac[0][0]), frame @ (jac[1][1] - jac[0][1])])
            by_frame = in_frame.T @ forces[i]
            assert not forces[i][c.dim:].any()
            # rounding only: the size of the largest sum of products, never below 1
            scale = max(1.0, (np.abs(d.efc_J[span]).T @ np.abs(d.efc_force[span])).max())
            assert np.all(np.abs(by_rows - by_frame) <= 1e-12 * scale), \
                (path.name, i, by_rows, by_frame)
            checked += 1
            pushing += forces[i][0] > 0
    assert checked > 0 and pushing > 0


def test_contact_views_and_refusals():
    path = CONTACT_MODELS[0]
    qpos, qvel, ctrl = states_with_contacts(path, count=1)[0]
    m, d = lever_at(path, qpos, qvel, ctrl)
    n = d.ncon
    shapes = {"pos": (n, 3), "frame": (n, 9), "friction": (n, 5), "solref": (n, 2),
              "solimp": (n, 5), "dist": (n,), "geom1": (n,), "dim": (n,), "mu": (n,)}
    for name, shape in shapes.items():
        assert getattr(d.contact, name).shape == shape, name
    assert d.contact.geom1.dtype == np.int32 and d.contact.dist.dtype == np.float64
    assert isinstance(d.contact[0].dist, float) and isinstance(d.contact[0].geom2, int)
    assert d.contact[-1].pos.tolist() == d.contact.pos[n - 1].tolist()
    # each contact's frame is orthonormal, its first row the normal
    for frame in d.contact.frame:
        assert np.allclose(frame.reshape(3, 3) @ frame.reshape(3, 3).T, np.eye(3), atol=1e-12)
    for name in EFC:
        assert getattr(d, name).shape[0] == d.nefc, name
    assert d.efc_J.shape == (d.nefc, m.nv)
    assert set(d.efc_type.tolist()) <= {int(t) for t in mujoco.mjtConstraint}
    with pytest.raises(IndexError):
        d.contact[n]
    with pytest.raises(AttributeError):
        d.contact.no_such_member
    with pytest.raises(AttributeError):
        d.contact[0].dist = 1.0
    with pytest.raises(AttributeError, match="cannot be set"):
        d.ncon = 0
    with pytest.raises(lever.StateError, match="does not exist"):
        mujoco.mj_contactForce(m, d, n, np.zeros(6))
    # a model without contacts: none, and no rows of theirs
    arm = mujoco.MjModel.from_xml_path(str(REPO / "models" / "arm2.xml"))
    data = mujoco.MjData(arm)
    mujoco.mj_forward(arm, data)
    assert data.ncon == 0 and len(data.contact) == 0 and data.contact.pos.shape == (0, 3)


def test_simulate_json_contacts_match_the_run(lever_cli):
    """`lever simulate --json`'s ncon and contact forces per line are those of the same run from
    Python."""
    path = CONTACT_MODELS[0]
    model = lever.load(str(path))
    data = lever.Data(model)
    rows = []

    def record(k, d):
        forces = [lever.contact_force(model, d, i) for i in range(d.ncon)]
        rows.append((d.ncon, np.array(forces).reshape(-1, 6)))

    lever.lab_run(model, data, np.zeros(model.nu), False, 300, record)
    out = subprocess.run([lever_cli, "simulate", str(path), "--steps", "300", "--json"],
                         capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    lines = [json.loads(line) for line in out.stdout.splitlines()]
    assert len(lines) == len(rows) == 301
    assert any(ncon > 0 for ncon, _ in rows)
    for (ncon, forces), line in zip(rows, lines):
        assert line["ncon"] == ncon == len(line["contact"])
        theirs = np.array([c["force"] for c in line["contact"]], dtype=float).reshape(-1, 6)
        assert np.array_equal(forces, theirs)
