"""lever.BatchRunner: forward() and step() over many states at once, one state per row.

The reference is lever itself one state at a time: every field a batch returns must equal, bit
for bit, what lever.forward leaves in a Data of its own at that state, on 1 and 2 threads, on the
arms (limit rows at some states) and on the gripper (forward runs the collision stage: 4 to 8
contacts); step(nstep) must equal nstep lever.step calls. Inputs in any layout give the same
numbers and are never written; every refusal is a lever.StateError naming what it refuses."""
import gc
import threading
import tracemalloc

import numpy as np
import pytest

import lever
from conftest import REPO

MODELS = ("arm2", "panda7", "gripper")
# every Data field a batch returns: sized by the model alone and computed by forward()
FIELDS = tuple(f["name"] for f in lever.data_field_table()
               if f["rows"] != "nefc" and f["stage"] not in ("inverse", "energy", "step"))


def load(name):
    return lever.load(str(REPO / "models" / f"{name}.xml"))


def arm_states(model, n, seed):
    """n states of an arm of hinges: qpos over each joint's range and a tenth beyond it (some
    states push a stop: limit rows), random velocities and controls."""
    rng = np.random.default_rng(seed)
    low, high = model.jnt_range[:, 0], model.jnt_range[:, 1]
    margin = 0.1 * (high - low)
    qpos = rng.uniform(low - margin, high + margin, (n, model.nq))
    qvel = rng.uniform(-2.0, 2.0, (n, model.nv))
    ctrl = rng.uniform(-1.0, 1.0, (n, model.nu))
    return qpos, qvel, ctrl


