// lever's MPR (engine/src/collision/mpr.hpp) against libccd's ccdMPRPenetration, the search
// MuJoCo 2.2.2 runs (Debian's libccd, the library Debian's MuJoCo links), bit for bit: both given
// the same geoms' support functions (lever's, detail::convex_support) and centres, the same
// tolerance and iterations, they must ask for the same support points in the same order and
// return the same depth, direction and point, every bit equal. And mpr_search, the engine's entry
// that records the points, must give the search's answer.
//
// Geoms: every solid type (sizes drawn) and two meshes from the shared robot files, the Panda's
// finger (OBJ) and hand (binary STL), each with its hull graph and neighbour table, with the graph
// alone, and with neither (every vertex visited). Every pair of them, margins 0 and 0.02, poses:
// random rotations from deep overlap to apart; grazing, the second geom moved along a random
// direction to where libccd's answer turns from overlap to none (bisection) and placed at it and
// either side of it; the centres coinciding (the nudge of v0); identity rotations with the centres
// apart along an axis (the origin on the segment v0 v1); tolerance 0 (the stop decided by
// roundings); and a short iteration limit.
#include <mujoco/mujoco.h>
#include <catch2/catch.hpp>

#include <ccd/ccd.h>
#include <ccd/vec3.h>

#include <array>
#include <bit>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include <lever/collision.hpp>
#include <lever/harness/from_mujoco.hpp>
#include <lever/harness/models.hpp>

#include "collision/mpr.hpp"
#include "collision/narrow_phase.hpp"
#include "sampling.hpp"

namespace lever::test::mpr_ccd {

namespace {

using Vec3 = Eigen::Vector3d;

std::string meshes_xml() {
  return R"(
<mujoco>
  <compiler meshdir=")" + robots_dir() + R"(/menagerie-2022/franka_emika_panda/assets/"/>
  <asset>
    <mesh name="finger" file="finger_0.obj"/>
    <mesh name="hand" file="hand.stl"/>
  </asset>
  <worldbody>
    <geom name="finger" type="mesh" mesh="finger"/>
    <geom name="hand" type="mesh" mesh="hand"/>
  </worldbody>
</mujoco>)";
}

/// A geom as both searches see it: its shape, and the support points asked of it, in order.
struct Geom {
  GeomShape shape;
  double margin = 0;
  std::vector<Vec3> asked;

  void support(const double* dir, double* point) {
    detail::convex_support(shape, margin, dir, point);
    asked.emplace_back(point[0], point[1], point[2]);
  }
};

// libccd's callbacks on a Geom
void ccd_support(const void* object, const ccd_vec3_t* dir, ccd_vec3_t* point) {
  static_cast<Geom*>(const_cast<void*>(object))->support(dir->v, point->v);
}
void ccd_center(const void* object, ccd_vec3_t* center) {
  const Vec3& pos = static_cast<const Geom*>(object)->shape.pos;
  for (int i = 0; i < 3; ++i) center->v[i] = pos[i];
}

/// lever's search's callbacks on a Geom
struct LeverSupport {
  Geom& geom;
  void operator()(const double* dir, double* point) { geom.support(dir, point); }
};

std::uint64_t bits(double x) { return std::bit_cast<std::uint64_t>(x); }

/// Every bit of a and b equal.
bool same(const double* a, const double* b, int n) {
  for (int i = 0; i < n; ++i) {
    if (bits(a[i]) != bits(b[i])) return false;
  }
  return true;
}

bool same_points(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  if (a.size() != b.size()) return false;
  for (size_t k = 0; k < a.size(); ++k) {
    if (!same(a[k].data(), b[k].data(), 3)) return false;
  }
  return true;
}

struct Outcome {
  bool found = false;
  double depth = 0;
  std::array<double, 3> dir{}, pos{};
  std::vector<Vec3> asked1, asked2;
};

Outcome run_ccd(const GeomShape& s1, const GeomShape& s2, double margin,
                const ConvexOptions& options) {
  Geom g1{s1, margin, {}}, g2{s2, margin, {}};
  ccd_t ccd;
  CCD_INIT(&ccd);
  ccd.support1 = ccd_support;
  ccd.support2 = ccd_support;
  ccd.center1 = ccd_center;
  ccd.center2 = ccd_center;
  ccd.max_iterations = static_cast<unsigned long>(options.mpr_iterations);
  ccd.mpr_tolerance = options.mpr_tolerance;
  ccd_real_t depth = 0;
  ccd_vec3_t dir{}, pos{};
  Outcome o;
  o.found = ccdMPRPenetration(&g1, &g2, &ccd, &depth, &dir, &pos) == 0;
  if (o.found) {
    o.depth = depth;
    for (int i = 0; i < 3; ++i) o.dir[i] = dir.v[i], o.pos[i] = pos.v[i];
  }
  o.asked1 = std::move(g1.asked);
  o.asked2 = std::move(g2.asked);
  return o;
}

Outcome run_lever(const GeomShape& s1, const GeomShape& s2, double margin,
                  const ConvexOptions& options) {
  Geom g1{s1, margin, {}}, g2{s2, margin, {}};
  LeverSupport a{g1}, b{g2};
  detail::mpr::Supports<LeverSupport, LeverSupport> both{a, b};
  detail::mpr::Search<double, decltype(both)> search(
      both, options.mpr_tolerance, static_cast<unsigned long>(options.mpr_iterations));
  detail::mpr::Answer<double> answer{};
  Outcome o;
  o.found = detail::mpr::overlapping(search.penetration({{s1.pos[0], s1.pos[1], s1.pos[2]}},
                                                        {{s2.pos[0], s2.pos[1], s2.pos[2]}},
                                                        answer));
  if (o.found) {
    o.depth = answer.depth;
    for (int i = 0; i < 3; ++i) o.dir[i] = answer.dir[i], o.pos[i] = answer.pos[i];
  }
  o.asked1 = std::move(g1.asked);
  o.asked2 = std::move(g2.asked);
  return o;
}

Eigen::Vector4d random_quaternion(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0, 1);
  const Eigen::Vector4d q(n(rng), n(rng), n(rng), n(rng));
  return q / q.norm();
}

