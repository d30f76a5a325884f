// Fixed tendons against MuJoCo 2.2.2: tests/models/constraints/tendons.xml (tendon springs and
// dampers, limits, friction loss, tendon couplings, tendon-driven actuators) on random states and
// runs, and the real files that use tendons (Menagerie 2022's Franka Panda hand and arm, the
// Robotiq 2F-85, the Shadow hands), through MuJoCo's compiled model and through lever's loader.
// The tendon arrays (ten_length, ten_J, ten_velocity), the actuators' (actuator_length,
// actuator_moment), qfrc_passive, the rows (a tendon's friction-loss row after the dofs', its
// limit rows after the joints') and the solver's answer agree within 1e-12.
#include <catch2/catch.hpp>
#include <lever/diff/runs.hpp>
#include <lever/forward.hpp>

#include <filesystem>

#include <lever/harness/models.hpp>
#include "diff_checks.hpp"
#include "sampling.hpp"
#include "robots.hpp"

namespace lever::test {

namespace {

constexpr int kTendonStates = samples(100);
constexpr double kTendonRunSeconds = 0.4;

std::string tendon_model_file() { return model_path("tests/models/constraints/tendons.xml"); }

// the quantities a tendon model must have compared, in every state
void require_tendon_quantities(const diff::Report& report, int states) {
  for (const char* q : {"ten_length", "ten_J", "ten_velocity", "actuator_length",
                        "actuator_moment", "actuator_velocity", "qfrc_passive", "qfrc_actuator",
                        "nefc", "ne", "nf", "efc_J", "efc_force", "qacc"}) {
    INFO(q);
    const diff::Extreme* e = report.find(q);
    REQUIRE(e != nullptr);
    CHECK(e->compared >= states);
  }
}

// the rows' kinds at one state
struct TendonRowCensus {
  int friction_tendon = 0, limit_tendon = 0, equality = 0;
};

TendonRowCensus tendon_census(const Data& data) {
  TendonRowCensus c;
  for (int r = 0; r < data.nefc; ++r) {
    c.friction_tendon += data.efc_type[r] == ConstraintType::kFrictionTendon;
    c.limit_tendon += data.efc_type[r] == ConstraintType::kLimitTendon;
    c.equality += data.efc_type[r] == ConstraintType::kEquality;
  }
  return c;
}

}  // namespace

TEST_CASE("diff: fixed tendons agree with MuJoCo on random states", "[diff][tendons]") {
  REQUIRE(mj_version() == 222);
  const std::string file = tendon_model_file();
  for (const diff::Path path : paths_to_compare()) {
    const std::uint64_t seed = diff::default_seed(file);
    INFO(context(file, path, seed));
    diff::Twin twin(file, path);
    const diff::Report report = diff::random_states(twin, kTendonStates, seed);
    check_within_bound(report, all_but_inverse_at_forward(report));
    inverse_at_forward_agrees(twin, kTendonStates, seed);
    require_tendon_quantities(report, kTendonStates);
  }
}

TEST_CASE("diff: tendon rows come in MuJoCo's order", "[diff][tendons]") {
  // from the keyframe: the couplings first, then friction loss (four tendons have it), then the
  // limit rows of `flex` (past its upper stop) after the joints'
  diff::Twin twin(tendon_model_file(), diff::Path::kLoader);
  reset_keyframe(twin.model, twin.data, 0);
  forward(twin.model, twin.data);
  const TendonRowCensus c = tendon_census(twin.data);
  CHECK(c.equality == 2);
  CHECK(c.friction_tendon == 4);
  CHECK(twin.data.nf == 4);
  CHECK(c.limit_tendon >= 1);
  for (int r = 0; r < twin.data.ne; ++r) CHECK(twin.data.efc_type[r] == ConstraintType::kEquality);
  for (int r = twin.data.ne; r < twin.data.ne + twin.data.nf; ++r) {
    CHECK(twin.data.efc_type[r] == ConstraintType::kFrictionTendon);
  }
  mj_resetDataKeyframe(twin.m.get(), twin.d.get(), 0);
  mj_forward(twin.m.get(), twin.d.get());
  REQUIRE(twin.d->nefc == twin.data.nefc);
  for (int r = 0; r < twin.data.nefc; ++r) {
    CHECK(static_cast<int>(twin.data.efc_type[r]) == twin.d->efc_type[r]);
    CHECK(twin.data.efc_id[r] == twin.d->efc_id[r]);
  }
}

TEST_CASE("diff: fixed tendons in lockstep and free runs", "[diff][tendons]") {
  REQUIRE(mj_version() == 222);
  const std::string file = tendon_model_file();
  for (const diff::Path path : paths_to_compare()) {
    check_lockstep_every_integrator(file, path, kTendonRunSeconds);
    check_free_run(file, path, kTendonRunSeconds);
  }
}

}  // namespace lever::test

namespace lever::test {

namespace {

// The real files whose tendons couple fingers (the Panda's and the 2F-85's split, the Shadow
// hands' distal couplings). Contacts are disabled on both sides: their fingers' meshes touch at
// rest in some poses, and what is compared here is the tendons, their actuators and rows.
constexpr const char* kTendonRobotFiles[] = {
    "menagerie-2022/franka_emika_panda/hand.xml",  "menagerie-2022/franka_emika_panda/panda.xml",
    "menagerie-2022/franka_emika_panda/scene.xml", "menagerie-2022/robotiq_2f85/2f85.xml",
    "menagerie-2022/shadow_hand/left_hand.xml",    "menagerie-2022/shadow_hand/right_hand.xml",
    "menagerie-2022/shadow_hand/scene_left.xml",   "menagerie-2022/shadow_hand/scene_right.xml"};

void without_contacts(diff::Twin& twin) {
  twin.m->opt.disableflags |= mjDSBL_CONTACT;
  twin.model.opt.disableflags |= kDisableContact;
  set_const(twin.model);
  twin.data = Data(twin.model);
}

}  // namespace

TEST_CASE("diff: real files with tendons agree with MuJoCo", "[diff][tendons][robots]") {
  REQUIRE(mj_version() == 222);
  const std::string folder = robots_dir();
  if (!robots_present(folder)) return;
  for (const char* name : kTendonRobotFiles) {
    const std::string file = folder + "/" + name;
    for (const diff::Path path : paths_to_compare()) {
      const std::uint64_t seed = diff::default_seed(file);
      INFO(context(file, path, seed));
      diff::Twin twin(file, path);
      without_contacts(twin);
      REQUIRE(twin.model.ntendon > 0);
      const int states = samples(20);
      const diff::Report report = diff::random_states(twin, states, seed);
      check_within_bound(report, all_but_inverse_at_forward(report));
      require_tendon_quantities(report, states);
      // 1 s from the first keyframe (or qpos0), its controls held, each engine stepping from
      // MuJoCo's state (lockstep), under the file's own integrator; a scene.xml adds only a floor
      // and lights to a robot run already (contacts are off), so its run is left out (CI time)
      if (std::string(name).find("scene") != std::string::npos) continue;
      check_within_bound(diff::lockstep(twin, twin.model.opt.integrator, 1.0, diff::Control::kKeep));
    }
  }
}

}  // namespace lever::test
