// Sensor noise (<flag sensornoise="enable">) as MuJoCo 2.2.2 adds it, tested by its statistics:
// a real number gets noise * N(0, 1); a positive one too, and only where it is positive; an axis
// or a quaternion is turned by an angle noise * N(0, 1) about a random axis. Each Data draws from
// its own generator, seeded with kSensorNoiseSeed when it is made and by reset(): the same run
// gives the same noise. The cutoff clips after the noise.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <vector>

#include <lever/lever.hpp>
#include <lever/mjcf.hpp>

namespace {

lever::Model noisy_model(bool noise_on) {
  const std::string flag = noise_on ? R"(<flag sensornoise="enable"/>)" : "";
  return lever::mjcf::load_string(R"(<mujoco>
  <option>)" + flag + R"(</option>
  <worldbody>
    <body name="link" pos="0 0 1">
      <joint name="hinge" axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.02" contype="0" conaffinity="0"/>
      <site name="tip" pos="0.3 0 0"/>
    </body>
  </worldbody>
  <sensor>
    <jointpos name="angle" joint="hinge" noise="0.1"/>
    <framequat name="quat" objtype="site" objname="tip" noise="0.05"/>
    <framexaxis name="axis" objtype="site" objname="tip" noise="0.05"/>
    <touch name="touch" site="tip" noise="0.3"/>
    <jointpos name="clipped" joint="hinge" noise="1" cutoff="0.5"/>
  </sensor>
</mujoco>)",
                                  "noise.xml");
}

// the angle between two unit quaternions' rotations
double angle_between(const double* a, const lever::Quat& b) {
  const double dot = std::abs(a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]);
  return 2 * std::acos(std::min(1.0, dot));
}

}  // namespace

TEST_CASE("sensor noise has MuJoCo's distribution, per data type", "[sensors]") {
  const lever::Model model = noisy_model(true);
  lever::Data data(model);
  data.qpos[0] = 0.3;
  const lever::Model quiet = noisy_model(false);
  lever::Data clean(quiet);
  clean.qpos[0] = 0.3;
  lever::forward(quiet, clean);
  const double angle = clean.sensordata[0];
  const lever::Quat quat(clean.sensordata[1], clean.sensordata[2], clean.sensordata[3],
                         clean.sensordata[4]);
  const Eigen::Vector3d axis(clean.sensordata[5], clean.sensordata[6], clean.sensordata[7]);
  REQUIRE(angle == 0.3);  // without the flag, no noise

  constexpr int kDraws = 20000;
  double sum = 0, sum_squares = 0, quat_angles = 0, axis_angles = 0, clipped_max = 0;
  int clipped_at_cutoff = 0;
  for (int k = 0; k < kDraws; ++k) {
    lever::forward(model, data);
    const double e = data.sensordata[0] - angle;
    sum += e;
    sum_squares += e * e;
    // the quaternion stays a unit quaternion, turned by |noise N(0, 1)|
    const double* q = data.sensordata.data() + 1;
    REQUIRE(std::abs(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3] - 1) < 1e-12);
    quat_angles += angle_between(q, quat);
    // the axis stays a unit vector, turned by at most that angle
    const Eigen::Vector3d a(data.sensordata[5], data.sensordata[6], data.sensordata[7]);
    REQUIRE(std::abs(a.norm() - 1) < 1e-12);
    axis_angles += std::acos(std::min(1.0, a.dot(axis)));
    // touch reads 0 here: a positive sensor gets noise only where it is positive
    REQUIRE(data.sensordata[8] == 0.0);
    // noise 1 on 0.3, clipped at 0.5 afterwards
    clipped_max = std::max(clipped_max, std::abs(data.sensordata[9]));
    clipped_at_cutoff += data.sensordata[9] == 0.5 || data.sensordata[9] == -0.5;
  }
  const double mean = sum / kDraws, sd = std::sqrt(sum_squares / kDraws - mean * mean);
  INFO("jointpos noise: mean " << mean << ", standard deviation " << sd << " (noise 0.1)");
  CHECK(std::abs(mean) < 4 * 0.1 / std::sqrt(kDraws));  // four standard errors
  CHECK(std::abs(sd - 0.1) < 0.003);
  // E|N(0, 1)| = sqrt(2 / pi)
  const double expected = std::sqrt(2 / std::numbers::pi) * 0.05;
  INFO("quaternion: mean angle " << quat_angles / kDraws << ", expected " << expected);
  CHECK(std::abs(quat_angles / kDraws - expected) < 0.02 * expected);
  // an axis turned about a random axis by theta moves by less than theta
  CHECK(axis_angles / kDraws < expected);
  CHECK(axis_angles / kDraws > 0.5 * expected);
  CHECK(clipped_max == 0.5);
  // P(0.3 + N > 0.5) + P(0.3 + N < -0.5) = 0.42 + 0.21
  CHECK(std::abs(static_cast<double>(clipped_at_cutoff) / kDraws - 0.633) < 0.02);
}

TEST_CASE("sensor noise repeats: each Data's generator starts from the same seed", "[sensors]") {
  const lever::Model model = noisy_model(true);
  lever::Data a(model), b(model);
  std::vector<double> first;
  for (int k = 0; k < 10; ++k) {
    lever::forward(model, a);
    lever::forward(model, b);
    CHECK(a.sensordata == b.sensordata);
    first.push_back(a.sensordata[0]);
  }
  CHECK(first[0] != first[1]);  // a new draw each time
  lever::reset(model, a);       // reset() starts the sequence again
  lever::forward(model, a);
  CHECK(a.sensordata[0] == first[0]);
}
