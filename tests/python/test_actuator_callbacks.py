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
