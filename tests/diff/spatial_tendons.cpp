// Spatial tendons against MuJoCo 2.2.2: tests/models/constraints/spatial_tendons.xml (sites,
// spheres and cylinders wrapped with and without side sites, side sites inside the geom, two geoms
// in one path, pulleys; limits, springs, dampers, friction loss, tendon actuators and a tendon
// coupling) on random states and runs, and the Robotiq 2F-85 scene's limited site-to-site
// tendon, through MuJoCo's compiled model and through lever's loader. The tendon arrays
// (ten_length, ten_J, ten_velocity, ten_wrapadr, ten_wrapnum, wrap_obj, wrap_xpos), qfrc_passive,
// the rows and the solver's answer agree within 1e-12; the random states are checked to hold
// every wrap both active and inactive, and on both sides of its geom.
#include <catch2/catch.hpp>
#include <lever/diff/runs.hpp>
#include <lever/forward.hpp>

#include <algorithm>
#include <filesystem>
#include <random>
#include <set>

#include <lever/harness/models.hpp>
#include "diff_checks.hpp"
#include "robots.hpp"

namespace lever::test {

namespace {

constexpr int kSpatialStates = 100;
constexpr double kSpatialRunSeconds = 0.3;

std::string spatial_model_file() { return model_path("tests/models/constraints/spatial_tendons.xml"); }

void require_spatial_quantities(const diff::Report& report, int states) {
  for (const char* q : {"ten_length", "ten_J", "ten_velocity", "ten_wrapadr", "ten_wrapnum",
                        "wrap_obj", "wrap_xpos", "actuator_length", "actuator_moment",
                        "qfrc_passive", "qfrc_actuator", "nefc", "efc_J", "efc_force", "qacc"}) {
    INFO(q);
    const diff::Extreme* e = report.find(q);
    REQUIRE(e != nullptr);
    CHECK(e->compared >= states);
  }
}

// What the random states exercised: per wrapping object of the path (by its index in wrap_*),
// whether it wrapped in some state and ran straight in another, and on which sides (the sign of
// the turn from the first tangent point to the second about the geom's centre, in its z axis or,
// for a sphere, about the normal of the plane of the two sites).
struct WrapCensus {
  std::set<int> wrapped, straight, turned_left, turned_right;
};

void count_wraps(const Model& model, const Data& data, WrapCensus& census) {
  for (int t = 0; t < model.ntendon; ++t) {
    // walk the path and its points together: a site and a pulley have one point each, a geom
    // two when the tendon wraps around it and none when it runs straight
    int point = data.ten_wrapadr[t];
    const int end = point + data.ten_wrapnum[t];
    for (int w = model.tendon_adr[t]; w < model.tendon_adr[t] + model.tendon_num[t]; ++w) {
      const WrapType type = model.wrap_type[w];
      if (type == WrapType::kPulley) {
        ++point;
        continue;
      }
      if (type == WrapType::kSite) {
        ++point;  // every site of the path has one point, -1 (a pulley one, -2)
        continue;
      }
      const int geom = model.wrap_objid[w];
      if (point + 1 < end && data.wrap_obj[point / 2][point % 2] == geom) {
        census.wrapped.insert(w);
        Eigen::Vector3d a, b;
        for (int c = 0; c < 3; ++c) {
          a[c] = data.wrap_xpos[point / 2][3 * (point % 2) + c];
          b[c] = data.wrap_xpos[(point + 1) / 2][3 * ((point + 1) % 2) + c];
        }
        const Eigen::Vector3d centre = data.geom_xpos[geom];
        const Eigen::Vector3d axis = data.geom_xmat[geom].col(2);
        const double turn = (a - centre).cross(b - centre).dot(axis);
        (turn > 0 ? census.turned_left : census.turned_right).insert(w);
        point += 2;
      } else {
        census.straight.insert(w);
      }
    }
  }
}

}  // namespace

TEST_CASE("diff: spatial tendons agree with MuJoCo on random states", "[diff][tendons]") {
  REQUIRE(mj_version() == 222);
  const std::string file = spatial_model_file();
  for (const diff::Path path : paths_to_compare()) {
    const std::uint64_t seed = diff::default_seed(file);
    INFO(context(file, path, seed));
    diff::Twin twin(file, path);
    const diff::Report report = diff::random_states(twin, kSpatialStates, seed);
    check_within_bound(report, all_but_inverse_at_forward(report));
    inverse_at_forward_agrees(twin, kSpatialStates, seed);
    require_spatial_quantities(report, kSpatialStates);
  }
}

TEST_CASE("diff: the random states wrap every geom both ways and not at all", "[diff][tendons]") {
  // the same states random_states draws: every wrapping object of the path wraps in some and runs
  // straight in others; the cylinders are wrapped on both sides
  diff::Twin twin(spatial_model_file(), diff::Path::kLoader);
  std::mt19937_64 rng(diff::default_seed(spatial_model_file()));
  WrapCensus census;
  for (int k = 0; k < kSpatialStates; ++k) {
    twin.set_state(random_state(twin.model, rng));
    random_qacc(twin.model, rng);
    forward(twin.model, twin.data);
    count_wraps(twin.model, twin.data, census);
  }
  int cylinders = 0;
  for (int w = 0; w < twin.model.nwrap; ++w) {
    const WrapType type = twin.model.wrap_type[w];
    if (type != WrapType::kSphere && type != WrapType::kCylinder) continue;
    INFO("path object " << w << " (geom " << twin.model.wrap_objid[w] << ")");
    CHECK(census.wrapped.count(w) == 1);
    CHECK(census.straight.count(w) == 1);
    if (type == WrapType::kCylinder && twin.model.wrap_prm[w] < 0) {
      ++cylinders;
      CHECK(census.turned_left.count(w) == 1);
      CHECK(census.turned_right.count(w) == 1);
    }
  }
  CHECK(cylinders >= 3);
}

TEST_CASE("diff: the random states make every kind of spatial tendon row", "[diff][tendons]") {
  // on the states random_states draws: the coupling's row, friction-loss rows of SF and BE, and
  // limit rows of SE, knob and lift (each within its margin of a stop in some state), with the
  // same types and ids as MuJoCo's
  diff::Twin twin(spatial_model_file(), diff::Path::kLoader);
  std::mt19937_64 rng(diff::default_seed(spatial_model_file()));
  std::set<int> limited, with_friction;
  int equality_rows = 0;
  for (int k = 0; k < kSpatialStates; ++k) {
    const State s = random_state(twin.model, rng);
    random_qacc(twin.model, rng);
    twin.set_state(s);
    forward(twin.model, twin.data);
    twin.mujoco_forward();
    REQUIRE(twin.d->nefc == twin.data.nefc);
    for (int r = 0; r < twin.data.nefc; ++r) {
      CHECK(static_cast<int>(twin.data.efc_type[r]) == twin.d->efc_type[r]);
      CHECK(twin.data.efc_id[r] == twin.d->efc_id[r]);
      const ConstraintType type = twin.data.efc_type[r];
      if (type == ConstraintType::kLimitTendon) limited.insert(twin.data.efc_id[r]);
      if (type == ConstraintType::kFrictionTendon) with_friction.insert(twin.data.efc_id[r]);
      equality_rows += type == ConstraintType::kEquality;
    }
  }
  const auto tendon = [&](const char* name) {
    const auto& names = twin.model.tendon_name;
    return static_cast<int>(std::find(names.begin(), names.end(), name) - names.begin());
  };
  CHECK(equality_rows == kSpatialStates);
  CHECK(with_friction == std::set<int>{tendon("SF"), tendon("BE")});
  CHECK(limited == std::set<int>{tendon("SE"), tendon("knob"), tendon("lift")});
}

TEST_CASE("diff: spatial tendons in lockstep and free runs", "[diff][tendons]") {
  REQUIRE(mj_version() == 222);
  const std::string file = spatial_model_file();
  for (const diff::Path path : paths_to_compare()) {
    check_lockstep_every_integrator(file, path, kSpatialRunSeconds);
  }
  check_free_run(file, diff::Path::kLoader, kSpatialRunSeconds);
}

TEST_CASE("diff: the 2F-85 scene's spatial tendon agrees with MuJoCo", "[diff][tendons][robots]") {
  // a limited site-to-site tendon holding a free box from a world site; contacts off, as for the
  // other tendon robots (the random states put the box inside the fingers and the floor)
  REQUIRE(mj_version() == 222);
  const std::string folder = robots_dir();
  if (!robots_present(folder)) return;
  const std::string file = folder + "/menagerie-2022/robotiq_2f85/scene.xml";
  for (const diff::Path path : paths_to_compare()) {
    const std::uint64_t seed = diff::default_seed(file);
    INFO(context(file, path, seed));
    diff::Twin twin(file, path);
    twin.m->opt.disableflags |= mjDSBL_CONTACT;
    twin.model.opt.disableflags |= kDisableContact;
    set_const(twin.model);
    twin.data = Data(twin.model);
    REQUIRE(twin.model.wrap_type[twin.model.tendon_adr[1]] == WrapType::kSite);
    const diff::Report report = diff::random_states(twin, 20, seed);
    check_within_bound(report, all_but_inverse_at_forward(report));
    require_spatial_quantities(report, 20);
    check_within_bound(diff::lockstep(twin, twin.model.opt.integrator, 0.5, diff::Control::kKeep));
  }
}

}  // namespace lever::test
