// The random trees the properties run on draw what they claim to: branching trees, welded bodies,
// both joint types, hinges about coordinate axes (set_const's own kernels) and general axes,
// springs, physical inertias; and a seed rebuilds its tree exactly.
#include <set>

#include "property_models.hpp"

namespace lever::test {

namespace {

// A rigid body's principal moments: each at most the sum of the other two.
bool rigid_body_moments(const Eigen::Vector3d& I) {
  return I.x() + I.y() >= I.z() && I.y() + I.z() >= I.x() && I.x() + I.z() >= I.y();
}

}  // namespace

TEST_CASE("property: the random trees cover what the properties should see", "[property][trees]") {
  std::set<JointKind> kinds;
  int branching = 0, welded = 0, springs = 0, offset_anchors = 0, largest_nv = 0;
  for (const ModelCase& c : random_trees()) {
    const Model& m = c.model;
    INFO(c.name);
    REQUIRE(m.nv >= 1);
    largest_nv = std::max(largest_nv, m.nv);
    std::vector<int> children(m.nbody, 0);
    for (int b = 1; b < m.nbody; ++b) {
      CHECK(m.body_parentid[b] < b);
      ++children[m.body_parentid[b]];
      if (m.body_jntnum[b] == 0) ++welded;
      CHECK(rigid_body_moments(m.body_inertia[b]));
      CHECK(m.body_mass[b] > 0);
    }
    for (int b = 1; b < m.nbody; ++b) branching += children[b] >= 2;
    for (int j = 0; j < m.njnt; ++j) {
      kinds.insert(m.jnt_kind[j]);
      springs += m.jnt_stiffness[j] > 0;
      offset_anchors += m.jnt_offset[j] != 0;
    }
    // the seed alone rebuilds the tree
    const Model again = random_tree(c.seed);
    CHECK(again.body_parentid == m.body_parentid);
    CHECK(again.jnt_axis == m.jnt_axis);
    CHECK(again.body_inertia == m.body_inertia);
  }
  CHECK(kinds.size() == 5);  // hinge about x, y, z, any other axis; slide
  CHECK(branching > 0);
  CHECK(welded > 0);
  CHECK(springs > 0);
  CHECK(offset_anchors > 0);
  CHECK(largest_nv >= 20);
}

TEST_CASE("property: the random MJCF trees have ball and free joints, branches and welds",
          "[property][trees]") {
  std::set<JointType> types;
  int branching = 0, welded = 0, free_roots = 0;
  for (const ModelCase& c : random_mjcf_trees()) {
    const Model& m = c.model;
    INFO(c.name);
    REQUIRE(m.nv >= 1);
    std::vector<int> children(m.nbody, 0);
    for (int b = 1; b < m.nbody; ++b) {
      ++children[m.body_parentid[b]];
      if (m.body_jntnum[b] == 0) ++welded;
      CHECK(rigid_body_moments(m.body_inertia[b]));
    }
    for (int b = 1; b < m.nbody; ++b) branching += children[b] >= 2;
    for (int j = 0; j < m.njnt; ++j) {
      types.insert(m.jnt_type[j]);
      if (m.jnt_type[j] == JointType::kFree) {
        ++free_roots;
        CHECK(m.body_parentid[m.jnt_bodyid[j]] == 0);  // MuJoCo: a free joint is on a root
      }
    }
    // the seed alone rebuilds the text
    CHECK(random_tree_mjcf(c.seed) == random_tree_mjcf(c.seed));
  }
  CHECK(types.size() == 4);  // hinge, slide, ball, free
  CHECK(branching > 0);
  CHECK(welded > 0);
  CHECK(free_roots > 0);
}

}  // namespace lever::test
