// lever::integrate_pos against MuJoCo 2.2.2's mj_integratePos, joint kind by joint kind, on a model
// with a free, a ball, a hinge and a slide joint: lever's Model carries only what integrate_pos
// reads, copied from MuJoCo's compiled model (tests/models/floating.xml runs the whole engine).
#include <mujoco/mujoco.h>
#include <catch2/catch.hpp>

#include <lever/dynamics.hpp>
#include <lever/error.hpp>
#include <lever/fields.hpp>
#include <lever/model.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <random>

namespace lever::test {

namespace {

constexpr const char* kXml = R"(<mujoco>
  <worldbody>
    <body name="box" pos="0 0 1">
      <freejoint/>
      <geom type="box" size=".1 .2 .3" mass="1"/>
      <body name="arm" pos="0 0 -.4">
        <joint name="ball" type="ball"/>
        <geom type="capsule" fromto="0 0 0 0 0 -.4" size=".05" mass="1"/>
        <body name="tip" pos="0 0 -.4">
          <joint name="hinge" type="hinge" axis="0 1 0"/>
          <joint name="slide" type="slide" axis="1 0 0"/>
          <geom type="sphere" size=".05" mass="1"/>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>)";

struct MjModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};

std::unique_ptr<mjModel, MjModelDeleter> load_mujoco() {
  const auto file = std::filesystem::temp_directory_path() / "lever_integrate_pos_test.xml";
  std::ofstream(file) << kXml;
  char error[1000] = "";
  mjModel* m = mj_loadXML(file.string().c_str(), nullptr, error, sizeof(error));
  std::filesystem::remove(file);
  INFO(error);
  REQUIRE(m != nullptr);
  return std::unique_ptr<mjModel, MjModelDeleter>(m);
}

// The joint layout of MuJoCo's model: all integrate_pos reads.
Model joint_layout(const mjModel* m) {
  Model model;
  model.nq = m->nq;
  model.nv = m->nv;
  model.njnt = m->njnt;
  size_model(model);
  for (int j = 0; j < m->njnt; ++j) {
    model.jnt_qposadr[j] = m->jnt_qposadr[j];
    model.jnt_dofadr[j] = m->jnt_dofadr[j];
    switch (m->jnt_type[j]) {
      case mjJNT_FREE: model.jnt_kind[j] = JointKind::kFree; break;
      case mjJNT_BALL: model.jnt_kind[j] = JointKind::kBall; break;
      case mjJNT_SLIDE: model.jnt_kind[j] = JointKind::kSlide; break;
      default: model.jnt_kind[j] = JointKind::kHinge; break;
    }
  }
  return model;
}

}  // namespace

TEST_CASE("diff: integrate_pos agrees with mj_integratePos for free, ball, hinge and slide joints",
          "[diff][integrate]") {
  const auto m = load_mujoco();
  REQUIRE(m->nq == 7 + 4 + 2);
  REQUIRE(m->nv == 6 + 3 + 2);
  const Model model = joint_layout(m.get());
  std::mt19937_64 rng(19);
  std::uniform_real_distribution<double> uniform(-2.0, 2.0);
  double worst = 0.0;
  for (int trial = 0; trial < 1000; ++trial) {
    Eigen::VectorXd qpos(m->nq), qvel(m->nv);
    for (int i = 0; i < m->nq; ++i) qpos[i] = uniform(rng);  // quaternions not unit: normalized
    for (int i = 0; i < m->nv; ++i) qvel[i] = uniform(rng);
    if (trial % 10 == 0) qvel.segment(3, 3).setZero();  // a free body that does not turn
    const double h = trial % 2 == 0 ? 0.002 : 0.1;
    Eigen::VectorXd expected = qpos;
    mj_integratePos(m.get(), expected.data(), qvel.data(), h);
    integrate_pos(model, qpos, qvel, h);
    for (int i = 0; i < m->nq; ++i) {
      worst =
          std::max(worst, std::abs(qpos[i] - expected[i]) / std::max(1.0, std::abs(expected[i])));
    }
  }
  INFO("worst relative difference " << worst);
  CHECK(worst <= 1e-12);
  // quaternions leave unit length
  Eigen::VectorXd qpos = Eigen::VectorXd::Zero(m->nq), qvel = Eigen::VectorXd::Ones(m->nv);
  qpos[3] = qpos[7] = 1.0;
  integrate_pos(model, qpos, qvel, 0.5);
  CHECK(std::abs(qpos.segment(3, 4).norm() - 1.0) <= 1e-15);
  CHECK(std::abs(qpos.segment(7, 4).norm() - 1.0) <= 1e-15);
}

TEST_CASE("diff: differentiate_pos agrees with mj_differentiatePos and undoes integrate_pos",
          "[diff][integrate]") {
  const auto m = load_mujoco();
  const Model model = joint_layout(m.get());
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> uniform(-2.0, 2.0);
  double worst = 0.0, worst_round_trip = 0.0;
  for (int trial = 0; trial < 1000; ++trial) {
    Eigen::VectorXd qpos1(m->nq), qvel(m->nv);
    for (int i = 0; i < m->nq; ++i) qpos1[i] = uniform(rng);
    for (int i = 0; i < m->nv; ++i) qvel[i] = uniform(rng);
    const double h = trial % 2 == 0 ? 0.002 : 0.1;
    // unit quaternions, as MuJoCo's function assumes: a zero step normalizes them
    integrate_pos(model, qpos1, Eigen::VectorXd::Zero(m->nv), h);
    Eigen::VectorXd qpos2 = qpos1;
    integrate_pos(model, qpos2, qvel, h);
    Eigen::VectorXd ours(m->nv), theirs(m->nv);
    differentiate_pos(model, ours, h, qpos1, qpos2);
    mj_differentiatePos(m.get(), theirs.data(), h, qpos1.data(), qpos2.data());
    for (int i = 0; i < m->nv; ++i) {
      worst = std::max(worst, std::abs(ours[i] - theirs[i]) / std::max(1.0, std::abs(theirs[i])));
      // a turn of h |w| < pi comes back as the velocity that made it
      worst_round_trip = std::max(worst_round_trip, std::abs(ours[i] - qvel[i]));
    }
  }
  INFO("worst relative difference " << worst << ", worst round trip " << worst_round_trip);
  CHECK(worst <= 1e-12);
  // the quaternion's rounding (~1e-16) divided by h = 0.002, then through atan2 and a
  // normalization: ~1e-13; a wrong axis, sign or frame would be O(1)
  CHECK(worst_round_trip <= 1e-9);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(m->nq), short_qvel = Eigen::VectorXd::Zero(m->nq - 1);
  CHECK_THROWS_AS(differentiate_pos(model, short_qvel, 0.1, q, q), StateError);
}

TEST_CASE("diff: integrate_pos refuses vectors of the wrong size", "[diff][integrate]") {
  const auto m = load_mujoco();
  const Model model = joint_layout(m.get());
  Eigen::VectorXd qpos = Eigen::VectorXd::Zero(m->nq), qvel = Eigen::VectorXd::Zero(m->nv);
  Eigen::VectorXd short_qpos = Eigen::VectorXd::Zero(m->nv);  // nv, not nq: the common mistake
  CHECK_THROWS_AS(integrate_pos(model, short_qpos, qvel, 0.01), StateError);
  Eigen::VectorXd long_qvel = Eigen::VectorXd::Zero(m->nq);
  CHECK_THROWS_AS(integrate_pos(model, qpos, long_qvel, 0.01), StateError);
  CHECK(qpos.isZero(0.0));  // nothing half-done
}

}  // namespace lever::test
