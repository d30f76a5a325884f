"""Pickling and copying lever.Model, lever.Data and lever.mujoco's MjModel and MjData: every array
of the field table, the names, the keyframes and the options of a model, and the state, contacts,
constraint rows and warnings of a Data come back bit for bit, and a copy then runs exactly as the
original does. The arrays compared are read from the field table (lever.model_field_table(),
lever.data_field_table()), so a new array is compared without a line here."""
import copy
import pickle

import numpy as np
import pytest

import lever
import lever.mujoco as mujoco
from conftest import MODEL_FILES, REPO

MODEL_ARRAYS = [f["name"] for f in lever.model_field_table()]
DATA_ARRAYS = [f["name"] for f in lever.data_field_table()]
NAMES = ("body_name", "jnt_name", "geom_name", "site_name", "actuator_name", "key_name")
KEYS = ("key_time", "key_qpos", "key_qvel", "key_ctrl")
SIZES = ("nq", "nv", "nu", "nbody", "njnt", "ngeom", "nsite", "nkey", "npair", "nexclude",
         "nconmax", "njmax")
BOX_DROP = REPO / "models" / "box_drop.xml"


def same_array(a, b, what):
    a, b = np.asarray(a), np.asarray(b)
    assert (a.dtype, a.shape) == (b.dtype, b.shape), what
    assert a.tobytes() == b.tobytes(), f"{what}: {a} != {b}"


def assert_same_model(a: lever.Model, b: lever.Model) -> None:
    assert a is not b
    for name in MODEL_ARRAYS + list(KEYS):
        same_array(getattr(a, name), getattr(b, name), "model." + name)
        assert not np.shares_memory(getattr(a, name), getattr(b, name)), name
    for name in NAMES + SIZES + ("name", "source", "timestep", "integrator"):
        assert getattr(a, name) == getattr(b, name), name
    same_array(a.gravity, b.gravity, "model.gravity")
    assert a.to_json() == b.to_json()  # options and everything else lever writes of a model


def assert_same_data(a: lever.Data, b: lever.Data) -> None:
    assert a is not b
    for name in DATA_ARRAYS + ["efc_J"]:
        same_array(getattr(a, name), getattr(b, name), "data." + name)
    for name in lever.contact_members():
        same_array(a.contact_field(name), b.contact_field(name), "data.contact." + name)
    assert (a.time, a.ncon, a.nefc, a.warnings, a.warning_count) == \
        (b.time, b.ncon, b.nefc, b.warnings, b.warning_count)
    assert a.to_json() == b.to_json()


COPIES = {
    "pickle": lambda x: pickle.loads(pickle.dumps(x)),
    "pickle protocol 2": lambda x: pickle.loads(pickle.dumps(x, protocol=2)),
    "copy": copy.copy,
    "deepcopy": copy.deepcopy,
}


@pytest.mark.parametrize("path", MODEL_FILES, ids=lambda p: p.name)
def test_every_model_pickles_and_copies_bit_for_bit(path):
    model = lever.load(str(path))
    for how, make in COPIES.items():
        assert_same_model(model, make(model))


def test_a_model_edited_in_python_pickles_as_edited():
    model = lever.load(str(REPO / "models" / "arm2.xml"))
    model.body_mass[1] *= 1.5           # a parameter, set_const not called yet:
    model.body_subtreemass[0] = 123.0   # a constant stays as it was left
    model.dof_damping[:] = [0.25, 0.5]
    model.timestep = 0.001
    model.gravity[:] = [0.0, 0.0, -3.7]
    model.integrator = 1
    for how, make in COPIES.items():
        clone = make(model)
        assert_same_model(model, clone)
        assert clone.body_subtreemass[0] == 123.0 and clone.timestep == 0.001, how
    lever.set_const(model)
    assert_same_model(model, pickle.loads(pickle.dumps(model)))


