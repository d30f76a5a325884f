// lever's collision() against MuJoCo 2.2.2's mj_collision on random states of the scenes in
// tests/diff/contact_scenes: MuJoCo's compiled model is copied into lever (harness from_mujoco),
// lever runs kinematics() + collision(), MuJoCo mj_fwdPosition, and the contact lists must be
// the same list: ncon, geom1, geom2, dim and exclude exactly, in order; pos, frame, dist,
// friction, solref, solimp and includemargin within the agreement bound.
//
// The two collision stages are held to that on the same input: the geom poses agree within the
// bound, and MuJoCo's mj_collision is run again on lever's poses. The contacts of each engine's
// own poses are also compared and reported, not gated: on the same poses the two agree bitwise,
// so what differs there is MuJoCo's own answer moved by the poses' last-bit differences, which
// a contact's normal can amplify (two capsules whose segments nearly cross: the normal is the
// direction between nearest points micrometres apart; seen at 368 times the bound).
//
// The scenes hold cylinders and ellipsoids against other solids (MuJoCo's MPR pairs), which lever
// collides with the same MPR: every contact MuJoCo makes is compared. A pair lever has no function
// for (a height field) would be set aside, and a state where MuJoCo made one must show lever's
// kContactUnsupported warning; these scenes have none.
#include <mujoco/mujoco.h>
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <lever/collision.hpp>
#include <lever/error.hpp>
#include <lever/harness/from_mujoco.hpp>
#include <lever/harness/models.hpp>
#include <lever/harness/tolerance.hpp>
#include <lever/kinematics.hpp>
#include "sampling.hpp"

