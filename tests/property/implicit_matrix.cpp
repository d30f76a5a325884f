// The implicit integrator's matrix K = M - h D (engine/src/pipeline/implicit.cpp) on every model and random
// tree (branches, several joints in one body, ball and free joints):
//  - D's bias part is -d qfrc_bias / d qvel. qfrc_bias is quadratic in qvel, so a central
//    difference with any step is exact but for rounding; a step of 1 keeps that rounding near
//    eps |qfrc_bias| (measured: at most 3.6e-15 of the scale over every model and tree), so the
//    project's 1e-12 of the scale holds with room, far below a wrong term (a missing Coriolis
//    product changes an entry by O(|qvel|)).
//  - K is non-zero only where M is (dofs on one branch), and factor_lu_tree's (U + I) L is K again,
//    without pivoting and without fill-in; solve_lu_tree solves K x = f.
#include <cmath>
#include <utility>

#include "pipeline/pipeline.hpp"
#include "property_models.hpp"

namespace lever::test {

namespace {

constexpr double kImplicitMatrixBound = 1e-12;
constexpr int kImplicitMatrixStates = kStatesPerModel / 4;

// Whether dofs i and j are on one branch (one is the other or an ancestor of it).
bool on_one_branch(const Model& model, int i, int j) {
  if (i < j) std::swap(i, j);
  while (i > j) i = model.dof_parentid[i];
  return i == j;
}

}  // namespace

TEST_CASE("property: the implicit step's D is -d qfrc_bias / d qvel plus the actuators and dampers",
          "[property][implicit]") {
  for (const ModelCase& c : every_model_and_random_trees()) {
    const Model& model = c.model;
    Data data(model), moved(model);
    std::mt19937_64 rng(c.seed);
    Eigen::MatrixXd D(model.nv, model.nv), expected(model.nv, model.nv);
    for (int k = 0; k < states_for(c, kImplicitMatrixStates); ++k) {
      apply(random_state(model, rng), data);
      forward(model, data);
      smooth_velocity_derivative(model, data, D);
      double scale = std::max(1.0, max_abs(data.qfrc_bias));
      for (int j = 0; j < model.nv; ++j) {
        moved = data;
        moved.qvel[j] = data.qvel[j] + 1.0;
        forward(model, moved);
        const Eigen::VectorXd plus = moved.qfrc_bias;
        moved.qvel[j] = data.qvel[j] - 1.0;
        forward(model, moved);
        expected.col(j) = -(plus - moved.qfrc_bias) / 2.0;
        scale = std::max({scale, max_abs(plus), max_abs(moved.qfrc_bias)});
      }
      add_actuator_damping_velocity_terms(model, data, expected);
      INFO(c.name << ", seed " << c.seed << ", state " << k);
      CHECK((D - expected).cwiseAbs().maxCoeff() <= kImplicitMatrixBound * scale);
    }
  }
}

TEST_CASE("property: M - h D factors as (U + I) L without pivoting or fill-in, and solves",
          "[property][implicit]") {
  for (const ModelCase& c : every_model_and_random_trees()) {
    const Model& model = c.model;
    const int nv = model.nv;
    Data data(model);
    std::mt19937_64 rng(c.seed);
    Eigen::MatrixXd D(nv, nv);
    for (int k = 0; k < states_for(c, kImplicitMatrixStates); ++k) {
      apply(random_state(model, rng), data);
      forward(model, data);
      smooth_velocity_derivative(model, data, D);
      const Eigen::MatrixXd K = data.M - model.opt.timestep * D;
      INFO(c.name << ", seed " << c.seed << ", state " << k);
      for (int i = 0; i < nv; ++i) {
        for (int j = 0; j < nv; ++j) {
          if (!on_one_branch(model, i, j)) CHECK(K(i, j) == 0.0);
        }
      }
      Eigen::MatrixXd factor = K;
      factor_lu_tree(model, factor);
      const Eigen::MatrixXd U = factor.triangularView<Eigen::StrictlyUpper>().toDenseMatrix() +
                                Eigen::MatrixXd::Identity(nv, nv);
      const Eigen::MatrixXd L = factor.triangularView<Eigen::Lower>();
      const double scale = std::max(1.0, K.cwiseAbs().maxCoeff());
      CHECK((U * L - K).cwiseAbs().maxCoeff() <= 1e-12 * scale);
      // the factor keeps M's pattern: nothing filled in off the branches
      for (int i = 0; i < nv; ++i) {
        for (int j = 0; j < nv; ++j) {
          if (!on_one_branch(model, i, j)) CHECK(factor(i, j) == 0.0);
        }
      }
      const Eigen::VectorXd f = data.qfrc_smooth + data.qfrc_constraint;
      Eigen::VectorXd x = f;
      solve_lu_tree(model, factor, x.data(), data.work.dof_chain.data());
      CHECK((K * x - f).cwiseAbs().maxCoeff() <=
            1e-12 * std::max({1.0, max_abs(f), scale * max_abs(x)}));
    }
  }
}

}  // namespace lever::test
