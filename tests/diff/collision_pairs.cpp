// The narrow phase against MuJoCo 2.2.2's own pair functions (mjCOLLISIONFUNC), one geom pair
// at a time: both are given the same sizes, positions and rotation matrices (written into
// MuJoCo's mjData and copied into lever's GeomShape), and must return the same number of contacts
// in the same order with dist, pos and the frame rows they set within the agreement bound.
//
// Poses: random ones near contact, and deliberate ones at MuJoCo's branch points (resting flat,
// a disc parallel to the plane, parallel capsules, coincident centres), each also tilted 1e-9
// away from the tie, within the margin, and in deep penetration.
#include <mujoco/mujoco.h>
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <lever/collision.hpp>
#include <lever/harness/from_mujoco.hpp>
#include <lever/harness/tolerance.hpp>

namespace lever::test {

namespace {

// one geom of each type, ids in this order; poses and sizes are overwritten per case
constexpr const char* kShapes = R"(
<mujoco>
  <worldbody>
    <geom name="plane" type="plane" size="1 1 0.1"/>
    <geom name="sphere" type="sphere" size="0.1"/>
    <geom name="capsule" type="capsule" size="0.1 0.2"/>
    <geom name="ellipsoid" type="ellipsoid" size="0.1 0.2 0.3"/>
    <geom name="cylinder" type="cylinder" size="0.1 0.2"/>
    <geom name="box" type="box" size="0.1 0.2 0.3"/>
    <geom name="sphere2" type="sphere" size="0.1"/>
    <geom name="capsule2" type="capsule" size="0.1 0.2"/>
  </worldbody>
</mujoco>)";

using Vec3 = Eigen::Vector3d;
using Quat = Eigen::Vector4d;

/// One geom's pose and size for a case.
struct Pose {
  Vec3 pos{0, 0, 0};
  Quat quat{1, 0, 0, 0};
  Vec3 size{0.1, 0.1, 0.1};
};

Quat axis_angle(const Vec3& axis, double angle) {
  const Vec3 u = axis.normalized();
  return Quat(std::cos(angle / 2), std::sin(angle / 2) * u[0], std::sin(angle / 2) * u[1],
              std::sin(angle / 2) * u[2]);
}

Quat compose(const Quat& a, const Quat& b) {
  Quat r;
  mju_mulQuat(r.data(), a.data(), b.data());
  return r;
}

/// The two engines side by side, on geoms g1 and g2 of kShapes.
class PairBench {
 public:
  PairBench() : model_(mujoco_load_string(kShapes)), data_(mujoco_data(model_.get())) {}

  int geom(const char* name) const { return mj_name2id(model_.get(), mjOBJ_GEOM, name); }
  GeomType type(int g) const { return static_cast<GeomType>(model_->geom_type[g]); }

  /// Runs one case; returns how many contacts both found (after checking they agree).
  int compare(int g1, int g2, const Pose& p1, const Pose& p2, double margin,
              const std::string& what) {
    mjModel* m = model_.get();
    mjData* d = data_.get();
    const GeomShape s1 = place(g1, p1), s2 = place(g2, p2);

    std::array<mjContact, mjMAXCONPAIR> theirs{};
    const int n_mujoco =
        mjCOLLISIONFUNC[m->geom_type[g1]][m->geom_type[g2]](m, d, theirs.data(), g1, g2, margin);
    std::array<Contact, kMaxPairContacts> ours;
    const int n_lever = collide_shapes(s1, s2, margin, ours.data());

    INFO(what << ": " << m->names + m->name_geomadr[g1] << " - " << m->names + m->name_geomadr[g2]
              << ", margin " << margin);
    REQUIRE(n_lever == n_mujoco);
    for (int k = 0; k < n_mujoco; ++k) {
      const mjContact& c = theirs[k];
      INFO("contact " << k);
      check_value("dist", 0, ours[k].dist, c.dist, c.dist);
      const double pos_size = magnitude(c.pos, 3);
      for (int i = 0; i < 3; ++i) check_value("pos", i, ours[k].pos[i], c.pos[i], pos_size);
      // the narrow phase sets the normal and, for plane-capsule, the first tangent; the driver
      // completes the frame (compared in collision/driver.cpp)
      for (int i = 0; i < 6; ++i) {
        check_value("frame", i, ours[k].frame(i / 3, i % 3), c.frame[i], 1.0);
      }
    }
    ++cases_;
    contacts_ += n_mujoco;
    return n_mujoco;
  }

