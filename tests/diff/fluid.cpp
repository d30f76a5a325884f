// Passive fluid forces (<option viscosity density wind>, MuJoCo 2.2.2's inertia-box model) against
// MuJoCo 2.2.2: random states (qfrc_passive, qacc and every other output; one Euler, RK4 and
// implicit step from each, the implicit one through the drag's velocity derivative) and lockstep
// runs on tests/models/fluid/medium.xml, both paths; and the real files that set a medium.
#include <catch2/catch.hpp>
#include <lever/diff/runs.hpp>
#include <lever/error.hpp>
#include <lever/forward.hpp>
#include <lever/mjcf.hpp>

#include <filesystem>
#include <string>

#include <lever/harness/models.hpp>
#include "diff_checks.hpp"
#include "robots.hpp"

namespace lever::test {

namespace {

constexpr int kFluidStates = 60;
constexpr double kFluidRunSeconds = 0.3;

std::string fluid_model() { return model_path("tests/models/fluid/medium.xml"); }

}  // namespace

TEST_CASE("diff: fluid forces agree with MuJoCo on random states and lockstep runs",
          "[diff][fluid]") {
  REQUIRE(mj_version() == 222);
  const std::string file = fluid_model();
  for (const diff::Path path : paths_to_compare()) {
    const std::uint64_t seed = diff::default_seed(file);
    INFO(context(file, path, seed));
    diff::Twin twin(file, path);
    REQUIRE(twin.model.opt.viscosity == 0.3);
    REQUIRE(twin.model.opt.density == 800);
    REQUIRE(twin.model.opt.wind == Eigen::Vector3d(1.5, -0.7, 0.4));
    const diff::Report report = diff::random_states(twin, kFluidStates, seed);
    check_within_bound(report);
    for (const char* q : {"qfrc_passive", "qacc", "qpos after one implicit step",
                          "qvel after one implicit step", "qvel after one RK4 step"}) {
      INFO(q);
      const diff::Extreme* e = report.find(q);
      REQUIRE(e != nullptr);
      CHECK(e->compared >= kFluidStates);
    }
    for (const Integrator integrator :
         {Integrator::kEuler, Integrator::kImplicit, Integrator::kRK4}) {
      INFO(integrator_name(integrator));
      check_within_bound(
          diff::lockstep(twin, integrator, kFluidRunSeconds, diff::Control::kZero));
    }
  }
}

TEST_CASE("diff: the medium is what moves the bodies in medium.xml", "[diff][fluid]") {
  // the comparison above would pass on a medium that did nothing if both engines ignored it:
  // lever's drag at the keyframe is far from the joint damping alone, and the wind alone (a body
  // at rest) pushes every body that has mass
  Model model = mjcf::load_file(fluid_model());
  Data data(model);
  reset_keyframe(model, data, model.key("gust"));
  forward(model, data);
  const Eigen::VectorXd with_medium = data.qfrc_passive;
  const Eigen::VectorXd damping_only =
      -Eigen::Map<const Eigen::VectorXd>(model.dof_damping.data(), model.nv).cwiseProduct(data.qvel);
  CHECK((with_medium - damping_only).cwiseAbs().minCoeff() > 1e-3);

  data.qvel.setZero();
  forward(model, data);
  CHECK(data.qfrc_passive.head<3>().norm() > 1e-2);  // the wind on the free box
  model.opt.wind.setZero();
  set_const(model);
  forward(model, data);
  CHECK(data.qfrc_passive.norm() == 0.0);  // no wind, at rest: no drag
}

TEST_CASE("diff: real files that set a medium load and agree, or are refused by another feature",
          "[diff][fluid][robots]") {
  REQUIRE(mj_version() == 222);
  const std::string folder = robots_dir();
  if (!robots_present(folder)) return;
  // (the third, flag/flag.xml, wind on a cloth without contacts: tests/diff/composites.cpp)
  for (const char* name : {"menagerie-2022/robotiq_2f85/scene.xml",
                           "mujoco-2.2.2/adhesion/active_adhesion.xml"}) {
    const std::string file = folder + "/" + name;
    INFO(file);
    Model model;
    try {
      model = mjcf::load_file(file);
    } catch (const Error& e) {
      // the medium itself is never what is refused
      const std::string why = e.what();
      INFO(why);
      for (const char* medium : {"'viscosity'", "'density'", "'wind'"}) {
        CHECK(why.find(medium) == std::string::npos);
      }
      continue;
    }
    CHECK(has_fluid(model.opt));
    for (const diff::Path path : paths_to_compare()) {
      const std::uint64_t seed = diff::default_seed(file);
      INFO(context(file, path, seed));
      diff::Twin twin(file, path);
      // contacts on: the 2F-85's finger meshes touch each other, the hanging box and the floor
      // in most random poses (MPR on the meshes' hulls), so the drag is compared beside the
      // contact forces, those held to the solver's bound (MuJoCo at tolerance 0)
      const diff::Report report = diff::random_states(twin, 20, seed);
      check_within_bound(report);
      const diff::Extreme* ncon = report.find("ncon");
      REQUIRE(ncon != nullptr);
      CHECK(ncon->max_abs_mujoco >= 1);  // some state had contacts to compare
    }
  }
}

}  // namespace lever::test
