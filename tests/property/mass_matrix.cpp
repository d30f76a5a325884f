// M(q) is symmetric and positive definite at every pose, and crba writes every entry of it.
#include <Eigen/Cholesky>

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

}  // namespace lever::test