def gripper_states(model, n):
    """n states of a pick: the carriage lowered round the box on the table (4 contacts), the
    fingers closed on it (8), the box lifted (4); ctrl the command in force at each."""
    data = lever.Data(model)
    lever.reset_keyframe(model, data, "open")
    plan = [(-0.23, 0.0, 0.0)] * 250 + [(-0.23, 0.035, 0.035)] * 250 + [(-0.1, 0.035, 0.035)] * 250
    qpos, qvel, ctrl = [], [], []
    for k, command in enumerate(plan):
        data.ctrl[:] = command
        lever.step(model, data)
        if k % (len(plan) // n) == 0 and len(qpos) < n:
            qpos.append(data.qpos.copy())
            qvel.append(data.qvel.copy())
            ctrl.append(data.ctrl.copy())
    return np.array(qpos), np.array(qvel), np.array(ctrl)


def states(model, n=30, seed=1):
    if model.name == "gripper":
        return gripper_states(model, n)
    return arm_states(model, n, seed)


def one_by_one(model, qpos, qvel, ctrl, fields):
    """lever.forward at each state in a fresh Data: field -> array (n,) + the field's shape."""
    out = {name: [] for name in fields}
    contacts = []
    for k in range(len(qpos)):
        data = lever.Data(model)
        data.qpos[:], data.qvel[:] = qpos[k], qvel[k]
        if ctrl is not None:
            data.ctrl[:] = ctrl[k]
        lever.forward(model, data)
        contacts.append(data.ncon)
        for name in fields:
            out[name].append(getattr(data, name).copy())
    return {name: np.array(rows) for name, rows in out.items()}, contacts


def stepped_one_by_one(model, qpos, qvel, ctrl, nstep):
    new_qpos, new_qvel = np.empty_like(qpos), np.empty_like(qvel)
    for k in range(len(qpos)):
        data = lever.Data(model)
        data.qpos[:], data.qvel[:] = qpos[k], qvel[k]
        if ctrl is not None:
            data.ctrl[:] = ctrl[k]
        for _ in range(nstep):
            lever.step(model, data)
        new_qpos[k], new_qvel[k] = data.qpos, data.qvel
    return new_qpos, new_qvel


@pytest.mark.parametrize("threads", (1, 2))
@pytest.mark.parametrize("name", MODELS)
def test_every_field_equals_forward_state_by_state(name, threads):
    model = load(name)
    qpos, qvel, ctrl = states(model)
    runner = lever.BatchRunner(model, threads=threads)
    assert runner.threads == threads
    out = runner.forward(qpos, qvel, ctrl, fields=FIELDS)
    expected, contacts = one_by_one(model, qpos, qvel, ctrl, FIELDS)
    if name == "gripper":  # the collision stage ran, with the contact set changing
        assert min(contacts) > 0 and len(set(contacts)) > 1, contacts
    assert list(out) == list(FIELDS)
    for field in FIELDS:
        assert out[field].shape == expected[field].shape, field
        assert out[field].dtype == expected[field].dtype, field
        assert np.array_equal(out[field], expected[field]), field
    # the default: qacc alone
    default = runner.forward(qpos, qvel, ctrl)
    assert list(default) == ["qacc"]
    assert np.array_equal(default["qacc"], expected["qacc"])


@pytest.mark.parametrize("threads", (1, 2))
@pytest.mark.parametrize("name", MODELS)
def test_step_equals_steps_state_by_state(name, threads):
    model = load(name)
    qpos, qvel, ctrl = states(model)
    runner = lever.BatchRunner(model, threads=threads)
    new_qpos, new_qvel = runner.step(qpos, qvel, ctrl, nstep=3)
    expected_qpos, expected_qvel = stepped_one_by_one(model, qpos, qvel, ctrl, 3)
    assert np.array_equal(new_qpos, expected_qpos)
    assert np.array_equal(new_qvel, expected_qvel)
    assert not np.array_equal(new_qpos, qpos)  # the states did move
    # nstep=1 by default; nstep=0 returns copies of the states
    one_qpos, one_qvel = runner.step(qpos, qvel, ctrl)
    assert np.array_equal(one_qpos, stepped_one_by_one(model, qpos, qvel, ctrl, 1)[0])
    same_qpos, same_qvel = runner.step(qpos, qvel, ctrl, nstep=0)
    assert np.array_equal(same_qpos, qpos) and same_qpos is not qpos


@pytest.mark.parametrize("name", MODELS)
def test_no_ctrl_means_zero_controls(name):
    model = load(name)
    qpos, qvel, _ = states(model)
    zeros = np.zeros((len(qpos), model.nu))
    runner = lever.BatchRunner(model, threads=2)
    fields = ("qacc", "actuator_force", "qfrc_actuator")
    without = runner.forward(qpos, qvel, fields=fields)
    expected, _ = one_by_one(model, qpos, qvel, None, fields)
    for field in fields:
        assert np.array_equal(without[field], expected[field]), field
        assert np.array_equal(without[field], runner.forward(qpos, qvel, zeros, fields)[field])
    for a, b in zip(runner.step(qpos, qvel, nstep=2), runner.step(qpos, qvel, zeros, nstep=2)):
        assert np.array_equal(a, b)
    # a batch without controls after one with them: the controls are zero again
    runner.forward(qpos, qvel, np.ones((len(qpos), model.nu)))
    assert np.array_equal(runner.forward(qpos, qvel)["qacc"], expected["qacc"])


@pytest.mark.parametrize("name", ("panda7", "gripper"))
def test_any_layout_gives_the_same_numbers_and_no_input_is_written(name):
    model = load(name)
    qpos, qvel, ctrl = states(model)
    runner = lever.BatchRunner(model, threads=2)
    fields = ("qacc", "site_xpos", "M")
    expected = runner.forward(qpos, qvel, ctrl, fields)
    expected_step = runner.step(qpos, qvel, ctrl, nstep=2)

    wide = np.zeros((2 * len(qpos), model.nq + 3))
    wide[::2, 1:model.nq + 1] = qpos  # a strided slice of a larger array
    layouts = {
        "transposed": (np.asfortranarray(qpos), qvel.T.copy().T, np.asfortranarray(ctrl)),
        "sliced": (wide[::2, 1:model.nq + 1], qvel[::1, :], ctrl),
        "lists": (qpos.tolist(), qvel.tolist(), ctrl.tolist()),
    }
    for layout, (q, v, u) in layouts.items():
        assert layout == "lists" or not q.flags.c_contiguous  # copied, not mapped
        out = runner.forward(q, v, u, fields)
        for field in fields:
            assert np.array_equal(out[field], expected[field]), (layout, field)
        for a, b in zip(runner.step(q, v, u, nstep=2), expected_step):
            assert np.array_equal(a, b), layout

    # the inputs, contiguous or not, are as they were
    before = [a.copy() for a in (qpos, qvel, ctrl, wide)]
    runner.forward(qpos, qvel, ctrl, fields)
    new_qpos, new_qvel = runner.step(qpos, qvel, ctrl, nstep=2)
    runner.step(wide[::2, 1:model.nq + 1], qvel, ctrl)
    for a, b in zip((qpos, qvel, ctrl, wide), before):
        assert np.array_equal(a, b)
    assert new_qpos.flags.c_contiguous and new_qpos.flags.owndata
    assert not np.shares_memory(new_qpos, qpos) and not np.shares_memory(new_qvel, qvel)


def test_contiguous_float64_rows_are_read_in_place():
    """C-contiguous float64 rows are BatchRunner's columns as they are: no copy (numpy reports
    its allocations to tracemalloc); any other layout is copied once."""
    model = load("arm2")
    runner = lever.BatchRunner(model, threads=2)
    qpos, qvel, _ = arm_states(model, 20000, 3)
    runner.forward(qpos, qvel, fields=())  # the first call's own allocations out of the way

    def peak(q, v):
        tracemalloc.start()
        try:
            runner.forward(q, v, fields=())
            return tracemalloc.get_traced_memory()[1]
        finally:
            tracemalloc.stop()

    assert peak(qpos, qvel) < qpos.nbytes / 10
    assert peak(np.asfortranarray(qpos), qvel) >= qpos.nbytes


def test_outputs_are_the_callers_and_the_model_is_kept():
    runner = lever.BatchRunner(load("arm2"), threads=2)  # no other reference to the model
    gc.collect()
    model = runner.model
    qpos, qvel, ctrl = states(model)
    first = runner.forward(qpos, qvel, ctrl, ("qacc", "xpos"))
    kept = {k: v.copy() for k, v in first.items()}
    runner.forward(qpos + 0.1, qvel, ctrl, ("qacc", "xpos"))
    for field, values in first.items():  # arrays of their own, not views of the runner's Data
        assert values.flags.owndata and values.flags.writeable
        assert np.array_equal(values, kept[field])
    # the runner reads the model it was given: an edit (then set_const) shows in the next batch
    model.body_mass[2] *= 2.0
    lever.set_const(model)
    expected, _ = one_by_one(model, qpos, qvel, ctrl, ("qacc",))
    assert np.array_equal(runner.forward(qpos, qvel, ctrl)["qacc"], expected["qacc"])
    assert not np.array_equal(expected["qacc"], kept["qacc"])
    assert "arm2" in repr(runner) and "threads=2" in repr(runner)


def test_one_runner_from_two_python_threads():
    """The GIL is released while a batch runs: a second Python thread calling the same runner
    waits for the first batch rather than sharing its Data."""
    model = load("panda7")
    runner = lever.BatchRunner(model, threads=2)
    batches = [states(model, 40, seed) for seed in (5, 6)]
    expected = [one_by_one(model, *b, ("qacc",))[0]["qacc"] for b in batches]
    failures = []

    def run(i):
        for _ in range(20):
            if not np.array_equal(runner.forward(*batches[i])["qacc"], expected[i]):
                failures.append(i)

    workers = [threading.Thread(target=run, args=(i,)) for i in (0, 1)]
    for w in workers:
        w.start()
    for w in workers:
        w.join()
    assert failures == []


def test_zero_states():
    model = load("panda7")
    runner = lever.BatchRunner(model, threads=2)
    out = runner.forward(np.zeros((0, model.nq)), np.zeros((0, model.nv)), fields=("qacc", "M"))
    assert out["qacc"].shape == (0, model.nv) and out["M"].shape == (0, model.nv, model.nv)
    qpos, qvel = runner.step(np.zeros((0, model.nq)), np.zeros((0, model.nv)))
    assert qpos.shape == (0, model.nq) and qvel.shape == (0, model.nv)


@pytest.mark.parametrize("field, says", [
    ("efc_force", "constraint row"),   # rows: the state's live constraint rows
    ("efc_J", "constraint rows"),
    ("contact", "contacts"),           # the state's contacts
    ("contact_dist", "contacts"),
    ("ncon", "contacts"),
    ("qfrc_inverse", "lever.inverse"),  # not computed by forward()
    ("energy", "lever.compute_energy"),
    ("solver_fwdinv", "lever.step with fwdinv"),
    ("no_such_field", "data_field_table"),
])
def test_fields_a_batch_cannot_return_are_refused_by_name(field, says):
    model = load("gripper")
    qpos, qvel, ctrl = states(model, 4)
    runner = lever.BatchRunner(model, threads=2)
    with pytest.raises(lever.StateError, match=field) as refused:
        runner.forward(qpos, qvel, ctrl, fields=("qacc", field))
    assert says in str(refused.value)


def test_wrong_shapes_and_arguments_are_refused_by_name():
    model = load("panda7")
    qpos, qvel, ctrl = states(model, 5)
    runner = lever.BatchRunner(model, threads=2)
    before = [a.copy() for a in (qpos, qvel, ctrl)]
    bad_calls = {
        "qpos": [(qpos[:, :3], qvel, ctrl), (qpos[0], qvel, ctrl), (qpos[None], qvel, ctrl),
                 (qpos.T, qvel, ctrl), ("seven", qvel, ctrl)],
        "qvel": [(qpos, qvel[:4], ctrl), (qpos, qvel[:, :6], ctrl), (qpos, None, ctrl)],
        "ctrl": [(qpos, qvel, ctrl[:, :2]), (qpos, qvel, ctrl[:3]), (qpos, qvel, ctrl[0])],
    }
    for name, calls in bad_calls.items():
        for args in calls:
            for call in (runner.forward, runner.step):
                with pytest.raises(lever.StateError, match=name) as refused:
                    call(*args)
                assert "one state per row" in str(refused.value) or "numbers" in str(refused.value)
    with pytest.raises(lever.StateError, match="nstep"):
        runner.step(qpos, qvel, ctrl, nstep=-1)
    for threads in (0, -2):
        with pytest.raises(lever.StateError, match="threads"):
            lever.BatchRunner(model, threads=threads)
    with pytest.raises(lever.StateError, match="model"):
        lever.BatchRunner(None)
    for a, b in zip((qpos, qvel, ctrl), before):
        assert np.array_equal(a, b)
    # the runner still works after every refusal
    expected, _ = one_by_one(model, qpos, qvel, ctrl, ("qacc",))
    assert np.array_equal(runner.forward(qpos, qvel, ctrl)["qacc"], expected["qacc"])
