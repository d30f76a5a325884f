// Actuator transmissions against MuJoCo 2.2.2: tests/models/actuators/transmissions.xml (joint
// and jointinparent on hinges, slides, balls and free joints, sites with and without a reference
// site, a slider-crank) and MuJoCo's slider-crank sample, on random states and in lockstep runs.
// Then tests/models/actuators/muscles.xml: filters, integrators with actrange, muscles (their
// curves, activation dynamics and the compiler's length ranges). actuator_length,
// actuator_moment, actuator_velocity, actuator_force, act, act_dot, qfrc_actuator and the state
// after each step agree within 1e-12.
#include <catch2/catch.hpp>
#include <lever/diff/runs.hpp>
#include <lever/forward.hpp>

#include <filesystem>

#include <lever/harness/models.hpp>
#include "diff_checks.hpp"

namespace lever::test {

namespace {

constexpr int kActuatorStates = 60;
constexpr double kActuatorRunSeconds = 0.2;

void require_actuator_quantities(const diff::Report& report, int states) {
  for (const char* q : {"actuator_length", "actuator_moment", "actuator_velocity",
                        "actuator_force", "qfrc_actuator", "qacc"}) {
    INFO(q);
    const diff::Extreme* e = report.find(q);
    REQUIRE(e != nullptr);
    CHECK(e->compared >= states);
  }
}

std::vector<std::string> actuator_model_files() {
  std::vector<std::string> files = {model_path("tests/models/actuators/transmissions.xml")};
  const std::string crank = robots_dir() + "/mujoco-2.2.2/slider_crank/slider_crank.xml";
  if (std::filesystem::exists(crank)) files.push_back(crank);
  return files;
}

}  // namespace

TEST_CASE("diff: actuator transmissions agree with MuJoCo on random states",
          "[diff][actuators]") {
  REQUIRE(mj_version() == 222);
  for (const std::string& file : actuator_model_files()) {
    for (const diff::Path path : paths_to_compare()) {
      const std::uint64_t seed = diff::default_seed(file);
      INFO(context(file, path, seed));
      diff::Twin twin(file, path);
      const diff::Report report = diff::random_states(twin, kActuatorStates, seed);
      check_within_bound(report, all_but_inverse_at_forward(report));
      require_actuator_quantities(report, kActuatorStates);
    }
  }
}

TEST_CASE("diff: actuator transmissions in lockstep runs", "[diff][actuators]") {
  REQUIRE(mj_version() == 222);
  for (const std::string& file : actuator_model_files()) {
    for (const diff::Path path : paths_to_compare()) {
      for (const Integrator integrator :
           {Integrator::kEuler, Integrator::kRK4, Integrator::kImplicit}) {
        INFO(context(file, path, 0) << ", " << integrator_name(integrator));
        diff::Twin twin(file, path);
        check_within_bound(
            diff::lockstep(twin, integrator, kActuatorRunSeconds, diff::Control::kSmooth));
      }
    }
  }
}


TEST_CASE("diff: muscles and activation dynamics agree with MuJoCo", "[diff][actuators][muscles]") {
  REQUIRE(mj_version() == 222);
  const std::string file = model_path("tests/models/actuators/muscles.xml");
  for (const diff::Path path : paths_to_compare()) {
    const std::uint64_t seed = diff::default_seed(file);
    INFO(context(file, path, seed));
    diff::Twin twin(file, path);
    const diff::Report report = diff::random_states(twin, kActuatorStates, seed);
    check_within_bound(report, all_but_inverse_at_forward(report));
    require_actuator_quantities(report, kActuatorStates);
    const diff::Extreme* act_dot = report.find("act_dot");
    REQUIRE(act_dot != nullptr);
    CHECK(act_dot->compared >= kActuatorStates);
    for (const Integrator integrator :
         {Integrator::kEuler, Integrator::kRK4, Integrator::kImplicit}) {
      INFO(integrator_name(integrator));
      diff::Twin run(file, path);
      check_within_bound(
          diff::lockstep(run, integrator, kActuatorRunSeconds, diff::Control::kSmooth));
    }
  }
}

}  // namespace lever::test