def test_keyframes_pickle():
    path = next(p for p in MODEL_FILES if lever.load(str(p)).nkey > 0)
    model = lever.load(str(path))
    model.key_qpos[0, 0] += 0.125
    clone = pickle.loads(pickle.dumps(model))
    assert_same_model(model, clone)
    assert clone.key_name == model.key_name and clone.nkey > 0


def contact_state():
    """box_drop after its box landed: contacts, contact rows and a recorded warning."""
    model = lever.load(str(BOX_DROP))
    data = lever.Data(model)
    for _ in range(300):
        lever.step(model, data)
    lever.forward(model, data)
    assert data.ncon > 0 and data.nefc > 0
    data.ctrl[...] = np.nan if model.nu else 0.0
    data.qfrc_applied[0] = np.nan  # lever records a bad qfrc_applied in data.warnings
    lever.forward(model, data)
    data.qfrc_applied[0] = 0.0
    assert data.warning_count > 0
    lever.inverse(model, data)
    lever.compute_energy(model, data)
    return model, data


def test_data_pickles_and_copies_bit_for_bit_and_runs_on_as_the_original():
    model, data = contact_state()
    for how, make in COPIES.items():
        clone = make(data)
        assert_same_data(data, clone)
        clone_model = clone.model
        assert (clone_model is model) == (how == "copy"), how
        # the copy evaluates and steps exactly as the original (M's factor and the spatial
        # inertias, outside the field table, came along)
        a = lever.solve_mass(model, data, np.arange(model.nv, dtype=float))
        b = lever.solve_mass(clone_model, clone, np.arange(model.nv, dtype=float))
        same_array(a, b, "solve_mass")
        original = copy.copy(data)
        for _ in range(20):
            lever.step(model, original)
            lever.step(clone_model, clone)
        assert_same_data(original, clone)


def test_a_model_and_its_data_pickled_together_stay_paired():
    model, data = contact_state()
    model2, data2 = pickle.loads(pickle.dumps((model, data)))
    assert data2.model is model2
    lever.forward(model2, data2)  # paired: no "another Model"
    model3, data3 = copy.deepcopy((model, data))
    assert data3.model is model3 and model3 is not model


def test_an_unpickled_data_does_not_fit_another_model():
    model, data = contact_state()
    arm2 = lever.load(str(REPO / "models" / "arm2.xml"))
    _, state = lever.Data(arm2).__getstate__()
    blank = lever.Data.__new__(lever.Data)  # as pickle makes it, then __setstate__
    with pytest.raises(lever.StateError, match="cannot unpickle: data.qpos holds 16 bytes"):
        blank.__setstate__((model, state))


# ---- lever.mujoco ------------------------------------------------------------------------------

def test_mujoco_model_and_data_pickle_and_copy():
    m = mujoco.MjModel.from_xml_path(str(BOX_DROP))
    d = mujoco.MjData(m)
    mujoco.mj_step(m, d, 300)
    mujoco.mj_forward(m, d)
    assert d.ncon > 0
    m.body_mass[1] *= 2  # edited, pickled as edited
    for how, make in COPIES.items():
        m2 = make(m)
        assert isinstance(m2, mujoco.MjModel) and m2 is not m
        assert_same_model(m._native, m2._native)
        d2 = make(d)
        assert isinstance(d2, mujoco.MjData) and d2 is not d
        assert_same_data(d._native, d2._native)
        same_array(d.contact.dist, d2.contact.dist, how)
        # MuJoCo's functions take any MjData of a model of these sizes: a copy runs with the
        # original model or with the copied one alike
        for model in (m, m2):
            d3 = make(d)
            mujoco.mj_step(model, d3)
        d_next = copy.copy(d)
        mujoco.mj_step(m, d_next)
        mujoco.mj_step(m2, d2)
        assert_same_data(d_next._native, d2._native)
    pair = pickle.loads(pickle.dumps((m, d)))
    assert pair[1]._native.model is pair[0]._native
