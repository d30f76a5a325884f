// Actuator transmissions against MuJoCo 2.2.2: tests/models/actuators/transmissions.xml (joint
// and jointinparent on hinges, slides, balls and free joints, sites with and without a reference
// site, a slider-crank) and MuJoCo's slider-crank sample, on random states and in lockstep runs.
// Then tests/models/actuators/muscles.xml: filters, integrators with actrange, muscles (their
// curves, activation dynamics and the compiler's length ranges). actuator_length,
// actuator_moment, actuator_velocity, actuator_force, act, act_dot, qfrc_actuator and the state
// after each step agree within 1e-12.
#include <catch2/catch.hpp>
#include <lever/diff/compare.hpp>
#include <lever/diff/runs.hpp>
#include <lever/forward.hpp>

#include <filesystem>
#include <fstream>
#include <random>

#include <lever/harness/models.hpp>
#include "diff_checks.hpp"
#include "robots.hpp"

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
      check_lockstep_every_integrator(file, path, kActuatorRunSeconds);
    }
  }
}


namespace {

// Random states of a model with activations on both paths: every quantity within the bound,
// act_dot compared at each state; then lockstep runs under `integrators`.
void check_activation_model(const std::string& file,
                            std::initializer_list<Integrator> integrators) {
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
    for (const Integrator integrator : integrators) {
      INFO(integrator_name(integrator));
      diff::Twin run(file, path);
      check_within_bound(
          diff::lockstep(run, integrator, kActuatorRunSeconds, diff::Control::kSmooth));
    }
  }
}

}  // namespace

TEST_CASE("diff: muscles and activation dynamics agree with MuJoCo", "[diff][actuators][muscles]") {
  REQUIRE(mj_version() == 222);
  check_activation_model(model_path("tests/models/actuators/muscles.xml"),
                         {Integrator::kEuler, Integrator::kRK4, Integrator::kImplicit});
}

TEST_CASE("diff: intvelocity, damper and cylinder agree with MuJoCo", "[diff][actuators]") {
  REQUIRE(mj_version() == 222);
  check_activation_model(model_path("tests/models/actuators/shortcuts.xml"),
                         {Integrator::kEuler, Integrator::kImplicit});
}

namespace {

// A state of the adhesion scene with contacts of every kind likely: the box resting on the floor
// or pressed into it, slightly turned; the ball in the floor or in its margin's gap; the pad
// near the box's top half of the time; controls anywhere in their ranges.
State adhesion_state(const Model& model, std::mt19937_64& rng) {
  State s = random_state(model, rng);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const auto place = [&](const char* body, double x, double y, double z, double dz, double turn) {
    const int adr = model.jnt_qposadr[model.body_jntadr[model.body(body)]];  // its free joint
    s.qpos[adr + 0] = x + 0.02 * u(rng);
    s.qpos[adr + 1] = y + 0.02 * u(rng);
    s.qpos[adr + 2] = z + dz * u(rng);
    Eigen::Vector4d q(1.0, turn * u(rng), turn * u(rng), turn * u(rng));
    q.normalize();
    for (int k = 0; k < 4; ++k) s.qpos[adr + 3 + k] = q[k];
  };
  place("box", 0.0, 0.0, 0.048, 0.004, 0.05);
  place("ball", 0.2, 0.0, 0.035, 0.015, 0.0);
  if (u(rng) > 0) s.qpos[model.jnt_qposadr[model.joint("lift")]] = -0.052 + 0.006 * u(rng);
  return s;
}

}  // namespace

