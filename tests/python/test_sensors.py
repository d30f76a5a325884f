"""Sensors from Python: data.sensordata after mj_forward, named access (model.sensor('name'),
data.sensor('name').data) as MuJoCo's bindings give it, and lever's own Data and Model holding
the same numbers. The numbers themselves are held to MuJoCo's by tests/diff/sensors.cpp."""
import numpy as np

import lever
import lever.mujoco as mujoco
from conftest import REPO

SENSORS = REPO / "tests" / "models" / "sensors.xml"


def test_sensordata_after_forward():
    model = mujoco.MjModel.from_xml_path(str(SENSORS))
    data = mujoco.MjData(model)
    assert model.nsensor >= 40
    assert data.sensordata.shape == (model.nsensordata,)
    mujoco.mj_resetDataKeyframe(model, data, 0)
    data.time = 1.25
    mujoco.mj_forward(model, data)
    # what a sensor reads, by name, is its slice of sensordata
    gyro = model.sensor("imu_gyro")
    assert gyro.type[0] == 3 and gyro.dim[0] == 3  # mjSENS_GYRO, three numbers
    adr = int(gyro.adr[0])
    np.testing.assert_array_equal(data.sensor("imu_gyro").data, data.sensordata[adr:adr + 3])
    # joint and clock sensors read the state itself
    assert data.sensor("yaw_pos").data[0] == data.joint("yaw").qpos[0]
    assert data.sensor("elbow_vel").data[0] == data.joint("elbow").qvel[0]
    assert data.sensor("clock").data[0] == 1.25
    np.testing.assert_array_equal(data.sensor("world_com").data, data.body("world").subtree_com)
    # an acceleration sensor needed the forces inside the tree: they were computed
    assert np.any(data.body("upper").cfrc_int != 0)
    assert mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SENSOR, "clock") == model.sensor("clock").id


def test_lever_data_has_the_sensors():
    model = lever.load(str(SENSORS))
    data = lever.Data(model)
    lever.forward(model, data)
    assert data.sensordata.shape == (model.nsensordata,)
    assert "sensordata" in [f["name"] for f in lever.data_field_table()]
    assert model.sensor_name[model.sensor_name.index("clock")] == "clock"


USER_SENSORS = """<mujoco>
  <worldbody>
    <body name="arm" pos="0 0 1">
      <joint name="a" axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03"/>
      <site name="tip" pos="0.3 0 0"/>
    </body>
  </worldbody>
  <sensor>
    <jointpos joint="a"/>
    <user name="angle" objtype="site" objname="tip" dim="2" needstage="pos" datatype="real"
          cutoff="5"/>
    <user name="speed" objtype="joint" objname="a" dim="1" needstage="vel" datatype="real"/>
  </sensor>
</mujoco>"""


def test_user_sensors_by_callback():
    model = lever.load_string(USER_SENSORS)
    data = lever.Data(model)
    data.qpos[0] = 0.5
    data.qvel[0] = -2.0
    # without a callback the user sensors stay zero, as MuJoCo leaves them
    lever.forward(model, data)
    np.testing.assert_array_equal(data.sensordata[1:], [0, 0, 0])
    stages = []

    def fill(m, d, stage):
        stages.append(stage)
        assert m is model and d is data
        if stage == 1:
            d.sensordata[1:3] = [10 * d.qpos[0], 100.0]  # 100 is cut off at 5
        elif stage == 2:
            d.sensordata[3] = 3 * d.qvel[0]

    model.set_sensor_callback(fill)
    lever.forward(model, data)
    assert stages == [1, 2]  # no user sensor needs the acceleration stage
    np.testing.assert_array_equal(data.sensordata, [0.5, 5.0, 5.0, -6.0])
    model.set_sensor_callback(None)
    data.qpos[0] = 0.1
    lever.forward(model, data)
    assert data.sensordata[0] == 0.1 and data.sensordata[1] == 5.0  # left as they were


def test_mjcb_sensor_in_lever_mujoco():
    model = mujoco.MjModel.from_xml_string(USER_SENSORS)
    data = mujoco.MjData(model)
    data.qvel[0] = 0.25

    def fill(m, d, stage):
        assert m is model and d is data
        if stage == mujoco.mjtStage.mjSTAGE_VEL:
            d.sensordata[3] = d.qvel[0] + 1

    mujoco.set_mjcb_sensor(fill)
    try:
        mujoco.mj_forward(model, data)
    finally:
        mujoco.set_mjcb_sensor(None)
    assert data.sensor("speed").data[0] == 1.25


def test_option_flags_in_python():
    model = mujoco.MjModel.from_xml_string("""<mujoco>
  <option o_margin="0.01"><flag gravity="disable" energy="enable"/></option>
  <worldbody><body pos="0 0 1"><joint axis="0 1 0"/>
    <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03"/></body></worldbody>
</mujoco>""")
    assert model.opt.disableflags == mujoco.mjtDisableBit.mjDSBL_GRAVITY
    assert model.opt.enableflags == mujoco.mjtEnableBit.mjENBL_ENERGY
    assert model.opt.o_margin == 0.01
    np.testing.assert_array_equal(model.opt.o_solref, [0.02, 1])
    data = mujoco.MjData(model)
    data.qvel[0] = 1.0
    mujoco.mj_forward(model, data)
    assert data.qacc[0] == 0  # no gravity
    assert data.energy[0] == 0 and data.energy[1] > 0  # forward computed the energy
    model.opt.disableflags = 0
    mujoco.mj_forward(model, data)
    assert data.qacc[0] != 0
