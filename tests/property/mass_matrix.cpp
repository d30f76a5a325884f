// M(q) is symmetric and positive definite at every pose.
#include <Eigen/Cholesky>

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

}  // namespace lever::test