Vec3 random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0, 1);
  const Vec3 v(n(rng), n(rng), n(rng));
  return v / v.norm();
}

double draw(std::mt19937_64& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

Mat3 rotation(const Eigen::Vector4d& q) {
  Mat3 R;
  mju_quat2Mat(R.data(), q.data());  // row by row, as Mat3 is stored
  return R;
}

/// The geoms to pair: the solids (sizes drawn per case) and the meshes in three variants.
class Geoms {
 public:
  Geoms() : model_(mujoco_load_string(meshes_xml())), lever_(from_mujoco(model_.get())) {
    for (const GeomType t : {GeomType::kSphere, GeomType::kCapsule, GeomType::kEllipsoid,
                             GeomType::kCylinder, GeomType::kBox}) {
      GeomShape s;
      s.type = t;
      shapes_.push_back(s);
      names_.push_back(std::string("type ") + std::to_string(static_cast<int>(t)));
    }
    for (int g = 0; g < 2; ++g) {
      const int mesh = lever_.geom_dataid[g];
      GeomShape s;
      s.type = GeomType::kMesh;
      s.size = lever_.geom_size[g];
      s.rbound = lever_.geom_rbound[g];
      s.mesh_vert = lever_.mesh_vert[static_cast<size_t>(lever_.mesh_vertadr[mesh])].data();
      s.mesh_vertnum = lever_.mesh_vertnum[mesh];
      const int graph = lever_.mesh_graphadr[mesh];
      REQUIRE(graph >= 0);
      s.mesh_graph = lever_.mesh_graph.data() + graph;
      s.mesh_hull = lever_.mesh_hull_neighbours.data() + graph;
      const std::string name = g == 0 ? "finger" : "hand";
      shapes_.push_back(s);
      names_.push_back(name + " (hull table)");
      s.mesh_hull = nullptr;
      shapes_.push_back(s);
      names_.push_back(name + " (hull graph)");
      s.mesh_graph = nullptr;
      shapes_.push_back(s);
      names_.push_back(name + " (every vertex)");
    }
  }

  int count() const { return static_cast<int>(shapes_.size()); }
  const std::string& name(int i) const { return names_[static_cast<size_t>(i)]; }

  /// Geom i with a drawn size (a solid) and rbound, posed at pos with rotation R.
  GeomShape posed(int i, std::mt19937_64& rng, const Vec3& pos, const Mat3& R) const {
    GeomShape s = shapes_[static_cast<size_t>(i)];
    if (s.type != GeomType::kMesh) {
      s.size = Vec3(draw(rng, 0.02, 0.2), draw(rng, 0.02, 0.2), draw(rng, 0.02, 0.2));
      s.rbound = s.size.norm() + s.size[0];  // a bound on every solid of these sizes
    }
    s.pos = pos;
    s.mat = R;
    return s;
  }

 private:
  MjModelPtr model_;
  Model lever_;
  std::vector<GeomShape> shapes_;
  std::vector<std::string> names_;
};

struct Tally {
  int cases = 0, found = 0, apart = 0, no_direction = 0, capped = 0;
};

/// Both searches on the pair; REQUIREs every bit equal. Returns whether they found an overlap.
bool compare(const GeomShape& s1, const GeomShape& s2, double margin, const ConvexOptions& options,
             Tally& tally) {
  const Outcome theirs = run_ccd(s1, s2, margin, options);
  const Outcome ours = run_lever(s1, s2, margin, options);
  ++tally.cases;
  REQUIRE(ours.found == theirs.found);
  REQUIRE(ours.asked1.size() == theirs.asked1.size());
  REQUIRE(same_points(ours.asked1, theirs.asked1));
  REQUIRE(same_points(ours.asked2, theirs.asked2));
  if (!theirs.found) {
    ++tally.apart;
    return false;
  }
  ++tally.found;
  REQUIRE(bits(ours.depth) == bits(theirs.depth));
  REQUIRE(same(ours.dir.data(), theirs.dir.data(), 3));
  REQUIRE(same(ours.pos.data(), theirs.pos.data(), 3));
  if (theirs.dir == std::array<double, 3>{0, 0, 0}) ++tally.no_direction;
  // the engine's entry: the same answer and the same number of support points
  constexpr int kCapacity = 1024;
  std::vector<Vec3> points1(kCapacity), points2(kCapacity);
  Contact c;
  const int asked =
      detail::mpr_search(s1, s2, margin, options, c, points1.data(), points2.data(), kCapacity);
  REQUIRE(asked == static_cast<int>(theirs.asked1.size()));
  const double dist = margin - theirs.depth;
  REQUIRE(bits(c.dist) == bits(dist));
  REQUIRE(same(c.pos.data(), theirs.pos.data(), 3));
  const Vec3 normal = c.frame.row(0).transpose();
  REQUIRE(same(normal.data(), theirs.dir.data(), 3));
  for (size_t k = 0; k < static_cast<size_t>(std::min(asked, kCapacity)); ++k) {
    REQUIRE(same(points1[k].data(), theirs.asked1[k].data(), 3));
    REQUIRE(same(points2[k].data(), theirs.asked2[k].data(), 3));
  }
  return true;
}

}  // namespace

