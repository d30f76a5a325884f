// Equality constraints and friction loss against MuJoCo 2.2.2: random states, lockstep runs and
// free runs on the models of tests/models/constraints/, through MuJoCo's compiled model (the engine
// alone) and through lever's loader. The rows come first in MuJoCo's order (equality, friction
// loss, limits), and every quantity, the solver's answer included (qacc, efc_force,
// qfrc_constraint, at MuJoCo's tolerance 0), agrees within 1e-12.
#include <catch2/catch.hpp>
#include <lever/diff/runs.hpp>
#include <lever/forward.hpp>

#include <algorithm>
#include <cmath>
#include <random>

#include <lever/harness/models.hpp>
#include <lever/harness/random_state.hpp>
#include "diff_checks.hpp"
#include "sampling.hpp"

namespace lever::test {

namespace {

constexpr int kConstraintStates = samples(100);
constexpr double kConstraintRunSeconds = 0.4;

std::string constraint_model(const char* name) {
  return model_path(std::string("tests/models/constraints/") + name);
}

// How many of the rows of the last forward() have each kind and state.
struct RowCensus {
  int equality = 0, friction = 0, linear = 0, quadratic_friction = 0;
};

RowCensus census(const Data& data) {
  RowCensus c;
  for (int r = 0; r < data.nefc; ++r) {
    if (data.efc_type[r] == ConstraintType::kEquality) ++c.equality;
    if (data.efc_type[r] != ConstraintType::kFrictionDof) continue;
    ++c.friction;
    const ConstraintState s = data.efc_state[r];
    if (s == ConstraintState::kLinearNeg || s == ConstraintState::kLinearPos) ++c.linear;
    if (s == ConstraintState::kActive) ++c.quadratic_friction;
  }
  return c;
}

void random_states_agree(const char* name, diff::Path path) {
  REQUIRE(mj_version() == 222);
  const std::string file = constraint_model(name);
  const std::uint64_t seed = diff::default_seed(file);
  INFO(context(file, path, seed));
  diff::Twin twin(file, path);
  const diff::Report report = diff::random_states(twin, kConstraintStates, seed);
  check_within_bound(report, all_but_inverse_at_forward(report));
  inverse_at_forward_agrees(twin, kConstraintStates, seed);
  // the rows were the same rows in every state, and their forces were compared
  for (const char* q : {"nefc", "ne", "nf", "efc_force", "efc_state", "efc_frictionloss", "qacc",
                        "qfrc_constraint", "efc_J", "efc_R"}) {
    INFO(q);
    const diff::Extreme* e = report.find(q);
    REQUIRE(e != nullptr);
    CHECK(e->compared >= kConstraintStates);
  }
}

}  // namespace

TEST_CASE("diff: friction loss rows agree with MuJoCo on random states", "[diff][constraints]") {
  for (const diff::Path path : paths_to_compare()) random_states_agree("friction_loss.xml", path);
}

TEST_CASE("diff: equality constraint rows agree with MuJoCo on random states",
          "[diff][constraints]") {
  for (const diff::Path path : paths_to_compare()) random_states_agree("equality.xml", path);
}

TEST_CASE("diff: the rows come in MuJoCo's order, every state of a friction-loss row reached",
          "[diff][constraints]") {
  // friction_loss.xml at rest under gravity: the shoulder's friction holds the arm (its force at
  // the box's side) while the carriage's and the elbow's are inside it
  diff::Twin twin(constraint_model("friction_loss.xml"), diff::Path::kEngine);
  forward(twin.model, twin.data);
  const RowCensus rest = census(twin.data);
  CHECK(rest.friction == 10);  // the wrist's frictionloss 0 makes no row
  CHECK(rest.linear > 0);
  CHECK(rest.quadratic_friction > 0);
  // equality.xml: equality rows first, then nothing else (no limits, no friction)
  diff::Twin eq(constraint_model("equality.xml"), diff::Path::kEngine);
  forward(eq.model, eq.data);
  CHECK(eq.data.ne == 20);  // 3 + 3 + 6 + 6 + 1 + 1; the inactive coupling makes none
  CHECK(eq.data.nefc == eq.data.ne);
  for (int r = 0; r < eq.data.ne; ++r) CHECK(eq.data.efc_type[r] == ConstraintType::kEquality);
}

TEST_CASE("diff: equality constraints and friction loss in lockstep and free runs",
          "[diff][constraints]") {
  REQUIRE(mj_version() == 222);
  for (const char* name : {"friction_loss.xml", "equality.xml"}) {
    const std::string file = constraint_model(name);
    for (const diff::Path path : paths_to_compare()) {
      check_lockstep_every_integrator(file, path, kConstraintRunSeconds);
      check_free_run(file, path, kConstraintRunSeconds);
    }
  }
}

}  // namespace lever::test
