// The narrow phase of the pairs with a box (engine/src/collision/box.cpp) against MuJoCo 2.2.2's
// own functions, mjCOLLISIONFUNC[type1][type2], called on the same shapes: the number of contacts
// and their order exactly; dist, pos and the frame's first two rows (normal, zeros) within the
// agreement bound, value by value. Thousands of seeded random poses per pair, poses snapped to
// the boxes' symmetries (exact ties), and deliberate ones: resting flat, on an edge, corner down,
// tilted 1e-9 away from ties, face to face turned 45 degrees, a sphere at a corner, an edge, a
// face and inside, a capsule parallel to a face, at 30 and 60 degrees, within the margin.
// Last, MuJoCo's whole collision stage on a box-box scene shows where repeated contacts go.
#include <mujoco/mujoco.h>

#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <sstream>
#include <string>

#include <lever/harness/from_mujoco.hpp>
#include <lever/harness/tolerance.hpp>

#include "collision/narrow_phase.hpp"

namespace lever::test {

namespace {

// geom ids of the model below
constexpr int kSphere = 0, kCapsule = 1, kBox1 = 2, kBox2 = 3;

// The geoms only carry types: each comparison writes sizes and poses into mjModel/mjData.
constexpr const char* kGeomsXml = R"(
<mujoco>
  <worldbody>
    <geom type="sphere" size="0.1"/>
    <geom type="capsule" size="0.1 0.2"/>
    <geom type="box" size="0.1 0.2 0.3"/>
    <geom type="box" size="0.3 0.2 0.1"/>
  </worldbody>
</mujoco>)";

using Vec = Eigen::Vector3d;

GeomShape shape(GeomType type, const Vec& size, const Vec& pos, const Mat3& mat) {
  GeomShape g;
  g.type = type;
  g.size = size;
  g.pos = pos;
  g.mat = mat;
  return g;
}

Mat3 rotation(const Vec& axis, double angle) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

Mat3 random_rotation_matrix(std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  Eigen::Quaterniond q(normal(rng), normal(rng), normal(rng), normal(rng));
  q.normalize();
  return q.toRotationMatrix();
}

double uniform_in(std::mt19937_64& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

/// A point of the cube [-1, 1]^3.
Vec random_point(std::mt19937_64& rng) {
  return Vec(uniform_in(rng, -1, 1), uniform_in(rng, -1, 1), uniform_in(rng, -1, 1));
}

Vec random_unit_vector(std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  return Vec(normal(rng), normal(rng), normal(rng)).normalized();
}

/// One of the 24 rotations that map a box onto its axes (exact 0 and +-1 entries).
Mat3 random_axis_permutation(std::mt19937_64& rng) {
  std::array<int, 3> perm = {0, 1, 2};
  std::shuffle(perm.begin(), perm.end(), rng);
  Mat3 m = Mat3::Zero();
  for (int i = 0; i < 3; ++i) m(i, perm[i]) = std::bernoulli_distribution(0.5)(rng) ? 1 : -1;
  if (m.determinant() < 0) m.row(2) *= -1;
  return m;
}

std::string describe_shape(const GeomShape& g) {
  std::ostringstream s;
  s.precision(17);
  s << "size " << g.size.transpose() << " pos " << g.pos.transpose() << " mat "
    << Eigen::Map<const Eigen::Matrix<double, 1, 9>>(g.mat.data());
  return s.str();
}

/// What a batch of comparisons saw, for its assertions and its summary line.
struct BoxTally {
  long calls = 0, with_contacts = 0, contacts = 0;
  double worst = 0;  ///< largest |lever - mujoco| / bound over every value
  std::array<long, kMaxPairContacts + 1> by_count{};  ///< calls by MuJoCo's contact count
  int most_after_driver = 0;  ///< box-box: most contacts left after the driver's removal
};

class MujocoGeoms {
 public:
  MujocoGeoms() : model_(mujoco_load_string(kGeomsXml)), data_(mujoco_data(model_.get())) {}

  /// MuJoCo's narrow-phase function for these two geoms, as its driver calls it.
  int collide(int id1, const GeomShape& g1, int id2, const GeomShape& g2, double margin,
              mjContact* con) {
    put(id1, g1);
    put(id2, g2);
    mjModel* m = model_.get();
    const mjfCollision function = mjCOLLISIONFUNC[m->geom_type[id1]][m->geom_type[id2]];
    REQUIRE(function != nullptr);
    return function(m, data_.get(), con, id1, id2, margin);
  }

 private:
  void put(int id, const GeomShape& g) {
    for (int k = 0; k < 3; ++k) {
      model_->geom_size[3 * id + k] = g.size[k];
      data_->geom_xpos[3 * id + k] = g.pos[k];
    }
    for (int k = 0; k < 9; ++k) data_->geom_xmat[9 * id + k] = g.mat.data()[k];  // row-major both
  }
  MjModelPtr model_;
  MjDataPtr data_;
};

using PairFunction = int (*)(const GeomShape&, const GeomShape&, double, Contact*);

/// One comparison: lever's function against MuJoCo's on the same two shapes. Returns lever's
/// contact count; a disagreement fails with both shapes printed to rerun it.
int compare(MujocoGeoms& mujoco, int id1, const GeomShape& g1, int id2, const GeomShape& g2,
            double margin, PairFunction ours, BoxTally& tally, const std::string& what) {
  std::array<mjContact, mjMAXCONPAIR> theirs{};
  std::array<Contact, kMaxPairContacts> mine{};
  const int n_mujoco = mujoco.collide(id1, g1, id2, g2, margin, theirs.data());
  const int n_lever = ours(g1, g2, margin, mine.data());
  ++tally.calls;
  std::ostringstream where;
  where.precision(17);
  where << what << "; margin " << margin << "\n  geom1 " << describe_shape(g1) << "\n  geom2 "
        << describe_shape(g2);
  INFO(where.str());
  if (n_mujoco != n_lever) {
    FAIL_CHECK("contact count: lever " << n_lever << " vs mujoco " << n_mujoco);
    return n_lever;
  }
  if (n_mujoco > 0) ++tally.with_contacts;
  tally.contacts += n_mujoco;
  ++tally.by_count[std::min(n_mujoco, kMaxPairContacts)];

  double worst = 0;
  std::string worst_what;
  const auto check = [&](const std::string& name, double lever_value, double mujoco_value) {
    const double e = excess(lever_value, mujoco_value);
    if (e > worst) {
      worst = e;
      std::ostringstream line;
      line.precision(17);
      line << name << ": lever " << lever_value << " vs mujoco " << mujoco_value << " (" << e
           << " of the bound)";
      worst_what = line.str();
    }
  };
  for (int i = 0; i < n_mujoco; ++i) {
    const std::string c = "contact " + std::to_string(i) + " ";
    check(c + "dist", mine[i].dist, theirs[i].dist);
    for (int k = 0; k < 3; ++k) {
      check(c + "pos[" + std::to_string(k) + "]", mine[i].pos[k], theirs[i].pos[k]);
      check(c + "normal[" + std::to_string(k) + "]", mine[i].frame(0, k), theirs[i].frame[k]);
      check(c + "frame[" + std::to_string(3 + k) + "]", mine[i].frame(1, k),
            theirs[i].frame[3 + k]);
    }
  }
  tally.worst = std::max(tally.worst, worst);
  if (worst > 1) FAIL_CHECK(worst_what);
  return n_lever;
}

std::string summary(const std::string& pair, const BoxTally& t) {
  std::ostringstream s;
  s << pair << ": " << t.calls << " poses, " << t.with_contacts << " with contacts, " << t.contacts
    << " contacts; worst " << t.worst << " of the bound; poses by contact count:";
  for (int n = 0; n <= kMaxPairContacts; ++n) {
    if (t.by_count[n] > 0) s << " " << n << ":" << t.by_count[n];
  }
  return s.str();
}

// ---- shapes ----------------------------------------------------------------------------------

Vec random_box_size(std::mt19937_64& rng) {
  return Vec(uniform_in(rng, 0.05, 0.5), uniform_in(rng, 0.05, 0.5), uniform_in(rng, 0.05, 0.5));
}

double random_margin(std::mt19937_64& rng) {
  return std::bernoulli_distribution(0.5)(rng) ? 0.0 : uniform_in(rng, 0.0, 0.1);
}

/// A centre for geom 2 near geom 1: within the sum of their bounding radii (plus the margin).
Vec near(const Vec& center1, double reach, std::mt19937_64& rng) {
  return center1 + random_unit_vector(rng) * uniform_in(rng, 0.0, reach);
}

}  // namespace

TEST_CASE("diff: sphere-box contacts equal MuJoCo's", "[diff][collision]") {
  REQUIRE(mj_version() == 222);
  MujocoGeoms mujoco;
  BoxTally tally;
  std::mt19937_64 rng(19001);
  const auto sphere_at = [](double r, const Vec& p) {
    return shape(GeomType::kSphere, Vec(r, 0, 0), p, Mat3::Identity());
  };

  SECTION("random poses") {
    for (int i = 0; i < 5000; ++i) {
      const GeomShape box = shape(GeomType::kBox, random_box_size(rng), random_point(rng),
                                  random_rotation_matrix(rng));
      const double r = uniform_in(rng, 0.02, 0.4), margin = random_margin(rng);
      // a quarter of the centres inside the box
      const Vec center = std::bernoulli_distribution(0.25)(rng)
                             ? Vec(box.pos + box.mat * box.size.cwiseProduct(random_point(rng)))
                             : near(box.pos, box.size.norm() + r + margin, rng);
      compare(mujoco, kSphere, sphere_at(r, center), kBox1, box, margin, detail::collide_sphere_box,
              tally, "random pose " + std::to_string(i));
    }
    INFO(summary("sphere-box, random", tally));
    CHECK(tally.worst <= 1);
    CHECK(tally.with_contacts > tally.calls / 4);
    CHECK(tally.by_count[0] > tally.calls / 10);
    SUCCEED(summary("sphere-box, random", tally));
  }

  SECTION("deliberate poses: corner, edge, face, inside, margin") {
    const Vec size(0.1, 0.2, 0.3);
    const Mat3 turn = rotation(Vec(1, 2, 3), 0.7);
    const Vec origin(0.3, -0.2, 0.5);
    const GeomShape box = shape(GeomType::kBox, size, origin, turn);
    const double r = 0.05;
    const auto at = [&](const Vec& local) { return Vec(origin + turn * local); };
    struct Case {
      const char* name;
      Vec local;  // sphere centre in the box's frame
      double margin;
      int expected;
    };
    const Case cases[] = {
        {"at a corner, penetrating", Vec(0.11, 0.21, 0.31), 0, 1},
        {"at a corner, exactly touching", size + Vec::Constant(r / std::sqrt(3.0)), 0, 1},
        {"at an edge", Vec(0.13, 0.23, 0.0), 0, 1},
        {"on a face", Vec(0.0, 0.0, 0.34), 0, 1},
        {"on a face, within the margin", Vec(0.0, 0.0, 0.36), 0.02, 1},
        {"on a face, beyond the margin", Vec(0.0, 0.0, 0.36), 0.005, 0},
        {"inside, nearest +z", Vec(0.0, 0.0, 0.25), 0, 1},
        {"inside, nearest -x", Vec(-0.07, 0.0, 0.0), 0, 1},
        {"inside, at the centre (tie of the x faces)", Vec(0, 0, 0), 0, 1},
        {"inside, equally near +x and +y", Vec(0.05, 0.15, 0.0), 0, 1},
        {"on the surface exactly", Vec(0.1, 0.0, 0.0), 0, 1},
        {"a corner just beyond reach", Vec(0.14, 0.24, 0.34), 0, 0},
    };
    for (const Case& c : cases) {
      INFO(c.name);
      const int n = compare(mujoco, kSphere, sphere_at(r, at(c.local)), kBox1, box, c.margin,
                            detail::collide_sphere_box, tally, c.name);
      CHECK(n == c.expected);
    }
    CHECK(tally.worst <= 1);
  }
}

TEST_CASE("diff: capsule-box contacts equal MuJoCo's", "[diff][collision]") {
  REQUIRE(mj_version() == 222);
  MujocoGeoms mujoco;
  BoxTally tally;
  std::mt19937_64 rng(19002);

  SECTION("random poses") {
    for (int i = 0; i < 6000; ++i) {
      const GeomShape box = shape(GeomType::kBox, random_box_size(rng), random_point(rng),
                                  random_rotation_matrix(rng));
      const Vec size(uniform_in(rng, 0.02, 0.3), uniform_in(rng, 0.05, 0.6), 0);
      const double margin = random_margin(rng);
      // a third of the capsules snapped to the box's axes (exact ties of the orientation tests)
      const Mat3 mat = std::bernoulli_distribution(1.0 / 3)(rng)
                           ? Mat3(box.mat * random_axis_permutation(rng))
                           : random_rotation_matrix(rng);
      const Vec center = near(box.pos, box.size.norm() + size[0] + size[1] + margin, rng);
      compare(mujoco, kCapsule, shape(GeomType::kCapsule, size, center, mat), kBox1, box, margin,
              detail::collide_capsule_box, tally, "random pose " + std::to_string(i));
    }
    INFO(summary("capsule-box, random", tally));
    CHECK(tally.worst <= 1);
    CHECK(tally.by_count[1] > 100);
    CHECK(tally.by_count[2] > 100);
    SUCCEED(summary("capsule-box, random", tally));
  }

  SECTION("deliberate poses: parallel, 30 and 60 degrees, edges, margin") {
    const Vec size(0.2, 0.15, 0.1);  // box: top face z = +0.1
    const Mat3 turn = rotation(Vec(-1, 0.5, 2), 0.4);
    const Vec origin(-0.1, 0.4, 0.2);
    const GeomShape box = shape(GeomType::kBox, size, origin, turn);
    const double r = 0.03, half = 0.1;
    // a capsule in the box's frame: centre and its axis's direction (local z of the capsule)
    const auto capsule = [&](const Vec& local_center, const Mat3& local_mat) {
      return shape(GeomType::kCapsule, Vec(r, half, 0), origin + turn * local_center,
                   turn * local_mat);
    };
    const Mat3 lying_along_x = rotation(Vec::UnitY(), M_PI / 2);  // capsule z -> box x
    struct Case {
      std::string name;
      GeomShape g;
      double margin;
      int expected;  // -1: not asserted beyond MuJoCo's count
    };
    std::vector<Case> cases;
    cases.push_back({"parallel to the top face, penetrating",
                     capsule(Vec(0, 0, 0.1 + r - 0.005), lying_along_x), 0, 2});
    cases.push_back({"parallel to the top face, within the margin",
                     capsule(Vec(0, 0, 0.1 + r + 0.005), lying_along_x), 0.01, 2});
    cases.push_back({"parallel to the top face, beyond the margin",
                     capsule(Vec(0, 0, 0.1 + r + 0.005), lying_along_x), 0.001, 0});
    cases.push_back({"parallel, tilted 1e-9",
                     capsule(Vec(0, 0, 0.1 + r - 0.005), rotation(Vec::UnitY(), M_PI / 2 + 1e-9)),
                     0, 2});
    cases.push_back({"along a top edge", capsule(Vec(0, 0.15, 0.1), lying_along_x), 0, -1});
    cases.push_back({"end-on onto the top face",
                     capsule(Vec(0.05, 0, 0.1 + half + r - 0.01), Mat3::Identity()), 0, 1});
    cases.push_back({"inside the box", capsule(Vec(0, 0, 0), lying_along_x), 0, -1});
    for (const double degrees : {30.0, 60.0, 44.0, 46.0}) {
      // tilted from the top face about the box's y axis, the lower end touching the face
      const double a = degrees * M_PI / 180;
      const Mat3 tilt = rotation(Vec::UnitY(), M_PI / 2 - a);
      const Vec lower_end(-half * std::cos(a), 0, 0.1 + r - 0.002);
      cases.push_back({"end on the face, " + std::to_string(degrees) + " degrees",
                       capsule(lower_end + Vec(half * std::cos(a), 0, half * std::sin(a)), tilt), 0,
                       -1});
      // the same tilt across a top edge (the x = +0.2 edge), touching it near its middle
      const Mat3 across = rotation(Vec::UnitZ(), 0.3) * tilt;
      cases.push_back(
          {"over the +x top edge, " + std::to_string(degrees) + " degrees",
           capsule(Vec(0.2, 0, 0.1 + r + 0.001) + across * Vec(0, 0, 0.5 * half), across), 0.005,
           -1});
      // near a corner, pointing along the box's x edge at that angle
      cases.push_back({"at the (+x, +y, +z) corner, " + std::to_string(degrees) + " degrees",
                       capsule(Vec(0.2, 0.15, 0.1 + r - 0.003) +
                                   rotation(Vec::UnitY(), M_PI / 2 + a) * Vec(0, 0, half),
                               rotation(Vec::UnitY(), M_PI / 2 + a)),
                       0.01, -1});
    }
    cases.push_back({"crossing a top edge (X)",
                     capsule(Vec(0.2, 0, 0.1 + r - 0.004),
                             rotation(Vec::UnitX(), M_PI / 2) * rotation(Vec::UnitY(), 0.2)),
                     0, -1});
    cases.push_back({"T onto a top edge",
                     capsule(Vec(0.2 + 0.02, 0, 0.1 + half + r - 0.004), Mat3::Identity()), 0, -1});
    // MuJoCo compares squared distances with a bound that is a length: a capsule this thick
    // reaches the box from where its segment finds nothing, and gets no contact
    cases.push_back({"thick capsule, segment 4.9 above the face (MuJoCo's bound)",
                     shape(GeomType::kCapsule, Vec(5, half, 0),
                           origin + turn * Vec(0, 0, 0.1 + 4.9), turn * lying_along_x),
                     0, 0});
    cases.push_back(
        {"segment of length 0 at a corner",
         shape(GeomType::kCapsule, Vec(r, 0, 0), origin + turn * Vec(0.21, 0.16, 0.11), turn), 0,
         0});
    int twos = 0;
    for (const Case& c : cases) {
      INFO(c.name);
      const int n = compare(mujoco, kCapsule, c.g, kBox1, box, c.margin,
                            detail::collide_capsule_box, tally, c.name);
      if (c.expected >= 0) CHECK(n == c.expected);
      twos += n == 2;
    }
    CHECK(twos >= 4);
    CHECK(tally.worst <= 1);
  }
}

TEST_CASE("diff: box-box contacts equal MuJoCo's", "[diff][collision]") {
  REQUIRE(mj_version() == 222);
  MujocoGeoms mujoco;
  BoxTally tally;
  std::mt19937_64 rng(19003);
  const auto box = [](const Vec& size, const Vec& pos, const Mat3& mat) {
    return shape(GeomType::kBox, size, pos, mat);
  };
  // runs one comparison and records how many contacts the driver's removal would leave
  const auto run = [&](const GeomShape& b1, const GeomShape& b2, double margin,
                       const std::string& what) {
    const int n =
        compare(mujoco, kBox1, b1, kBox2, b2, margin, detail::collide_box_box, tally, what);
    std::array<Contact, kMaxPairContacts> contacts;
    detail::collide_box_box(b1, b2, margin, contacts.data());
    const int kept = detail::remove_repeated_positions(contacts.data(), n);
    tally.most_after_driver = std::max(tally.most_after_driver, kept);
    return kept;
  };

  SECTION("random poses") {
    for (int i = 0; i < 8000; ++i) {
      const GeomShape b1 =
          box(random_box_size(rng), random_point(rng), random_rotation_matrix(rng));
      const Vec size2 = random_box_size(rng);
      const double margin = random_margin(rng);
      const GeomShape b2 = box(size2, near(b1.pos, b1.size.norm() + size2.norm() + margin, rng),
                               random_rotation_matrix(rng));
      run(b1, b2, margin, "random pose " + std::to_string(i));
    }
    INFO(summary("box-box, random", tally));
    CHECK(tally.worst <= 1);
    CHECK(tally.with_contacts > tally.calls / 4);
    long many = 0;
    for (int n = 3; n <= kMaxPairContacts; ++n) many += tally.by_count[n];
    CHECK(many > 100);
    SUCCEED(summary("box-box, random", tally) +
            "; most after the driver: " + std::to_string(tally.most_after_driver));
  }

  SECTION("random stacks: box 2 on box 1, turned about the normal, tilted a little") {
    // the poses that clip a whole face: up to 8 polygon corners plus the lowest corner
    for (int i = 0; i < 4000; ++i) {
      const Mat3 mat1 = random_rotation_matrix(rng);
      const Vec size1 = random_box_size(rng);
      Vec size2 = random_box_size(rng);
      if (i % 2) size2.head<2>() = size1.head<2>();  // equal faces
      const double tilt = i % 3 == 0 ? 0.0 : uniform_in(rng, -0.05, 0.05);
      const Mat3 relative = rotation(Vec::UnitZ(), uniform_in(rng, 0, 2 * M_PI)) *
                            rotation(Vec(uniform_in(rng, -1, 1), uniform_in(rng, -1, 1), 0), tilt);
      const Vec local(uniform_in(rng, -0.2, 0.2), uniform_in(rng, -0.2, 0.2),
                      size1[2] + size2[2] + uniform_in(rng, -0.02, 0.01));
      const double margin = i % 4 == 0 ? 0.02 : 0.0;
      const Vec pos1 = random_point(rng);
      run(box(size1, pos1, mat1), box(size2, pos1 + mat1 * local, mat1 * relative), margin,
          "stack " + std::to_string(i));
    }
    INFO(summary("box-box, stacks", tally));
    CHECK(tally.worst <= 1);
    CHECK(tally.by_count[8] > 0);
    CHECK(tally.by_count[9] > 0);
    SUCCEED(summary("box-box, stacks", tally) +
            "; most after the driver: " + std::to_string(tally.most_after_driver));
  }

  SECTION("random poses snapped to the boxes' axes, exact and tilted 1e-9") {
    // box 2 resting on or pressed into box 1 with aligned (or 1e-9-tilted) axes: the separating
    // axis tests tie, edges coincide and clipped points repeat
    for (int i = 0; i < 4000; ++i) {
      const Mat3 mat1 = std::bernoulli_distribution(0.5)(rng) ? Mat3(Mat3::Identity())
                                                              : random_rotation_matrix(rng);
      // sizes from a small set, so that faces and edges line up exactly
      const auto pick = [&] { return 0.05 * std::uniform_int_distribution<int>(1, 6)(rng); };
      const Vec size1(pick(), pick(), pick()), size2(pick(), pick(), pick());
      Mat3 relative = random_axis_permutation(rng);
      const int tilt = std::uniform_int_distribution<int>(0, 2)(rng);
      if (tilt > 0)
        relative = rotation(random_unit_vector(rng), tilt == 1 ? 1e-9 : 1e-6) * relative;
      // box 2's centre: above box 1's +z face, shifted in x and y by multiples of 0.05
      const Vec extent2 = (relative.cwiseAbs() * size2);
      const auto step = [&] { return 0.05 * std::uniform_int_distribution<int>(-6, 6)(rng); };
      const double depth = std::uniform_int_distribution<int>(0, 3)(rng) * 0.01 - 0.005;
      const Vec local(step(), step(), size1[2] + extent2[2] - depth);
      const double margin = std::bernoulli_distribution(0.5)(rng) ? 0.0 : 0.01;
      const Vec pos1 = random_point(rng);
      run(box(size1, pos1, mat1), box(size2, pos1 + mat1 * local, mat1 * relative), margin,
          "snapped pose " + std::to_string(i));
    }
    INFO(summary("box-box, snapped", tally));
    CHECK(tally.worst <= 1);
    SUCCEED(summary("box-box, snapped", tally) +
            "; most after the driver: " + std::to_string(tally.most_after_driver));
  }

  SECTION("deliberate poses") {
    const Vec table(0.5, 0.4, 0.05), cube(0.1, 0.1, 0.1);
    const Mat3 world = rotation(Vec(0.3, -1, 0.2), 0.5);  // the whole scene turned
    const Vec origin(0.2, 0.1, -0.3);
    const auto on_table = [&](const Vec& local, const Mat3& local_mat) {
      return box(cube, origin + world * local, world * local_mat);
    };
    const GeomShape base = box(table, origin, world);
    const double top = table[2] + cube[2];  // centre height of a cube resting flat
    const double edge_height = table[2] + cube[2] * std::sqrt(2.0);
    const double corner_height = table[2] + cube[2] * std::sqrt(3.0);
    // the cube's diagonal along z: a rotation taking (1, 1, 1)/sqrt(3) to +z
    const Mat3 corner_down =
        Eigen::Quaterniond::FromTwoVectors(Vec(1, 1, 1).normalized(), Vec::UnitZ())
            .toRotationMatrix();
    const Mat3 on_edge = rotation(Vec::UnitX(), M_PI / 4);
    const Mat3 turned45 = rotation(Vec::UnitZ(), M_PI / 4);
    struct Case {
      std::string name;
      GeomShape b1, b2;
      double margin;
      int expected;  // contacts left after the driver's removal; -1: not asserted
    };
    std::vector<Case> cases = {
        {"resting flat, penetrating 1e-3", base, on_table(Vec(0, 0, top - 1e-3), Mat3::Identity()),
         0, 4},
        // dist 0 up to rounding: whether the corners pass `z <= margin` is the last bit's call
        {"resting flat, touching", base, on_table(Vec(0, 0, top), Mat3::Identity()), 0, -1},
        {"resting flat, within the margin", base,
         on_table(Vec(0, 0, top + 0.004), Mat3::Identity()), 0.005, 4},
        {"resting flat, beyond the margin", base,
         on_table(Vec(0, 0, top + 0.006), Mat3::Identity()), 0.005, 0},
        {"resting flat, turned 45 degrees", base, on_table(Vec(0, 0, top - 1e-3), turned45), 0, 4},
        {"resting flat over the table's corner", base,
         on_table(Vec(0.45, 0.35, top - 1e-3), Mat3::Identity()), 0, 4},
        {"on an edge", base, on_table(Vec(0, 0, edge_height - 1e-3), on_edge), 0, -1},
        {"on an edge, tilted +1e-9", base,
         on_table(Vec(0, 0, edge_height - 1e-3), rotation(Vec::UnitX(), M_PI / 4 + 1e-9)), 0, -1},
        {"on an edge, tilted -1e-9", base,
         on_table(Vec(0, 0, edge_height - 1e-3), rotation(Vec::UnitX(), M_PI / 4 - 1e-9)), 0, -1},
        {"corner down", base, on_table(Vec(0, 0, corner_height - 1e-3), corner_down), 0, 1},
        {"corner down, within the margin", base,
         on_table(Vec(0, 0, corner_height + 1e-3), corner_down), 0.002, 1},
    };
    for (const Vec& axis :
         std::array<Vec, 4>{Vec::UnitX(), Vec::UnitY(), Vec::UnitZ(), Vec(1, 1, 0)}) {
      for (const double tilt : {1e-9, -1e-9}) {
        cases.push_back({"resting flat, tilted " + std::to_string(tilt) + " about (" +
                             std::to_string(axis[0]) + ", " + std::to_string(axis[1]) + ", " +
                             std::to_string(axis[2]) + ")",
                         base, on_table(Vec(0.1, -0.05, top - 1e-3), rotation(axis, tilt)), 0, 4});
      }
    }
    // two equal cubes: face to face (exact ties everywhere), and turned 45 degrees (an octagon)
    const GeomShape lower = box(cube, origin, world);
    const auto upper = [&](const Mat3& m, double gap) {
      return box(cube, origin + world * Vec(0, 0, 2 * cube[2] + gap), world * m);
    };
    // every corner is found twice, by two clipped edges, and the driver drops the bitwise equal
    // repeats only: how many remain is rounding's call
    cases.push_back({"equal cubes face to face", lower, upper(Mat3::Identity(), -1e-3), 0, -1});
    cases.push_back({"equal cubes face to face, tilted 1e-9", lower,
                     upper(rotation(Vec(1, 2, 0), 1e-9), -1e-3), 0, -1});
    // penetrating: box 1's face, the octagon's 8 corners and box 2's lowest corner, which MuJoCo
    // keeps although it lies outside the face: 9, more than kMaxPairContacts
    cases.push_back({"equal cubes, turned 45 degrees", lower, upper(turned45, -1e-3), 0, 9});
    // apart within the margin: the penetration is negative, so the tie factor (1 - 1e-12) lets an
    // edge axis tie the face and win; the edge path gives the octagon alone
    cases.push_back({"equal cubes, turned 45 degrees, within the margin", lower,
                     upper(turned45, 1e-3), 0.002, 8});
    cases.push_back({"equal cubes, turned 45 degrees + 1e-9", lower,
                     upper(rotation(Vec::UnitZ(), M_PI / 4 + 1e-9), -1e-3), 0, 9});
    // edge across edge: both cubes stand on an edge, the edges crossed at right angles
    const Mat3 edge_x = rotation(Vec::UnitX(), M_PI / 4), edge_y = rotation(Vec::UnitY(), M_PI / 4);
    const double reach = cube[2] * std::sqrt(2.0);
    for (const double tilt : {0.0, 1e-9, 0.05}) {
      cases.push_back({"edge across edge, tilt " + std::to_string(tilt),
                       box(cube, origin, world * edge_x),
                       box(cube, origin + world * Vec(0.01, -0.01, 2 * reach - 1e-3),
                           world * rotation(Vec::UnitZ(), tilt) * edge_y),
                       0, -1});
    }
    cases.push_back({"edge across edge, within the margin", box(cube, origin, world * edge_x),
                     box(cube, origin + world * Vec(0, 0, 2 * reach + 1e-3), world * edge_y), 0.002,
                     -1});
    // the same scenes with the boxes swapped (box 2's face chosen)
    const std::size_t originals = cases.size();
    for (std::size_t i = 0; i < originals; ++i) {
      Case swapped = cases[i];
      std::swap(swapped.b1, swapped.b2);
      swapped.name += ", boxes swapped";
      swapped.expected = -1;  // box 1's face wins exact ties, so a swap can change the path
      cases.push_back(swapped);
    }
    for (const Case& c : cases) {
      INFO(c.name);
      const int kept = run(c.b1, c.b2, c.margin, c.name);
      if (c.expected >= 0) CHECK(kept == c.expected);
    }
    CHECK(tally.worst <= 1);
    SUCCEED(summary("box-box, deliberate", tally) +
            "; most after the driver: " + std::to_string(tally.most_after_driver));
  }
}

// The xArm7's finger pads (Menagerie's ufactory_xarm7: boxes 0.015 x 0.002 x 0.0095, centred on
// the fingers' hinge axis x, the left finger's pads facing the right finger's). Both fingers turn
// about parallel x axes, so at every grip the pads' +-x faces lie in the same two planes: their
// corners sit exactly on the reference face's edges, and whether a corner counts (strictly
// inside) is the last bit's call. Face to face the count after the driver's removal is 2, 3 or
// 4 depending on those bits. On the same poses lever's answer is MuJoCo's, bit for bit in the
// count and within the bound in every value: poses with the pads parallel, tilted 1e-9 and 1e-3
// about the shared axis, pressed up to 0.6 mm and apart within the margin, pad 1 against pad 1
// (equal heights) and against pad 2 (overlapping 1 mm), the hand turned anywhere.
TEST_CASE("diff: the xArm7's finger pads face to face: contacts equal MuJoCo's",
          "[diff][collision]") {
  REQUIRE(mj_version() == 222);
  MujocoGeoms mujoco;
  BoxTally tally;
  std::mt19937_64 rng(19005);
  const Vec pad(0.015, 0.002, 0.0095);
  std::array<int, kMaxPairContacts + 1> kept_by_count{};
  for (int i = 0; i < 3000; ++i) {
    // the hand anywhere; the fingers' common closing angle about x, and each pad's own tilt
    const Mat3 hand = i % 4 == 0 ? Mat3(Mat3::Identity()) : random_rotation_matrix(rng);
    const Vec origin = random_point(rng);
    const double grip = uniform_in(rng, -0.2, 0.2);
    const int tilt_kind = i % 3;
    const double tilt =
        tilt_kind == 0 ? 0.0 : (tilt_kind == 1 ? 1e-9 : 1e-3) * uniform_in(rng, -1, 1);
    const Mat3 left = hand * rotation(Vec::UnitX(), grip);
    const Mat3 right = hand * rotation(Vec::UnitX(), grip + tilt);
    // face to face along the pads' y: centre distance 2 * 0.002 less the press
    const double press = uniform_in(rng, -0.0002, 0.0006);
    const double dz = std::array<double, 3>{0.0, 0.018, -0.018}[i % 3 == 0 ? 0 : (i / 3) % 3];
    const Vec left_pos = origin;
    const Vec right_pos = origin + left * Vec(0, 2 * pad[1] - press, dz);
    const double margin = i % 5 == 0 ? 0.0005 : 0.0;
    const GeomShape b1 = shape(GeomType::kBox, pad, left_pos, left);
    const GeomShape b2 = shape(GeomType::kBox, pad, right_pos, right);
    const int n = compare(mujoco, kBox1, b1, kBox2, b2, margin, detail::collide_box_box, tally,
                          "pads " + std::to_string(i));
    std::array<Contact, kMaxPairContacts> contacts;
    detail::collide_box_box(b1, b2, margin, contacts.data());
    ++kept_by_count[detail::remove_repeated_positions(contacts.data(), n)];
  }
  std::ostringstream kept;
  for (int n = 0; n <= kMaxPairContacts; ++n) {
    if (kept_by_count[n] > 0) kept << " " << n << ":" << kept_by_count[n];
  }
  INFO(summary("xArm7 pads", tally) << "; after the driver:" << kept.str());
  CHECK(tally.worst <= 1);
  // the ties are there: face to face, rounding leaves 2, 3 or 4 contacts
  CHECK(kept_by_count[2] > 0);
  CHECK(kept_by_count[3] > 0);
  CHECK(kept_by_count[4] > 0);
  SUCCEED(summary("xArm7 pads", tally) + "; after the driver:" + kept.str());
}

// MuJoCo's function returns repeated positions (two equal cubes face to face: 9 points, the
// corners twice); its collision stage keeps 4. This shows that the driver drops them, and that
// remove_repeated_positions drops the same ones, in the same order.
TEST_CASE("diff: MuJoCo's driver drops repeated box-box positions, lever's rule matches",
          "[diff][collision]") {
  REQUIRE(mj_version() == 222);
  const MjModelPtr model = mujoco_load_string(R"(
<mujoco>
  <worldbody>
    <geom name="table" type="box" size="0.1 0.1 0.1"/>
    <body name="cube" pos="0 0 0.3">
      <freejoint/>
      <geom type="box" size="0.1 0.1 0.1"/>
    </body>
  </worldbody>
</mujoco>)");
  const MjDataPtr data = mujoco_data(model.get());
  mjModel* m = model.get();
  mjData* d = data.get();
  std::mt19937_64 rng(19004);
  int raw_more_than_kept = 0;
  for (int i = 0; i < 200; ++i) {
    // the cube on the table: exactly aligned in the first poses, shifted and turned after
    const double shift = i < 50 ? 0.0 : 0.05 * std::uniform_int_distribution<int>(-2, 2)(rng);
    const double turn = i < 100 ? 0.0 : M_PI / 2 * std::uniform_int_distribution<int>(0, 3)(rng);
    const double x = i % 2 ? shift : 0.0, y = i % 3 ? shift : 0.0;
    d->qpos[0] = x;
    d->qpos[1] = y;
    d->qpos[2] = 0.2 - 0.001 * (i % 4);
    d->qpos[3] = std::cos(turn / 2);
    d->qpos[4] = 0;
    d->qpos[5] = 0;
    d->qpos[6] = std::sin(turn / 2);
    mj_forward(m, d);

    std::array<GeomShape, 2> g;
    for (int k = 0; k < 2; ++k) {
      g[k] = shape(GeomType::kBox, Eigen::Map<const Vec>(m->geom_size + 3 * k),
                   Eigen::Map<const Vec>(d->geom_xpos + 3 * k),
                   Eigen::Map<const Mat3>(d->geom_xmat + 9 * k));
    }
    std::array<Contact, kMaxPairContacts> ours;
    const int raw = detail::collide_box_box(g[0], g[1], 0.0, ours.data());
    std::array<mjContact, mjMAXCONPAIR> theirs;
    REQUIRE(mjCOLLISIONFUNC[mjGEOM_BOX][mjGEOM_BOX](m, d, theirs.data(), 0, 1, 0.0) == raw);
    const int kept = detail::remove_repeated_positions(ours.data(), raw);
    INFO("pose " << i << ": function " << raw << ", lever kept " << kept << ", MuJoCo's ncon "
                 << d->ncon);
    REQUIRE(d->ncon == kept);
    for (int c = 0; c < kept; ++c) {
      CHECK(d->contact[c].geom1 == 0);
      for (int k = 0; k < 3; ++k) CHECK(agrees(ours[c].pos[k], d->contact[c].pos[k]));
    }
    raw_more_than_kept += raw > kept;
  }
  CHECK(raw_more_than_kept > 0);  // the function itself returned repeated positions
}

}  // namespace lever::test