TEST_CASE("MPR: lever's search and libccd's ccdMPRPenetration, bit for bit on every pair",
          "[collision][mpr]") {
  Geoms geoms;
  std::mt19937_64 rng(20260);
  Tally tally;
  // MuJoCo's default mpr_tolerance and mpr_iterations (the search's options, not a bound: every
  // comparison below is bit for bit)
  const ConvexOptions options{1e-6, 50, false};
  const Mat3 identity = Mat3::Identity();
  for (int i = 0; i < geoms.count(); ++i) {
    for (int j = i; j < geoms.count(); ++j) {
      for (const double margin : {0.0, 0.02}) {
        INFO(geoms.name(i) << " - " << geoms.name(j) << ", margin " << margin);
        // random rotations, the second geom from deep inside to beyond both bounds
        for (int k = 0; k < samples(100); ++k) {
          const GeomShape a = geoms.posed(i, rng, Vec3(draw(rng, -1, 1), draw(rng, -1, 1),
                                                       draw(rng, -1, 1)),
                                          rotation(random_quaternion(rng)));
          const double reach = a.rbound + geoms.posed(j, rng, Vec3::Zero(), identity).rbound;
          const Vec3 offset = random_unit(rng) * draw(rng, 0, 1.2 * reach);
          const GeomShape b = geoms.posed(j, rng, a.pos + offset, rotation(random_quaternion(rng)));
          INFO("random " << k);
          compare(a, b, margin, options, tally);
        }
        // grazing: the boundary along a random direction, found by bisection on libccd's answer
        for (int k = 0; k < samples(12); ++k) {
          const GeomShape a = geoms.posed(i, rng, Vec3(0.1, -0.2, 0.3),
                                          rotation(random_quaternion(rng)));
          GeomShape b = geoms.posed(j, rng, a.pos, rotation(random_quaternion(rng)));
          const Vec3 along = random_unit(rng);
          double inside = 0, outside = 2 * (a.rbound + b.rbound) + margin;
          for (int step = 0; step < 60; ++step) {
            const double mid = 0.5 * (inside + outside);
            b.pos = a.pos + along * mid;
            (run_ccd(a, b, margin, options).found ? inside : outside) = mid;
          }
          // the two sides of the boundary, and 1e-9 m within and beyond it (placements)
          for (const double at : {inside, outside, 0.5 * (inside + outside), inside - 1e-9,
                                  outside + 1e-9}) {
            b.pos = a.pos + along * at;
            INFO("grazing " << k << " at " << at);
            compare(a, b, margin, options, tally);
          }
        }
        // the centres coinciding: v0 on the origin, moved by libccd's nudge
        for (int k = 0; k < samples(8); ++k) {
          // the first two at the world's origin, geom 1's centre written -0 (v0 then -0, whose
          // sign libccd's nudge changes)
          const Vec3 at = k < 2 ? Vec3::Zero()
                                : Vec3(draw(rng, -1, 1), draw(rng, -1, 1), draw(rng, -1, 1));
          const GeomShape a = geoms.posed(i, rng, k == 1 ? Vec3(-0.0, -0.0, -0.0) : at,
                                          k == 0 ? identity : rotation(random_quaternion(rng)));
          const GeomShape b = geoms.posed(j, rng, at, k == 0 ? identity
                                                             : rotation(random_quaternion(rng)));
          INFO("coinciding " << k);
          compare(a, b, margin, options, tally);
        }
        // unrotated, apart along an axis: the origin on the line v0 v1
        for (int axis = 0; axis < 3; ++axis) {
          Vec3 offset = Vec3::Zero();
          const GeomShape a = geoms.posed(i, rng, Vec3::Zero(), identity);
          GeomShape b = geoms.posed(j, rng, Vec3::Zero(), identity);
          offset[axis] = 0.5 * (a.rbound + b.rbound);
          b.pos = offset;
          INFO("along axis " << axis);
          compare(a, b, margin, options, tally);
        }
        // tolerance 0: the expansion runs until a support point gains nothing but roundings,
        // where the order of each sum decides when it stops
        for (int k = 0; k < samples(8); ++k) {
          const GeomShape a = geoms.posed(i, rng, Vec3::Zero(), rotation(random_quaternion(rng)));
          const GeomShape b = geoms.posed(j, rng, random_unit(rng) * draw(rng, 0, a.rbound),
                                          rotation(random_quaternion(rng)));
          INFO("tolerance 0, case " << k);
          compare(a, b, margin, ConvexOptions{0.0, 100, false}, tally);
        }
        // few iterations and a fine tolerance: the expansion cut by the limit
        for (int k = 0; k < samples(4); ++k) {
          const GeomShape a = geoms.posed(i, rng, Vec3::Zero(), rotation(random_quaternion(rng)));
          const GeomShape b = geoms.posed(j, rng, random_unit(rng) * 0.3 * a.rbound,
                                          rotation(random_quaternion(rng)));
          INFO("capped " << k);
          ++tally.capped;
          compare(a, b, margin, ConvexOptions{1e-12, 2, false}, tally);
        }
      }
    }
  }
  INFO(tally.cases << " cases: " << tally.found << " overlapping (" << tally.no_direction
                   << " without a direction), " << tally.apart << " apart");
  // the cases reach both answers and the touch without a direction is not required (it needs
  // exact zeros), but overlap and separation both must occur many times
  CHECK(tally.cases >= samples(10000));
  CHECK(tally.found >= tally.cases / 4);
  CHECK(tally.apart >= tally.cases / 10);
  WARN(tally.cases << " cases: " << tally.found << " overlapping (" << tally.no_direction
                   << " without a direction), " << tally.apart << " apart");
}

}  // namespace lever::test::mpr_ccd
