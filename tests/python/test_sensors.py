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