  int cases() const { return cases_; }
  int contacts() const { return contacts_; }
  double worst() const { return worst_; }

 private:
  MjModelPtr model_;
  MjDataPtr data_;
  int cases_ = 0, contacts_ = 0;
  double worst_ = 0;

  GeomShape place(int g, const Pose& p) {
    mjModel* m = model_.get();
    mjData* d = data_.get();
    Quat q = p.quat;
    mju_normalize4(q.data());
    mju_quat2Mat(d->geom_xmat + 9 * g, q.data());
    for (int i = 0; i < 3; ++i) {
      d->geom_xpos[3 * g + i] = p.pos[i];
      m->geom_size[3 * g + i] = p.size[i];
    }
    GeomShape s;
    s.type = static_cast<GeomType>(m->geom_type[g]);
    s.size = p.size;
    s.pos = p.pos;
    for (int i = 0; i < 9; ++i) s.mat(i / 3, i % 3) = d->geom_xmat[9 * g + i];
    return s;
  }

  void check_value(const char* field, int index, double ours, double reference, double size) {
    const double e = excess(ours, reference, size);
    worst_ = std::max(worst_, e);
    INFO(describe(field, index, ours, reference, size));
    CHECK(e <= 1.0);
  }
};

double uniform(std::mt19937_64& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

Quat random_rotation(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0, 1);
  Quat q(n(rng), n(rng), n(rng), n(rng));
  return q / q.norm();
}

Vec3 random_direction(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0, 1);
  const Vec3 v(n(rng), n(rng), n(rng));
  return v / v.norm();
}

/// Sizes a geom of this type uses (plane: drawn size only; sphere: radius; capsule and cylinder:
/// radius, half-length; ellipsoid and box: three semi-axes).
Vec3 random_size(GeomType type, std::mt19937_64& rng) {
  const Vec3 s(uniform(rng, 0.05, 0.5), uniform(rng, 0.05, 0.5), uniform(rng, 0.05, 0.5));
  switch (type) {
    case GeomType::kPlane: return Vec3(1, 1, 0.1);
    case GeomType::kSphere: return Vec3(s[0], 0, 0);
    case GeomType::kCapsule:
    case GeomType::kCylinder: return Vec3(s[0], s[1], 0);
    default: return s;
  }
}

/// A radius that encloses the geom (for placing the other one near it).
double reach(GeomType type, const Vec3& size) {
  switch (type) {
    case GeomType::kSphere: return size[0];
    case GeomType::kCapsule:
    case GeomType::kCylinder: return size[0] + size[1];
    default: return size.norm();
  }
}

struct PairKind {
  const char* g1;
  const char* g2;
};

}  // namespace

