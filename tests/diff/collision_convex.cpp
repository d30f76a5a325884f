// The general convex pairs against MuJoCo 2.2.2's own pair functions (mjc_Convex and
// mjc_PlaneConvex through mjCOLLISIONFUNC), one geom pair at a time: every pair of types that
// MuJoCo runs MPR for, with both engines given the same sizes, positions, rotation matrices,
// bounding radii, mesh vertices and hull graphs, the same mpr_tolerance and mpr_iterations, with
// and without multiccd. They must return the same number of contacts in the same order with dist,
// pos and the frame rows they set within the agreement bound.
//
// Poses per pair: random ones from deep overlap to beyond the margin; grazing ones, the second
// geom moved along a random direction to where MuJoCo's answer changes from contact to none
// (found by bisection to 1e-9 m) and then placed 1e-7 m either side; resting ones, the second
// geom straight above the first at the distance of their support points along z (faces and
// discs parallel, MPR's ties).
#include <mujoco/mujoco.h>
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <map>
#include <random>
#include <string>
#include <vector>

#include <lever/collision.hpp>
#include <lever/harness/from_mujoco.hpp>
#include <lever/harness/models.hpp>
#include <lever/harness/tolerance.hpp>

namespace lever::test::convex_diff {

namespace {

using Vec3 = Eigen::Vector3d;

// two geoms of each convex type (ids in this order), and two meshes from the shared robot files:
// the Robotiq 2F-85's coupler and the Panda's hand (binary STL)
std::string shapes_xml() {
  return R"(
<mujoco>
  <compiler meshdir=")" + robots_dir() + R"(/"/>
  <asset>
    <mesh name="finger" file="menagerie-2022/robotiq_2f85/assets/coupler.stl"/>
    <mesh name="hand" file="menagerie-2022/franka_emika_panda/assets/hand.stl"/>
  </asset>
  <worldbody>
    <geom name="plane" type="plane" size="1 1 0.1"/>
    <geom name="sphere" type="sphere" size="0.1"/>
    <geom name="capsule" type="capsule" size="0.1 0.2"/>
    <geom name="ellipsoid" type="ellipsoid" size="0.1 0.2 0.3"/>
    <geom name="cylinder" type="cylinder" size="0.1 0.2"/>
    <geom name="box" type="box" size="0.1 0.2 0.3"/>
    <geom name="mesh" type="mesh" mesh="finger"/>
    <geom name="sphere2" type="sphere" size="0.1"/>
    <geom name="capsule2" type="capsule" size="0.1 0.2"/>
    <geom name="ellipsoid2" type="ellipsoid" size="0.1 0.2 0.3"/>
    <geom name="cylinder2" type="cylinder" size="0.1 0.2"/>
    <geom name="box2" type="box" size="0.1 0.2 0.3"/>
    <geom name="mesh2" type="mesh" mesh="hand"/>
  </worldbody>
</mujoco>)";
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

/// The two engines side by side on geoms of the shapes model.
class ConvexBench {
 public:
  ConvexBench()
      : model_(mujoco_load_string(shapes_xml())),
        data_(mujoco_data(model_.get())),
        lever_(from_mujoco(model_.get())) {
    mj_kinematics(model_.get(), data_.get());
  }

  int geom(const char* name) const { return mj_name2id(model_.get(), mjOBJ_GEOM, name); }
  mjModel* model() { return model_.get(); }

  void set_options(double tolerance, int iterations, bool multiccd) {
    model_->opt.mpr_tolerance = tolerance;
    model_->opt.mpr_iterations = iterations;
    if (multiccd) {
      model_->opt.enableflags |= mjENBL_MULTICCD;
    } else {
      model_->opt.enableflags &= ~mjENBL_MULTICCD;
    }
    options_ = ConvexOptions{tolerance, iterations, multiccd};
  }

  /// Place geom g (size for primitives; meshes keep theirs) at pos with orientation quat.
  void place(int g, const Vec3& pos, const Eigen::Vector4d& quat, const Vec3& size) {
    mjModel* m = model_.get();
    mjData* d = data_.get();
    Eigen::Vector4d q = quat;
    mju_normalize4(q.data());
    mju_quat2Mat(d->geom_xmat + 9 * g, q.data());
    for (int i = 0; i < 3; ++i) d->geom_xpos[3 * g + i] = pos[i];
    if (m->geom_type[g] != mjGEOM_MESH) {
      for (int i = 0; i < 3; ++i) m->geom_size[3 * g + i] = size[i];
      m->geom_rbound[g] = bounding_radius(m->geom_type[g], size);
    }
  }

  /// MuJoCo's number of contacts for the pair as placed.
  int mujoco_count(int g1, int g2, double margin) {
    std::array<mjContact, mjMAXCONPAIR> c{};
    mjModel* m = model_.get();
    return mjCOLLISIONFUNC[m->geom_type[g1]][m->geom_type[g2]](m, data_.get(), c.data(), g1, g2,
                                                               margin);
  }