namespace lever::test {

namespace {

std::string scene(const std::string& name) {
  return source_dir() + "/tests/diff/contact_scenes/" + name;
}

/// A random configuration that brings the scene's bodies into contact: slides within +-0.15 m,
/// hinges anywhere; one state in four keeps the hinges at exactly zero (the scenes are built so
/// that capsules then lie parallel to each other or to a plane).
/// qpos: nq numbers (a Data's qpos, or a vector of that size), overwritten.
void random_configuration(const Model& model, std::mt19937_64& rng, bool hinges_at_zero,
                          Eigen::Ref<Eigen::VectorXd> qpos) {
  std::uniform_real_distribution<double> slide(-0.15, 0.15),
      hinge(-std::numbers::pi, std::numbers::pi), unit(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  qpos = model.qpos0;
  for (int j = 0; j < model.njnt; ++j) {
    const int adr = model.jnt_qposadr[j];
    switch (model.jnt_type[j]) {
      case JointType::kSlide: qpos[adr] = slide(rng); break;
      case JointType::kHinge: qpos[adr] = hinges_at_zero ? 0.0 : hinge(rng); break;
      case JointType::kFree: {
        // within 0.15 m of the table's centre, from touching to 0.2 m above it; upright, turned
        // about the vertical only (faces parallel: the ties), or any orientation
        qpos[adr] = slide(rng);
        qpos[adr + 1] = slide(rng);
        qpos[adr + 2] = 0.2 * unit(rng);
        const double u = unit(rng);
        Eigen::Vector4d q(1, 0, 0, 0);
        if (u >= 0.25 && u < 0.5) {
          const double half = 0.5 * hinge(rng);
          q = Eigen::Vector4d(std::cos(half), 0, 0, std::sin(half));
        } else if (u >= 0.5) {
          q = Eigen::Vector4d(normal(rng), normal(rng), normal(rng), normal(rng)).normalized();
        }
        qpos.segment<4>(adr + 3) = q;
        break;
      }
      case JointType::kBall:
        qpos.segment<4>(adr) =
            Eigen::Vector4d(normal(rng), normal(rng), normal(rng), normal(rng)).normalized();
        break;
    }
  }
}

/// The contacts MuJoCo made that lever compares: those of pairs lever has a function for.
std::vector<int> comparable(const mjModel* m, const mjData* d, int& unsupported) {
  std::vector<int> kept;
  unsupported = 0;
  for (int i = 0; i < d->ncon; ++i) {
    const mjContact& c = d->contact[i];
    const auto t1 = static_cast<GeomType>(m->geom_type[c.geom1]);
    const auto t2 = static_cast<GeomType>(m->geom_type[c.geom2]);
    if (has_collision_function(t1, t2)) {
      kept.push_back(i);
    } else {
      ++unsupported;
    }
  }
  return kept;
}

struct Tally {
  int states = 0, contacts = 0, excluded = 0, states_with_unsupported = 0;
  double worst = 0;  ///< the collision stage on the same poses
  std::array<int, 7> by_dim{};
  // end to end (each engine's own kinematics): measured, not gated (see the test's comment)
  double end_to_end_worst = 0;
  int end_to_end_states_differing = 0;
};

/// Excess of one value, added to `worst`; a CHECK when `gate`.
void check_value(double& worst, bool gate, const char* field, int index, double ours,
                 double reference, double size) {
  const double e = excess(ours, reference, size);
  worst = std::max(worst, e);
  if (!gate) return;
  INFO(describe(field, index, ours, reference, size));
  CHECK(e <= 1.0);
}

template <size_t N>
void check_array(double& worst, bool gate, const char* field, const std::array<double, N>& ours,
                 const mjtNum* reference) {
  const double size = magnitude(reference, static_cast<int>(N));
  for (size_t i = 0; i < N; ++i) {
    check_value(worst, gate, field, static_cast<int>(i), ours[i], reference[i], size);
  }
}

/// lever's contact list against MuJoCo's `contacts` (the comparable ones, `order`); with `gate`,
/// every difference is a failure, else the list's structure must match for the values to be
/// measured into `worst` (returns whether it matched).
bool compare_contacts(const Data& data, const mjContact* contacts, const std::vector<int>& order,
                      bool gate, double& worst, Tally* tally) {
  if (!gate && data.ncon != static_cast<int>(order.size())) return false;
  REQUIRE(data.ncon == static_cast<int>(order.size()));
  for (int k = 0; k < data.ncon; ++k) {
    const Contact& ours = data.contact[k];
    const mjContact& c = contacts[order[k]];
    INFO("contact " << k << " (MuJoCo's " << order[k] << "): geoms " << c.geom1 << ", " << c.geom2);
    const bool same = ours.geom1 == c.geom1 && ours.geom2 == c.geom2 && ours.dim == c.dim &&
                      ours.exclude == c.exclude;
    if (!gate && !same) return false;
    REQUIRE(ours.geom1 == c.geom1);
    REQUIRE(ours.geom2 == c.geom2);
    CHECK(ours.dim == c.dim);
    CHECK(ours.exclude == c.exclude);
    check_value(worst, gate, "dist", 0, ours.dist, c.dist, c.dist);
    check_value(worst, gate, "includemargin", 0, ours.includemargin, c.includemargin,
                c.includemargin);
    const double pos_size = magnitude(c.pos, 3);
    for (int i = 0; i < 3; ++i) {
      check_value(worst, gate, "pos", i, ours.pos[i], c.pos[i], pos_size);
    }
    for (int i = 0; i < 9; ++i) {
      check_value(worst, gate, "frame", i, ours.frame(i / 3, i % 3), c.frame[i], 1.0);
    }
    check_array(worst, gate, "friction", ours.friction, c.friction);
    check_array(worst, gate, "solref", ours.solref, c.solref);
    check_array(worst, gate, "solimp", ours.solimp, c.solimp);
    if (tally) {
      ++tally->contacts;
      tally->excluded += ours.exclude;
      ++tally->by_dim[ours.dim];
    }
  }
  return true;
}

/// One state's contacts, lever's against MuJoCo's, at the qpos lever's data holds: MuJoCo's
/// collision on lever's geom poses gated, each engine's own kinematics measured into the tally.
void compare_state(const mjModel* m, mjData* d, const Model& model, Data& data, Tally& tally) {
  const int unsupported_kind = static_cast<int>(Warning::kContactUnsupported);
  for (int i = 0; i < model.nq; ++i) d->qpos[i] = data.qpos[i];
  mj_fwdPosition(m, d);
  REQUIRE(d->ncon < m->nconmax);  // MuJoCo did not drop any
  const std::vector<mjContact> reference(d->contact, d->contact + d->ncon);
  int unsupported = 0;
  const std::vector<int> reference_order = comparable(m, d, unsupported);

  // the geoms' poses from each engine's kinematics agree (the field table's diff checks them
  // too); MuJoCo's collision then runs again on lever's poses, so that both collision stages
  // see the same numbers
  kinematics(model, data);
  for (int g = 0; g < model.ngeom; ++g) {
    double ignored = 0;
    const double* xpos = d->geom_xpos + 3 * g;
    const double* xmat = d->geom_xmat + 9 * g;
    for (int i = 0; i < 3; ++i) {
      check_value(ignored, true, "geom_xpos", 3 * g + i, data.geom_xpos[g][i], xpos[i],
                  magnitude(xpos, 3));
      d->geom_xpos[3 * g + i] = data.geom_xpos[g][i];
    }
    for (int i = 0; i < 9; ++i) {
      check_value(ignored, true, "geom_xmat", 9 * g + i, data.geom_xmat[g](i / 3, i % 3), xmat[i],
                  1.0);
      d->geom_xmat[9 * g + i] = data.geom_xmat[g](i / 3, i % 3);
    }
  }
  mj_collision(m, d);

  const int warnings_before = data.warning[unsupported_kind].number;
  collision(model, data);
  const bool lever_warned = data.warning[unsupported_kind].number > warnings_before;

  const std::vector<int> order = comparable(m, d, unsupported);
  // a pair MuJoCo collided and lever could not is never silent
  if (unsupported > 0) CHECK(lever_warned);
  if (lever_warned) ++tally.states_with_unsupported;
  compare_contacts(data, d->contact, order, true, tally.worst, &tally);

  // end to end: lever's contacts against MuJoCo's from MuJoCo's own kinematics
  if (!compare_contacts(data, reference.data(), reference_order, false, tally.end_to_end_worst,
                        nullptr)) {
    ++tally.end_to_end_states_differing;
  }
  ++tally.states;
}

Tally compare_scene(const std::string& file, int states, std::uint64_t seed) {
  const MjModelPtr m = mujoco_load(scene(file));
  const MjDataPtr d = mujoco_data(m.get());
  const Model model = from_mujoco(m.get());
  Data data(model);
  std::mt19937_64 rng(seed);
  Tally tally;
  for (int s = 0; s < states; ++s) {
    INFO(file << ", state " << s << " (seed " << seed << ")");
    random_configuration(model, rng, s % 4 == 0, data.qpos);
    compare_state(m.get(), d.get(), model, data, tally);
  }
  return tally;
}

}  // namespace

TEST_CASE("collision driver: contacts equal MuJoCo's on random states of the contact scenes",
          "[diff][collision]") {
  REQUIRE(mj_version() == 222);
  for (const char* file : {"arm_and_objects.xml", "capsule_stack.xml", "free_objects.xml"}) {
    const Tally t = compare_scene(file, samples(2000), 19 + std::string(file).size());
    WARN(file << ": " << t.states << " states, " << t.contacts << " contacts (" << t.excluded
              << " beyond includemargin; condim 1/3/4/6: " << t.by_dim[1] << "/" << t.by_dim[3]
              << "/" << t.by_dim[4] << "/" << t.by_dim[6] << "), " << t.states_with_unsupported
              << " states with an unsupported pair; worst " << t.worst
              << " of the bound; end to end (each engine's kinematics) worst " << t.end_to_end_worst
              << " of the bound, " << t.end_to_end_states_differing
              << " states whose contact list differs");
    // the states must make contacts, of every kind the scene is built for
    CHECK(t.contacts > t.states);
    CHECK(t.excluded > 0);
    CHECK(t.states_with_unsupported == 0);
  }
}

}  // namespace lever::test

namespace lever::test {

TEST_CASE("collision driver: more contacts than nconmax is refused and changes nothing",
          "[diff][collision]") {
  const MjModelPtr m = mujoco_load(scene("capsule_stack.xml"));
  Model model = from_mujoco(m.get());
  model.nconmax = 8;
  Data data(model);
  std::mt19937_64 rng(7);

  // a state whose contacts fit, then one with more than nconmax
  int fitting = -1, overflowing = -1;
  std::vector<Eigen::VectorXd> states;
  for (int s = 0; s < 200 && (fitting < 0 || overflowing < 0); ++s) {
    Eigen::VectorXd qpos(model.nq);
    random_configuration(model, rng, false, qpos);
    states.push_back(qpos);
    data.qpos = qpos;
    kinematics(model, data);
    try {
      collision(model, data);
      if (data.ncon > 0 && fitting < 0) fitting = s;
    } catch (const StateError&) {
      if (overflowing < 0) overflowing = s;
    }
  }
  REQUIRE(fitting >= 0);
  REQUIRE(overflowing >= 0);

  data.qpos = states[fitting];
  kinematics(model, data);
  collision(model, data);
  const int ncon = data.ncon;
  const std::vector<Contact> before(data.contact.begin(), data.contact.begin() + ncon);

  data.qpos = states[overflowing];
  kinematics(model, data);
  CHECK_THROWS_WITH(collision(model, data), Catch::Contains("more than nconmax = 8"));
  CHECK(data.ncon == ncon);
  for (int k = 0; k < ncon; ++k) {
    CHECK(data.contact[k].geom1 == before[k].geom1);
    CHECK(data.contact[k].geom2 == before[k].geom2);
    CHECK(data.contact[k].dist == before[k].dist);
    CHECK(data.contact[k].pos == before[k].pos);
  }
}

TEST_CASE("collision driver: exclusions out of order are refused by name", "[diff][collision]") {
  const MjModelPtr m = mujoco_load(scene("arm_and_objects.xml"));
  Model unsorted = from_mujoco(m.get());
  REQUIRE(unsorted.nexclude == 2);
  std::swap(unsorted.exclude_signature[0], unsorted.exclude_signature[1]);
  Data data2(unsorted);
  kinematics(unsorted, data2);
  CHECK_THROWS_WITH(collision(unsorted, data2), Catch::Contains("sorted"));
}

TEST_CASE("collision driver: an unsupported pair within its bounding spheres is a warning",
          "[diff][collision]") {
  // a sphere over a height field: MuJoCo collides them by MPR on the field's prisms, lever has
  // no height fields and records and skips the pair
  const MjModelPtr m = mujoco_load_string(R"(
<mujoco>
  <asset>
    <hfield name="ground" nrow="3" ncol="3" size="1 1 0.1 0.1"/>
  </asset>
  <worldbody>
    <geom name="ground" type="hfield" hfield="ground"/>
    <body name="ball" pos="0 0 0.15">
      <joint type="slide" axis="0 0 1"/>
      <geom name="ball" type="sphere" size="0.05"/>
    </body>
  </worldbody>
</mujoco>)");
  const Model model = from_mujoco(m.get());
  Data data(model);
  kinematics(model, data);
  collision(model, data);
  CHECK(data.ncon == 0);
  const WarningStat& w = data.warning[static_cast<int>(Warning::kContactUnsupported)];
  CHECK(w.number == 1);
  CHECK(w.lastinfo == 0);  // the height field, first in MuJoCo's type order
  CHECK(warning_text(data).find("cannot collide") != std::string::npos);

  // MuJoCo gives a height field no bounding sphere (geom_rbound 0), so the pair passes the
  // driver's filter at any distance and is counted at every call
  REQUIRE(model.geom_rbound[0] == 0);
  data.qpos[0] = 5.0;
  kinematics(model, data);
  collision(model, data);
  CHECK(w.number == 2);
}

}  // namespace lever::test

namespace lever::test {

// The mid-phase before MPR (driver.cpp's boxes_apart) skips two geoms whose boxes are more than
// 2e-4 apart along an axis of either, on the argument that libccd cannot report a contact there.
// Tested where the argument is tight: the second geom moved along a direction to where MuJoCo's
// contact list changes from some contacts to none (bisection to 1e-10 m), then placed at offsets
// from 1e-7 inside to 1e-3 beyond it, across the mid-phase's 2e-4; in a third of the states the
// geoms are turned as the world is and moved along an axis, so that box-like faces are parallel
// and the boxes touch where the geoms do; with and without a margin.
TEST_CASE("collision driver: the mid-phase skips no pair MuJoCo collides, near first contact",
          "[diff][collision]") {
  REQUIRE(mj_version() == 222);
  struct ShapePair {
    const char* fixed;
    const char* moving;
  };
  const ShapePair pairs[] = {
      {R"(type="mesh" mesh="coupler")", R"(type="mesh" mesh="hand")"},
      {R"(type="box" size="0.05 0.06 0.07")", R"(type="mesh" mesh="coupler")"},
      {R"(type="cylinder" size="0.04 0.05")", R"(type="mesh" mesh="hand")"},
      {R"(type="ellipsoid" size="0.04 0.05 0.06")", R"(type="box" size="0.03 0.04 0.05")"},
      {R"(type="capsule" size="0.03 0.05")", R"(type="cylinder" size="0.04 0.05")"},
  };
  const double offsets[] = {-1e-7, 1e-7, 1e-6, 1e-5, 1e-4, 1.9e-4, 2.1e-4, 3e-4, 1e-3};
  Tally tally;
  int pair_number = 0;
  for (const double margin : {0.0, 0.002}) {
    for (const ShapePair& pair : pairs) {
      const std::string margin_attribute = " margin=\"" + std::to_string(margin) + "\"";
      const std::string xml = R"(
<mujoco>
  <compiler meshdir=")" + robots_dir() + R"(/"/>
  <option gravity="0 0 0"/>
  <asset>
    <mesh name="coupler" file="menagerie-2022/robotiq_2f85/assets/coupler.stl"
          scale="0.001 0.001 0.001"/>
    <mesh name="hand" file="menagerie-2022/franka_emika_panda/assets/hand.stl"/>
  </asset>
  <worldbody>
    <geom )" + pair.fixed + margin_attribute + R"(/>
    <body><freejoint/><geom )" + pair.moving + margin_attribute + R"(/></body>
  </worldbody>
</mujoco>)";
      const MjModelPtr m = mujoco_load_string(xml);
      const MjDataPtr d = mujoco_data(m.get());
      const Model model = from_mujoco(m.get());
      Data data(model);
      std::mt19937_64 rng(7 + pair_number++);
      std::normal_distribution<double> normal(0.0, 1.0);
      std::uniform_int_distribution<int> axis(0, 5);
      for (int s = 0; s < samples(24); ++s) {
        const bool aligned = s % 3 == 0;
        Eigen::Vector3d direction;
        Eigen::Quaterniond turn = Eigen::Quaterniond::Identity();
        if (aligned) {
          const int a = axis(rng);
          direction = Eigen::Vector3d::Unit(a % 3) * (a < 3 ? 1.0 : -1.0);
        } else {
          direction = Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
          turn = Eigen::Quaterniond(normal(rng), normal(rng), normal(rng), normal(rng)).normalized();
        }
        const auto place = [&](double distance) {
          data.qpos.head<3>() = distance * direction;
          data.qpos[3] = turn.w();
          data.qpos[4] = turn.x();
          data.qpos[5] = turn.y();
          data.qpos[6] = turn.z();
        };
        const auto mujoco_touches = [&](double distance) {
          place(distance);
          for (int i = 0; i < model.nq; ++i) d->qpos[i] = data.qpos[i];
          mj_fwdPosition(m.get(), d.get());
          return d->ncon > 0;
        };
        // from the centres together (overlapping) to a metre apart (not): MuJoCo's first contact
        double touching = 0.0, apart = 1.0;
        REQUIRE(mujoco_touches(touching));
        REQUIRE(!mujoco_touches(apart));
        while (apart - touching > 1e-10) {
          const double middle = 0.5 * (touching + apart);
          (mujoco_touches(middle) ? touching : apart) = middle;
        }
        for (const double offset : offsets) {
          INFO("shapes " << pair.fixed << " and " << pair.moving << ", margin " << margin
                         << ", state " << s << (aligned ? " (aligned)" : "") << ", " << offset
                         << " m beyond MuJoCo's first contact");
          place(apart + offset);
          compare_state(m.get(), d.get(), model, data, tally);
        }
      }
    }
  }
  WARN(tally.states << " states near first contact, " << tally.contacts
                    << " contacts; worst " << tally.worst << " of the bound");
  CHECK(tally.contacts > 0);
  CHECK(tally.states_with_unsupported == 0);
}

}  // namespace lever::test
