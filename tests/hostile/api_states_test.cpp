// Hostile states through the API, on every model of the repository: NaN, infinities, huge and
// denormal values in qpos, qvel, ctrl and qfrc_applied. forward() must record a warning whenever
// an output is not finite; step() must leave a finite state, and reset it (recording why) when it
// was bad, as MuJoCo 2.2.2's mj_step.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <string>

#include <lever/lever.hpp>
#include <lever/mjcf.hpp>

#include <lever/harness/models.hpp>

namespace {

struct Value {
  const char* name;
  double x;
  bool bad;  // MuJoCo's mju_isBad: NaN or |x| > 1e10
};

const Value kValues[] = {
    {"NaN", std::numeric_limits<double>::quiet_NaN(), true},
    {"+inf", std::numeric_limits<double>::infinity(), true},
    {"-inf", -std::numeric_limits<double>::infinity(), true},
    {"1e300", 1e300, true},
    {"-2e10", -2e10, true},
    {"1e10", 1e10, false},
    {"denormal", std::numeric_limits<double>::denorm_min(), false},
    {"-0", -0.0, false},
};

bool finite_outputs(const lever::Data& d) {
  for (const auto& x : d.xpos) {
    if (!x.allFinite()) return false;
  }
  return d.M.allFinite() && d.qfrc_bias.allFinite() && d.qfrc_passive.allFinite() &&
         d.qfrc_actuator.allFinite() && d.qacc.allFinite() && d.qfrc_constraint.allFinite() &&
         d.actuator_force.allFinite();
}

// The index of the last qpos entry that is a position or an angle, not part of a quaternion.
Eigen::Index last_plain_coordinate(const lever::Model& model) {
  const int j = model.njnt - 1;
  const int adr = model.jnt_qposadr[j];
  switch (model.jnt_type[j]) {
    case lever::JointType::kFree: return adr + 2;  // its position's z
    case lever::JointType::kBall: return adr - 1;  // the joint before it
    default: return adr;
  }
}

}  // namespace

TEST_CASE("hostile states through the API: warned about, reset by step, never silent",
          "[hostile][bad-state]") {
  for (const std::string& file : lever::test::all_model_files()) {
    const lever::Model model = lever::mjcf::load_file(file);
    for (const char* field : {"qpos", "qvel", "ctrl", "qfrc_applied"}) {
      for (const Value& v : kValues) {
        lever::Data probe(model);
        lever::ArenaVector& target = std::string(field) == "qpos"   ? probe.qpos
                                     : std::string(field) == "qvel" ? probe.qvel
                                     : std::string(field) == "ctrl" ? probe.ctrl
                                                                    : probe.qfrc_applied;
        if (target.size() == 0) continue;
        {
          INFO(file << " " << field << " = " << v.name);
          lever::Data data(model);
          lever::ArenaVector& x = std::string(field) == "qpos"   ? data.qpos
                                  : std::string(field) == "qvel" ? data.qvel
                                  : std::string(field) == "ctrl" ? data.ctrl
                                                                 : data.qfrc_applied;
          // qpos: the last coordinate that is not a quaternion's (forward normalizes those in
          // place, as MuJoCo's mj_normalizeQuat, so a huge one is gone before step sees it)
          x[std::string(field) == "qpos" ? last_plain_coordinate(model) : x.size() - 1] = v.x;

          lever::forward(model, data);
          // not finite only with a warning; a bad state, position or velocity is always warned
          // about (a bad control is warned about unless ctrlrange clamps it first, as MuJoCo)
          if (!finite_outputs(data)) CHECK(lever::warning_count(data) > 0);
          const std::string f(field);
          if (v.bad && (f == "qpos" || f == "qvel" || f == "qfrc_applied")) {
            CHECK(lever::warning_count(data) > 0);
            CHECK(!lever::warning_text(data).empty());
          }

          lever::step(model, data);
          CHECK(data.qpos.allFinite());
          CHECK(data.qvel.allFinite());
          CHECK(data.qacc.allFinite());
          if (v.bad && (f == "qpos" || f == "qvel")) {
            // mj_checkPos / mj_checkVel: reset to qpos0 and one step from rest
            CHECK(lever::warning_count(data) == 1);
            CHECK(data.time == model.opt.timestep);
          }
          if (std::abs(v.x) < 1 && f != "ctrl" && f != "qfrc_applied") {
            // a tiny value changes nothing (1e10 is not bad itself, but what it leads to can be)
            CHECK(lever::warning_count(data) == 0);
          }
        }
      }
    }
  }
}