  /// Both engines on the pair as placed; returns the number of contacts (after checking).
  int compare(int g1, int g2, double margin, const std::string& what) {
    mjModel* m = model_.get();
    mjData* d = data_.get();
    std::array<mjContact, mjMAXCONPAIR> theirs{};
    const int n_mujoco =
        mjCOLLISIONFUNC[m->geom_type[g1]][m->geom_type[g2]](m, d, theirs.data(), g1, g2, margin);
    std::array<Contact, kMaxPairContacts> ours;
    for (Contact& c : ours) c.frame.setZero();
    const int n_lever = collide_shapes(shape(g1), shape(g2), margin, ours.data(), options_);

    INFO(what << ": " << mj_id2name(m, mjOBJ_GEOM, g1) << " - " << mj_id2name(m, mjOBJ_GEOM, g2)
              << ", margin " << margin << (options_.multiccd ? ", multiccd" : ""));
    REQUIRE(n_lever == n_mujoco);
    for (int k = 0; k < n_mujoco; ++k) {
      const mjContact& c = theirs[k];
      INFO("contact " << k);
      check("dist", 0, ours[k].dist, c.dist, c.dist);
      const double pos_size = magnitude(c.pos, 3);
      for (int i = 0; i < 3; ++i) check("pos", i, ours[k].pos[i], c.pos[i], pos_size);
      for (int i = 0; i < 6; ++i) check("frame", i, ours[k].frame(i / 3, i % 3), c.frame[i], 1.0);
    }
    const std::string key = std::string(mj_id2name(m, mjOBJ_GEOM, g1)) + "-" +
                            mj_id2name(m, mjOBJ_GEOM, g2);
    Tally& t = tally_[key];
    ++t.cases;
    t.contacts += n_mujoco;
    if (n_mujoco > 1) ++t.multiple;
    t.worst = std::max(t.worst, last_worst_);
    last_worst_ = 0;
    return n_mujoco;
  }

  struct Tally {
    int cases = 0, contacts = 0, multiple = 0;
    double worst = 0;
  };
  const std::map<std::string, Tally>& tally() const { return tally_; }

 private:
  MjModelPtr model_;
  MjDataPtr data_;
  Model lever_;
  ConvexOptions options_;
  std::map<std::string, Tally> tally_;
  double last_worst_ = 0;

  static double bounding_radius(int type, const Vec3& s) {
    switch (type) {
      case mjGEOM_SPHERE: return s[0];
      case mjGEOM_CAPSULE: return s[0] + s[1];
      case mjGEOM_CYLINDER: return std::sqrt(s[0] * s[0] + s[1] * s[1]);
      case mjGEOM_ELLIPSOID: return std::max(std::max(s[0], s[1]), s[2]);
      default: return s.norm();
    }
  }

  GeomShape shape(int g) const {
    const mjModel* m = model_.get();
    const mjData* d = data_.get();
    GeomShape s;
    s.type = static_cast<GeomType>(m->geom_type[g]);
    for (int i = 0; i < 3; ++i) {
      s.size[i] = m->geom_size[3 * g + i];
      s.pos[i] = d->geom_xpos[3 * g + i];
    }
    for (int i = 0; i < 9; ++i) s.mat(i / 3, i % 3) = d->geom_xmat[9 * g + i];
    s.rbound = m->geom_rbound[g];
    const int mesh = lever_.geom_dataid[g];
    if (s.type == GeomType::kMesh) {
      s.mesh_vert = lever_.mesh_vert[lever_.mesh_vertadr[mesh]].data();
      s.mesh_vertnum = lever_.mesh_vertnum[mesh];
      const int graph = lever_.mesh_graphadr[mesh];
      s.mesh_graph = graph >= 0 ? lever_.mesh_graph.data() + graph : nullptr;
    }
    return s;
  }

