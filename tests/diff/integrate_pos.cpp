// lever::integrate_pos against MuJoCo 2.2.2's mj_integratePos, joint kind by joint kind, on a model
// with a free, a ball, a hinge and a slide joint. lever's loader does not take ball and free joints
// yet, so lever's Model carries only what integrate_pos reads, copied from MuJoCo's compiled model.
#include <mujoco/mujoco.h>
#include <catch2/catch.hpp>

#include <lever/dynamics.hpp>
#include <lever/error.hpp>
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
  for (int j = 0; j < m->njnt; ++j) {
    model.jnt_qposadr.push_back(m->jnt_qposadr[j]);
    model.jnt_dofadr.push_back(m->jnt_dofadr[j]);
    switch (m->jnt_type[j]) {
      case mjJNT_FREE: model.jnt_kind.push_back(JointKind::kFree); break;
      case mjJNT_BALL: model.jnt_kind.push_back(JointKind::kBall); break;
      case mjJNT_SLIDE: model.jnt_kind.push_back(JointKind::kSlide); break;
      default: model.jnt_kind.push_back(JointKind::kHinge); break;
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
