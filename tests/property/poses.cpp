// The lean pose stage against the whole kinematics: poses() is what kinematics() places, and the
// quaternions kinematics() composes beside the rotation matrices describe the same rotations.
#include "property_models.hpp"

namespace lever::test {

namespace {

template <class T>
bool same(const std::vector<T>& a, const std::vector<T>& b) {
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i] != b[i]) return false;
  }
  return a.size() == b.size();
}

}  // namespace

TEST_CASE("property: poses() writes kinematics()' frames bit for bit and leaves xquat alone",
          "[property][kinematics]") {
  for (const ModelCase& c : every_model_and_random_trees()) {
    Data full(c.model), lean(c.model);
    std::mt19937_64 rng(c.seed);
    for (int k = 0; k < kStatesPerModel / 10; ++k) {
      const auto state = random_state(c.model, rng);
      apply(state, full);
      apply(state, lean);
      kinematics(c.model, full);
      // a mark poses() must not touch: it computes no quaternions
      for (auto& q : lean.xquat) q = Eigen::Vector4d(2, 0, 0, 0);
      poses(c.model, lean);
      INFO(c.name << ", seed " << c.seed << ", state " << k);
      CHECK(lean.qpos == full.qpos);  // both normalized the state's quaternions
      CHECK(same(lean.xpos, full.xpos));
      CHECK(same(lean.xmat, full.xmat));
      CHECK(same(lean.xipos, full.xipos));
      CHECK(same(lean.ximat, full.ximat));
      CHECK(same(lean.xanchor, full.xanchor));
      CHECK(same(lean.xaxis, full.xaxis));
      CHECK(same(lean.geom_xpos, full.geom_xpos));
      CHECK(same(lean.geom_xmat, full.geom_xmat));
      CHECK(same(lean.site_xpos, full.site_xpos));
      CHECK(same(lean.site_xmat, full.site_xmat));
      for (int b = 1; b < c.model.nbody; ++b) CHECK(lean.xquat[b] == Eigen::Vector4d(2, 0, 0, 0));
    }
  }
}

TEST_CASE("property: kinematics()' xquat is a unit quaternion whose rotation is xmat",
          "[property][kinematics]") {
  // xmat comes from products of rotation matrices and xquat from products of quaternions: the
  // same rotations, each product rounded on its own, so they agree to rounding (a few eps per
  // level of the tree), not bit for bit
  constexpr double kBound = 1e-13;
  for (const ModelCase& c : every_model_and_random_trees()) {
    Data data(c.model);
    std::mt19937_64 rng(c.seed);
    for (int k = 0; k < kStatesPerModel / 10; ++k) {
      apply(random_state(c.model, rng), data);
      kinematics(c.model, data);
      for (int b = 0; b < c.model.nbody; ++b) {
        INFO(c.name << ", seed " << c.seed << ", state " << k << ", body " << b);
        CHECK(std::abs(data.xquat[b].norm() - 1.0) <= kBound);
        const Eigen::Matrix3d from_quat = quat_to_mat(data.xquat[b]);
        CHECK((from_quat - Eigen::Matrix3d(data.xmat[b])).cwiseAbs().maxCoeff() <= kBound);
      }
    }
  }
}

}  // namespace lever::test