  void check(const char* field, int index, double ours, double reference, double size) {
    const double e = excess(ours, reference, size);
    last_worst_ = std::max(last_worst_, e);
    INFO(describe(field, index, ours, reference, size));
    CHECK(e <= 1.0);
  }
};

/// A size for a geom of this type (sphere: radius; capsule, cylinder: radius, half-length).
Vec3 random_size(int type, std::mt19937_64& rng) {
  const Vec3 s(draw(rng, 0.03, 0.3), draw(rng, 0.03, 0.3), draw(rng, 0.03, 0.3));
  if (type == mjGEOM_SPHERE) return Vec3(s[0], 0, 0);
  if (type == mjGEOM_CAPSULE || type == mjGEOM_CYLINDER) return Vec3(s[0], s[1], 0);
  return s;
}

struct ConvexPair {
  const char* g1;
  const char* g2;
};

/// The pairs MuJoCo 2.2.2 runs MPR (or the plane's support point) for, each type order once as
/// its table has them.
const std::vector<ConvexPair>& convex_pairs() {
  static const std::vector<ConvexPair> pairs = {
      {"plane", "ellipsoid"},  {"plane", "mesh"},        {"sphere", "ellipsoid"},
      {"sphere", "cylinder"},  {"sphere", "mesh"},       {"capsule", "ellipsoid"},
      {"capsule", "cylinder"}, {"capsule", "mesh"},      {"ellipsoid", "ellipsoid2"},
      {"ellipsoid", "cylinder"}, {"ellipsoid", "box"},   {"ellipsoid", "mesh"},
      {"cylinder", "cylinder2"}, {"cylinder", "box"},    {"cylinder", "mesh"},
      {"box", "mesh"},         {"mesh", "mesh2"}};
  return pairs;
}

}  // namespace

TEST_CASE("convex pairs: MPR on MuJoCo's support functions agrees with mjc_Convex",
          "[diff][collision]") {
  REQUIRE(mj_version() == 222);
  ConvexBench bench;
  std::mt19937_64 rng(20261129);
  const mjModel* m = bench.model();
  for (const bool multiccd : {false, true}) {
    bench.set_options(multiccd ? 1e-8 : 1e-6, multiccd ? 100 : 50, multiccd);
    for (const ConvexPair& pair : convex_pairs()) {
      const int g1 = bench.geom(pair.g1), g2 = bench.geom(pair.g2);
      REQUIRE(g1 >= 0);
      REQUIRE(g2 >= 0);
      const int t1 = m->geom_type[g1], t2 = m->geom_type[g2];
      const bool plane = t1 == mjGEOM_PLANE;
      int touching = 0;
      for (int trial = 0; trial < 300; ++trial) {
        const Vec3 s1 = plane ? Vec3(1, 1, 0.1) : random_size(t1, rng);
        const Vec3 s2 = random_size(t2, rng);
        const Vec3 p1(draw(rng, -0.5, 0.5), draw(rng, -0.5, 0.5), draw(rng, -0.5, 0.5));
        const Eigen::Vector4d q1 = random_quaternion(rng), q2 = random_quaternion(rng);
        bench.place(g1, p1, q1, s1);
        const double margin = trial % 3 == 0 ? 0.0 : draw(rng, 0, 0.05);
        const double reach = m->geom_rbound[g1] + (t2 == mjGEOM_MESH ? m->geom_rbound[g2] : s2.norm());
        const Vec3 along = random_unit(rng);
        const std::string what = "trial " + std::to_string(trial);
        switch (trial % 3) {
          case 0: {  // from deep overlap to beyond the margin
            bench.place(g2, p1 + along * draw(rng, 0, 1.1 * reach + margin), q2, s2);
            if (bench.compare(g1, g2, margin, "random, " + what) > 0) ++touching;
            break;
          }
          case 1: {  // grazing: bisect MuJoCo's verdict along `along`
            double near = 0, far = 2 * reach + margin + 1;
            bench.place(g2, p1, q2, s2);
            if (bench.mujoco_count(g1, g2, margin) == 0) break;  // no overlap even centred
            while (far - near > 1e-9) {
              const double mid = 0.5 * (near + far);
              bench.place(g2, p1 + along * mid, q2, s2);
              (bench.mujoco_count(g1, g2, margin) > 0 ? near : far) = mid;
            }
            for (const double offset : {-1e-7, 0.0, 1e-7}) {
              bench.place(g2, p1 + along * (near + offset), q2, s2);
              if (bench.compare(g1, g2, margin, "grazing, " + what) > 0) ++touching;
            }
            break;
          }
          default: {  // resting: straight above, turned only about z (parallel faces and discs)
            const double turn = draw(rng, -M_PI, M_PI);
            const Eigen::Vector4d upright(std::cos(turn / 2), 0, 0, std::sin(turn / 2));
            bench.place(g1, p1, Eigen::Vector4d(1, 0, 0, 0), s1);
            const double height = (plane ? 0 : m->geom_rbound[g1]) +
                                  (t2 == mjGEOM_MESH ? m->geom_rbound[g2] : s2.norm());
            double near = 0, far = 2 * height + 1;
            bench.place(g2, p1, upright, s2);
            if (bench.mujoco_count(g1, g2, margin) == 0) break;
            while (far - near > 1e-9) {
              const double mid = 0.5 * (near + far);
              bench.place(g2, p1 + Vec3(0, 0, mid), upright, s2);
              (bench.mujoco_count(g1, g2, margin) > 0 ? near : far) = mid;
            }
            for (const double depth : {0.0, 1e-3, 2e-2}) {
              bench.place(g2, p1 + Vec3(0, 0, near - depth), upright, s2);
              if (bench.compare(g1, g2, margin, "resting, " + what) > 0) ++touching;
            }
          }
        }
      }
      INFO(pair.g1 << " - " << pair.g2);
      CHECK(touching > 100);  // the poses reach the contact branches
    }
  }
  std::string table;
  for (const auto& [pair, t] : bench.tally()) {
    table += "\n  " + pair + ": " + std::to_string(t.cases) + " cases, " +
             std::to_string(t.contacts) + " contacts (" + std::to_string(t.multiple) +
             " with more than one), worst " + std::to_string(t.worst) + " of the bound";
  }
  WARN("convex pairs against MuJoCo's pair functions:" << table);
}

}  // namespace lever::test::convex_diff
