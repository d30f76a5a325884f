"""User actuator parts from Python: Model.set_actuator_callbacks(gain=, bias=, dyn=) with Python
callables fn(model, data, id) (MuJoCo's mjcb_act_gain, mjcb_act_bias, mjcb_act_dyn). Callables that
compute the built-in fixed gain, affine bias and filter give the built-in types' numbers bit for
bit; MuJoCo's agreement is held by tests/diff/actuator_callbacks.cpp."""
import math

import numpy as np

import lever

ARM = """<mujoco>
  <compiler autolimits="true"/>
  <worldbody>
    <body pos="0 0 1">
      <joint name="shoulder" axis="0 1 0" damping="0.5"/>
      <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.04"/>
      <body pos="0.3 0 0">
        <joint name="elbow" axis="0 1 0" damping="0.2"/>
        <geom type="capsule" fromto="0 0 0 0.25 0 0" size="0.03"/>
      </body>
    </body>
  </worldbody>
  <actuator>
    <general joint="shoulder" gaintype="GAIN" gainprm="2.5" ctrlrange="-1 1"/>
    <general joint="elbow" gaintype="GAIN" gainprm="12" biastype="BIAS" biasprm="0 -12 -0.7"
             ctrlrange="-1 1"/>
    <general joint="elbow" dyntype="DYN" dynprm="0.04" gaintype="GAIN" gainprm="1.5"
             ctrlrange="-1 1"/>
  </actuator>
</mujoco>"""


def arm(user):
    names = {"GAIN": "user", "BIAS": "user", "DYN": "user"} if user else \
        {"GAIN": "fixed", "BIAS": "affine", "DYN": "filter"}
    xml = ARM
    for key, word in names.items():
        xml = xml.replace(key, word)
    return lever.load_string(xml)


def test_python_callbacks_reproduce_the_built_in_types():
    builtin, user = arm(False), arm(True)
    calls = {"gain": 0, "bias": 0, "dyn": 0}

    def gain(m, d, a):
        calls["gain"] += 1
        return m.actuator_gainprm[a][0]

    def bias(m, d, a):
        calls["bias"] += 1
        b = m.actuator_biasprm[a]
        return b[0] + b[1] * d.actuator_length[a] + b[2] * d.actuator_velocity[a]

    def dyn(m, d, a):
        calls["dyn"] += 1
        return (d.ctrl[a] - d.act[a - (m.nu - m.na)]) / max(1e-15, m.actuator_dynprm[a][0])

    user.set_actuator_callbacks(gain=gain, bias=bias, dyn=dyn)
    a, b = lever.Data(builtin), lever.Data(user)
    for k in range(50):
        a.ctrl[:] = b.ctrl[:] = [math.sin(0.01 * k + u) for u in range(3)]
        lever.step(builtin, a)
        lever.step(user, b)
        np.testing.assert_array_equal(b.qpos, a.qpos)
        np.testing.assert_array_equal(b.act, a.act)
        np.testing.assert_array_equal(b.actuator_force, a.actuator_force)
    assert calls["gain"] > 0 and calls["bias"] > 0 and calls["dyn"] > 0
    # None restores MuJoCo's values without callbacks: gain 1
    user.set_actuator_callbacks()
    b.ctrl[:] = 0.5
    lever.forward(user, b)
    assert b.actuator_force[0] == 0.5


def _user_gain(m, d, a):
    return m.actuator_gainprm[a][0] * (1 + 0.5 * math.cos(d.qpos[1]))


def _user_bias(m, d, a):
    b = m.actuator_biasprm[a]
    return b[0] + b[1] * d.actuator_length[a] + b[2] * d.actuator_velocity[a]


def _user_dyn(m, d, a):
    return (d.ctrl[a] - d.act[a - (m.nu - m.na)]) / m.actuator_dynprm[a][0]


def _run_with_module_callbacks(package, install, steps=40):
    """Two models of ARM with user parts in `package` (lever.mujoco or MuJoCo's own), made before
    install(package) sets the module-level callbacks (MuJoCo's package cannot call a Python
    callback while it compiles), stepped in turn; each model's qpos, qvel, act and
    actuator_force after each step."""
    models = [package.MjModel.from_xml_string(arm_xml(True)) for _ in range(2)]
    datas = [package.MjData(m) for m in models]
    install(package)
    out = [[], []]
    for k in range(steps):
        for i, (model, data) in enumerate(zip(models, datas)):
            data.ctrl[:] = [math.sin(0.05 * k + u) for u in range(3)]
            package.mj_step(model, data)
            out[i].append(np.concatenate([data.qpos, data.qvel, data.act, data.actuator_force]))
    return np.array(out)


def arm_xml(user):
    names = {"GAIN": "user", "BIAS": "user", "DYN": "user"} if user else \
        {"GAIN": "fixed", "BIAS": "affine", "DYN": "filter"}
    xml = ARM
    for key, word in names.items():
        xml = xml.replace(key, word)
    return xml


def test_module_level_act_callbacks_agree_with_mujocos_package():
    """lever.mujoco.set_mjcb_act_gain, _bias and _dyn as MuJoCo's own package has them: global,
    serving every model's user actuators, None clearing each; the runs against MuJoCo's."""
    import pytest
    real = pytest.importorskip("mujoco")
    from lever import mujoco as ours
    calls = {"ours": 0, "real": 0}

    def counted(name, fn):
        def wrapped(m, d, a):
            calls[name] += 1
            return fn(m, d, a)
        return wrapped

    def clear(package):
        package.set_mjcb_act_gain(None)
        package.set_mjcb_act_bias(None)
        package.set_mjcb_act_dyn(None)

    runs = {}
    try:
        for name, package in (("ours", ours), ("real", real)):
            def install(package, name=name):
                package.set_mjcb_act_gain(counted(name, _user_gain))
                package.set_mjcb_act_bias(_user_bias)
                package.set_mjcb_act_dyn(_user_dyn)
                assert package.get_mjcb_act_bias() is _user_bias

            runs[name] = _run_with_module_callbacks(package, install)
            clear(package)
            assert package.get_mjcb_act_gain() is None
            runs[name + " cleared"] = _run_with_module_callbacks(package, clear)
    finally:
        for package in (ours, real):
            package.set_mjcb_act_gain(None)
            package.set_mjcb_act_bias(None)
            package.set_mjcb_act_dyn(None)
    assert calls["ours"] == calls["real"] > 0  # each package called its gain callback as often
    for run in ("", " cleared"):
        ours_run, real_run = runs["ours" + run], runs["real" + run]
        assert np.all(np.abs(ours_run - real_run) <= 1e-12 * np.maximum(1, np.abs(real_run))), run
    # both models were served by the same global callbacks
    np.testing.assert_array_equal(runs["ours"][0], runs["ours"][1])
    # the callbacks mattered: without them the run is another
    assert np.max(np.abs(runs["ours"] - runs["ours cleared"])) > 1e-3