TEST_CASE("diff: adhesion (body transmissions) agrees with MuJoCo at random contact states",
          "[diff][actuators][contact]") {
  // actuator_moment and actuator_velocity are sums of the contact rows (efc_J) and the gap
  // contacts' normal rows: within 1e-12; qacc and qfrc_constraint, the solver's, within its bound
  // (MuJoCo at tolerance 0). Pyramidal and elliptic cones; condim 1 and 3; contacts with rows and
  // in the gap.
  REQUIRE(mj_version() == 222);
  const std::string file = model_path("tests/models/actuators/adhesion.xml");
  for (const Cone cone : {Cone::kPyramidal, Cone::kElliptic}) {
    for (const diff::Path path : paths_to_compare()) {
      INFO(context(file, path, 0) << (cone == Cone::kElliptic ? ", elliptic" : ", pyramidal"));
      diff::Twin twin(file, path);
      twin.set_cone(cone, 1.0);
      twin.m->opt.tolerance = 0;
      twin.m->opt.iterations = 1000;
      std::mt19937_64 rng(diff::default_seed(file));
      diff::Report report;
      report.set_solver_bound(diff::kContactSolverBound);
      int pad_contacts = 0, gap_contacts = 0, condim1 = 0;
      for (int k = 0; k < 40; ++k) {
        diff::compare_forward(twin, adhesion_state(twin.model, rng), k, report);
        for (int i = 0; i < twin.data.ncon; ++i) {
          const Contact& c = twin.data.contact[i];
          const int pad = twin.model.body("pad");
          pad_contacts += twin.model.geom_bodyid[c.geom1] == pad ||
                          twin.model.geom_bodyid[c.geom2] == pad;
          gap_contacts += c.exclude == 1;
          condim1 += c.dim == 1;
        }
      }
      CHECK(pad_contacts > 20);
      CHECK(gap_contacts > 20);
      CHECK(condim1 > 10);
      check_within_bound(report);
      std::string worst;
      for (const char* q : {"actuator_moment", "actuator_velocity", "qfrc_actuator", "qacc"}) {
        const diff::Extreme* e = report.find(q);
        REQUIRE(e != nullptr);
        worst += std::string(" ") + q + " " + std::to_string(e->max_ratio);
      }
      WARN(context(file, path, 0) << (cone == Cone::kElliptic ? ", elliptic: " : ", pyramidal: ")
                                  << pad_contacts << " pad contacts, " << gap_contacts
                                  << " in the gap, " << condim1 << " of condim 1; worst (of "
                                  << "1e-12):" << worst);
    }
  }
}

TEST_CASE("diff: adhesion in a lockstep run with contacts", "[diff][actuators][contact]") {
  REQUIRE(mj_version() == 222);
  const std::string file = model_path("tests/models/actuators/adhesion.xml");
  for (const diff::Path path : paths_to_compare()) {
    INFO(context(file, path, 0));
    // from the keyframe: the pad held on the box by its adhesion, the ball pulled to the floor
    diff::Twin twin(file, path);
    const diff::Report report =
        diff::lockstep(twin, Integrator::kEuler, kActuatorRunSeconds, diff::Control::kKeep);
    check_within_bound(report);
    const int pad = twin.model.actuator("pad");
    CHECK(twin.data.ncon >= 6);
    CHECK(twin.data.actuator_moment.row(pad).norm() > 0);  // still touching the box
    const diff::Extreme* qacc = report.find("qacc");
    REQUIRE(qacc != nullptr);
    WARN(context(file, path, 0) << ": " << twin.data.ncon << " contacts at the end; qacc worst "
                                << qacc->max_ratio << " of 1e-12");
  }
}

TEST_CASE("diff: MuJoCo's active adhesion sample, without its composite particles, agrees",
          "[diff][actuators][contact][robots]") {
  // the sample's own scene (two adhesion actuators, geoms with margin and gap, a spatial tendon
  // over pulleys, joint equalities, a medium), its <composite type="particle"> taken out
  REQUIRE(mj_version() == 222);
  const std::string real = robots_dir() + "/mujoco-2.2.2/adhesion/active_adhesion.xml";
  if (!robots_present(real)) return;
  std::string xml = read_text(real);
  const size_t from = xml.find("<composite"), to = xml.find("</composite>");
  REQUIRE(from != std::string::npos);
  REQUIRE(to != std::string::npos);
  xml.erase(from, to + std::string("</composite>").size() - from);
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / "lever_active_adhesion_without_composite.xml";
  {
    std::ofstream out(file);
    out << xml;
  }
  for (const diff::Path path : paths_to_compare()) {
    const std::uint64_t seed = diff::default_seed(real);
    INFO(context(real, path, seed));
    diff::Twin twin(file.string(), path);
    const diff::Report report = diff::random_states(twin, 20, seed);
    check_within_bound(report, all_but_inverse_at_forward(report));
    const diff::Extreme* moment = report.find("actuator_moment");
    REQUIRE(moment != nullptr);
    // an adhesion's moment is nonzero only in contact: some states must have had one
    CHECK(moment->max_abs_mujoco > 0);
    diff::Twin run(file.string(), path);
    check_within_bound(
        diff::lockstep(run, Integrator::kEuler, 0.02, diff::Control::kSmooth));
  }
  std::filesystem::remove(file);
}

}  // namespace lever::test