TEST_CASE("collision pairs: random poses near contact agree with MuJoCo's pair functions",
          "[diff][collision]") {
  REQUIRE(mj_version() == 222);
  PairBench bench;
  std::mt19937_64 rng(20260519);
  const std::vector<PairKind> kinds = {
      {"plane", "sphere"}, {"plane", "capsule"},  {"plane", "ellipsoid"}, {"plane", "cylinder"},
      {"plane", "box"},    {"sphere", "sphere2"}, {"sphere", "capsule"},  {"capsule", "capsule2"}};
  for (const PairKind& kind : kinds) {
    const int g1 = bench.geom(kind.g1), g2 = bench.geom(kind.g2);
    REQUIRE(g1 >= 0);
    REQUIRE(g2 >= 0);
    const GeomType t1 = bench.type(g1), t2 = bench.type(g2);

    int with_contacts = 0;
    for (int trial = 0; trial < 3000; ++trial) {
      Pose p1, p2;
      p1.size = random_size(t1, rng);
      p2.size = random_size(t2, rng);
      p1.quat = random_rotation(rng);
      p2.quat = random_rotation(rng);
      p1.pos = Vec3(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
      const double margin = trial % 3 == 0 ? 0.0 : uniform(rng, 0, 0.1);
      const double r2 = reach(t2, p2.size);
      if (t1 == GeomType::kPlane) {
        // the other geom's centre from deep below the plane to beyond its reach plus the margin
        Eigen::Matrix3d R;
        mju_quat2Mat(R.data(), p1.quat.data());  // column-major R holds R^T: row 2 is the normal
        const Vec3 normal = R.row(2).transpose();
        const Vec3 along = random_direction(rng);
        p2.pos = p1.pos + along - normal * normal.dot(along) +
                 normal * uniform(rng, -1.2 * r2, 1.2 * r2 + margin);
      } else {
        const double r1 = reach(t1, p1.size);
        p2.pos = p1.pos + random_direction(rng) * uniform(rng, 0, 1.2 * (r1 + r2) + margin);
      }
      if (bench.compare(g1, g2, p1, p2, margin, "random trial " + std::to_string(trial)) > 0) {
        ++with_contacts;
      }
    }
    INFO(kind.g1 << " - " << kind.g2);
    // the poses must reach the contact branches, not only the early returns
    CHECK(with_contacts > 300);
  }
  WARN("collision pairs (random): " << bench.cases() << " cases, " << bench.contacts()
                                    << " contacts, worst " << bench.worst() << " of the bound");
}

TEST_CASE("collision pairs: deliberate poses at MuJoCo's branch points agree",
          "[diff][collision]") {
  REQUIRE(mj_version() == 222);
  PairBench bench;
  const int plane = bench.geom("plane"), sphere = bench.geom("sphere"),
            sphere2 = bench.geom("sphere2"), capsule = bench.geom("capsule"),
            capsule2 = bench.geom("capsule2"), cylinder = bench.geom("cylinder"),
            ellipsoid = bench.geom("ellipsoid"), box = bench.geom("box");
  const Vec3 x(1, 0, 0), y(0, 1, 0), z(0, 0, 1);
  const Quat identity(1, 0, 0, 0);
  const double kTilt = 1e-9;

  // a tilted floor, so that the deliberate cases are not all axis-aligned
  for (const Quat& floor : {identity, axis_angle(Vec3(1, 2, 0), 0.3)}) {
    Eigen::Matrix3d R;
    mju_quat2Mat(R.data(), floor.data());
    const Vec3 normal = R.row(2).transpose();
    Pose p1;
    p1.quat = floor;
    p1.pos = Vec3(0.1, -0.2, 0.3);
    p1.size = Vec3(1, 1, 0.1);

    for (double margin : {0.0, 0.01}) {
      for (double tilt : {0.0, kTilt, -kTilt}) {
        // heights of the lowest point: resting exactly, within the margin, deep, just above it
        for (double height : {0.0, 0.005, -0.05, 0.0100001}) {
          const std::string what =
              "height " + std::to_string(height) + " tilt " + std::to_string(tilt);
          // box resting flat: four corners at the same depth
          Pose b;
          b.size = Vec3(0.1, 0.2, 0.3);
          b.quat = compose(floor, axis_angle(x + 0.5 * y, tilt));
          b.pos = p1.pos + normal * (b.size[2] + height);
          bench.compare(plane, box, p1, b, margin, "box flat, " + what);
          // box on an edge and on a corner
          b.quat = compose(floor, axis_angle(x, M_PI / 4 + tilt));
          b.pos = p1.pos + normal * (std::hypot(b.size[1], b.size[2]) *
                                         std::cos(M_PI / 4 - std::atan2(b.size[1], b.size[2])) +
                                     height);
          bench.compare(plane, box, p1, b, margin, "box on an edge, " + what);

          // capsule lying flat (both ends touch), and upright
          Pose c;
          c.size = Vec3(0.1, 0.2, 0);
          c.quat = compose(floor, axis_angle(y, M_PI / 2 + tilt));
          c.pos = p1.pos + normal * (c.size[0] + height);
          bench.compare(plane, capsule, p1, c, margin, "capsule flat, " + what);
          c.quat = compose(floor, axis_angle(y, tilt));
          c.pos = p1.pos + normal * (c.size[0] + c.size[1] + height);
          bench.compare(plane, capsule, p1, c, margin, "capsule upright, " + what);

          // cylinder on its disc (the disc-parallel branch when untilted), and on its side
          Pose k;
          k.size = Vec3(0.1, 0.2, 0);
          k.quat = compose(floor, axis_angle(x, tilt));
          k.pos = p1.pos + normal * (k.size[1] + height);
          bench.compare(plane, cylinder, p1, k, margin, "cylinder on its disc, " + what);
          k.quat = compose(floor, axis_angle(x, M_PI + tilt));
          bench.compare(plane, cylinder, p1, k, margin, "cylinder upside down, " + what);
          k.quat = compose(floor, axis_angle(x, M_PI / 2 + tilt));
          k.pos = p1.pos + normal * (k.size[0] + height);
          bench.compare(plane, cylinder, p1, k, margin, "cylinder on its side, " + what);

          // sphere and ellipsoid resting
          Pose s;
          s.size = Vec3(0.1, 0, 0);
          s.pos = p1.pos + normal * (s.size[0] + height);
          bench.compare(plane, sphere, p1, s, margin, "sphere, " + what);
          Pose e;
          e.size = Vec3(0.1, 0.2, 0.3);
          e.quat = compose(floor, axis_angle(x, tilt));
          e.pos = p1.pos + normal * (e.size[2] + height);
          bench.compare(plane, ellipsoid, p1, e, margin, "ellipsoid, " + what);
        }
      }
    }
  }

  for (double margin : {0.0, 0.01}) {
    for (double tilt : {0.0, kTilt, -kTilt}) {
      for (double gap : {-0.3, -0.05, 0.0, 0.005, 0.0100001}) {
        const std::string what = "gap " + std::to_string(gap) + " tilt " + std::to_string(tilt);
        Pose a, b;
        a.size = b.size = Vec3(0.1, 0.2, 0);
        a.pos = Vec3(0.3, -0.1, 0.2);
        // parallel capsules side by side (two contacts), offset along the axis, and end to end
        b.quat = axis_angle(x, tilt);
        b.pos = a.pos + y * (0.2 + gap);
        bench.compare(capsule, capsule2, a, b, margin, "parallel capsules, " + what);
        b.pos = a.pos + y * (0.2 + gap) + z * 0.3;
        bench.compare(capsule, capsule2, a, b, margin, "parallel offset capsules, " + what);
        b.pos = a.pos + z * (0.6 + gap);
        bench.compare(capsule, capsule2, a, b, margin, "capsules end to end, " + what);
        // crossed capsules
        b.quat = axis_angle(x, M_PI / 2 + tilt);
        b.pos = a.pos + y * (0.2 + gap);
        bench.compare(capsule, capsule2, a, b, margin, "crossed capsules, " + what);

        // spheres: apart, and concentric (the normal from the z axes' cross product, or x)
        Pose s1, s2;
        s1.size = Vec3(0.1, 0, 0);
        s2.size = Vec3(0.15, 0, 0);
        s1.pos = Vec3(-0.2, 0.1, 0.4);
        s2.pos = s1.pos + Vec3(1, 1, 1).normalized() * (0.25 + gap);
        bench.compare(sphere, sphere2, s1, s2, margin, "spheres, " + what);
        s2.pos = s1.pos;
        s2.quat = axis_angle(y, tilt);
        bench.compare(sphere, sphere2, s1, s2, margin, "concentric spheres, " + what);
        s2.quat = axis_angle(y, 0.7);
        bench.compare(sphere, sphere2, s1, s2, margin, "concentric turned spheres, " + what);

        // sphere against a capsule's side, its end, and on its axis
        Pose c;
        c.size = Vec3(0.1, 0.2, 0);
        c.quat = axis_angle(x, tilt);
        c.pos = s1.pos + y * (0.2 + gap);
        bench.compare(sphere, capsule, s1, c, margin, "sphere at a capsule's side, " + what);
        c.pos = s1.pos + z * (0.4 + gap);
        bench.compare(sphere, capsule, s1, c, margin, "sphere at a capsule's end, " + what);
        c.pos = s1.pos + z * 0.1;
        bench.compare(sphere, capsule, s1, c, margin, "sphere on a capsule's axis, " + what);
      }
    }
  }
  WARN("collision pairs (deliberate): " << bench.cases() << " cases, " << bench.contacts()
                                        << " contacts, worst " << bench.worst() << " of the bound");
  CHECK(bench.contacts() > 500);
}

}  // namespace lever::test
