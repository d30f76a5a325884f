// M(q) is symmetric and positive definite at every pose, crba writes every entry of it, and a
// simple body's block of M, which crba copies, is what the whole algorithm computes.
#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <limits>

#include "property_models.hpp"

namespace lever::test {

TEST_CASE("property: M is exactly symmetric and positive definite", "[property][crba]") {
  for (const ModelCase& c : every_model_and_random_trees()) {
    Data data(c.model);
    std::mt19937_64 rng(c.seed);
    for (int k = 0; k < kStatesPerModel; ++k) {
      apply(random_state(c.model, rng), data);
      kinematics(c.model, data);
      crba(c.model, data);
      INFO(c.name << ", seed " << c.seed << ", state " << k);
      // crba fills both triangles from one computation: symmetry must hold bit for bit
      CHECK((data.M - data.M.transpose()).cwiseAbs().maxCoeff() == 0.0);
      const Eigen::LLT<Eigen::MatrixXd> llt(data.M);
      CHECK(llt.info() == Eigen::Success);
    }
  }
}

TEST_CASE("property: crba writes every entry of M, zero where two dofs are on different branches",
          "[property][crba]") {
  // crba clears no matrix first: it writes each entry, so nothing a caller left in M stays
  for (const ModelCase& c : every_model_and_random_trees()) {
    Data data(c.model);
    std::mt19937_64 rng(c.seed);
    for (int k = 0; k < kStatesPerModel / 10; ++k) {
      apply(random_state(c.model, rng), data);
      kinematics(c.model, data);
      data.M.setConstant(std::numeric_limits<double>::quiet_NaN());
      crba(c.model, data);
      INFO(c.name << ", seed " << c.seed << ", state " << k);
      for (int i = 0; i < c.model.nv; ++i) {
        for (int j = 0; j < i; ++j) {
          bool coupled = false;  // j an ancestor of i
          for (int a = c.model.dof_parentid[i]; a >= 0; a = c.model.dof_parentid[a])
            coupled |= a == j;
          INFO("dofs " << i << ", " << j);
          CHECK(std::isfinite(data.M(i, j)));
          if (!coupled) CHECK((data.M(i, j) == 0.0 && data.M(j, i) == 0.0));
        }
        CHECK(std::isfinite(data.M(i, i)));
      }
    }
  }
}

TEST_CASE("property: a simple body's block of M is what the whole CRBA computes at every state",
          "[property][crba]") {
  // crba() copies a simple body's diagonal from dof_M0 and zeroes its couplings (MuJoCo's
  // body_simple rule, Model::body_simple): right only if that block is the same at every state.
  // The same model with no dof marked simple computes the whole matrix.
  int simple_models = 0;
  for (const ModelCase& c : every_model_and_random_trees()) {
    if (std::none_of(c.model.dof_simplenum.begin(), c.model.dof_simplenum.end(),
                     [](int n) { return n > 0; }))
      continue;
    ++simple_models;
    Model whole = c.model;
    std::fill(whole.dof_simplenum.begin(), whole.dof_simplenum.end(), 0);
    Data data(c.model), reference(whole);
    std::mt19937_64 rng(c.seed);
    for (int k = 0; k < kStatesPerModel; ++k) {
      const auto state = random_state(c.model, rng);
      apply(state, data);
      apply(state, reference);
      kinematics(c.model, data);
      crba(c.model, data);
      kinematics(whole, reference);
      crba(whole, reference);
      INFO(c.name << ", seed " << c.seed << ", state " << k);
      for (int i = 0; i < c.model.nv; ++i) {
        if (c.model.dof_simplenum[i] > 0) {
          CHECK(data.M(i, i) == c.model.dof_M0[i]);
          for (int j = c.model.dof_parentid[i]; j >= 0; j = c.model.dof_parentid[j])
            CHECK(data.M(i, j) == 0.0);
        }
        for (int j = 0; j < c.model.nv; ++j) {
          INFO("M(" << i << ", " << j << ")");
          const double expected = reference.M(i, j);
          CHECK(std::abs(data.M(i, j) - expected) <= 1e-12 * std::max(1.0, std::abs(expected)));
        }
      }
    }
  }
  CHECK(simple_models >= 3);  // box_drop, gripper, tests/models/simple_bodies.xml at least
}

}  // namespace lever::test
