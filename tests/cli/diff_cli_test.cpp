// `lever diff` as a user runs it: the lockstep trajectories of --trajectory under Euler, RK4 and
// MuJoCo 2.2.2's implicit integrator, --key NAME choosing the keyframe they start from, and the
// refusal of a keyframe the model does not have. Where the command reports MuJoCo's value of a
// quantity at some step, this test replays MuJoCo on its own (mjModel.opt.integrator set here,
// the keyframe reset here, the same control) and finds that value there, to the bit.
#include <algorithm>
#include <catch2/catch.hpp>

#include <mujoco/mujoco.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <lever/lever.hpp>
#include <lever/mjcf.hpp>

#include <lever/harness/from_mujoco.hpp>
#include <lever/harness/models.hpp>
#include <lever/harness/random_state.hpp>
#include "json_reader.hpp"
#include "run_lever.hpp"

namespace lever::test {

namespace {

// panda7 with a second keyframe after `home`, so that --key has something other than the first
// keyframe to choose. Written beside the temporary directory's other files.
std::string panda_with_two_keys() {
  std::ifstream in(model_path("models/panda7.xml"));
  std::stringstream text;
  text << in.rdbuf();
  std::string xml = text.str();
  const std::string end = "</keyframe>";
  const size_t at = xml.find(end);
  REQUIRE(at != std::string::npos);
  xml.insert(at, R"(  <key name="reach" qpos="0.3 0.5 -0.2 -1.2 0.4 1.9 0.1"
         ctrl="0.35 0.45 -0.15 -1.3 0.45 1.8 0.2"/>
  )");
  return temporary_file("lever-diff-panda7-two-keys.xml", xml);
}

// What MuJoCo alone computes in the lockstep's run: from keyframe `key`, under `integrator`, the
// harness's smooth control set at each step's start, mj_forward (whose qacc is compared) then
// mj_step (whose qpos, qvel are compared). Indexed [quantity][step][element].
struct Replay {
  std::vector<std::vector<double>> qacc, qfrc_constraint, qpos, qvel;
  const std::vector<std::vector<double>>& operator[](const std::string& quantity) const {
    if (quantity == "qacc") return qacc;
    if (quantity == "qfrc_constraint") return qfrc_constraint;
    if (quantity == "qpos") return qpos;
    REQUIRE(quantity == "qvel");
    return qvel;
  }
};

Replay replay(const std::string& file, int key, int integrator, int steps) {
  const Model model = mjcf::load_file(file);  // for the control's span, as the harness uses it
  MjModelPtr m = mujoco_load(file);
  m->opt.integrator = integrator;
  MjDataPtr d = mujoco_data(m.get());
  mj_resetDataKeyframe(m.get(), d.get(), key);
  Replay r;
  const auto copy = [](const double* x, int n) { return std::vector<double>(x, x + n); };
  Eigen::VectorXd ctrl(model.nu);
  for (int k = 0; k < steps; ++k) {
    smooth_control(model, d->time, ctrl);
    for (int a = 0; a < m->nu; ++a) d->ctrl[a] = ctrl[a];
    mj_forward(m.get(), d.get());
    r.qacc.push_back(copy(d->qacc, m->nv));
    r.qfrc_constraint.push_back(copy(d->qfrc_constraint, m->nv));
    mj_step(m.get(), d.get());
    r.qpos.push_back(copy(d->qpos, m->nq));
    r.qvel.push_back(copy(d->qvel, m->nv));
  }
  return r;
}

}  // namespace

TEST_CASE("cli: lever diff --trajectory --key: lockstep under Euler, RK4 and MuJoCo's implicit",
          "[diff][key]") {
  const std::string file = panda_with_two_keys();
  const Model model = mjcf::load_file(file);
  REQUIRE(model.nkey == 2);
  const Run run = run_lever("diff " + quoted(file) +
                            " --trajectory --key reach --json --states 2 --path loader");
  INFO(run.out);
  REQUIRE(run.status == 0);
  const json::Value out = json::parse(run.out);
  const json::Value& path = out["models"][0]["paths"][0];
  CHECK(path["path"].string == "loader");
  CHECK(path["pass"].boolean);
  CHECK(path["start"].string == "keyframe 'reach'");

  const int steps = static_cast<int>(std::lround(10.0 / model.opt.timestep));
  const int key = model.key("reach");
  const Replay euler = replay(file, key, mjINT_EULER, steps);
  const Replay rk4 = replay(file, key, mjINT_RK4, steps);
  const Replay implicit = replay(file, key, mjINT_IMPLICIT, steps);
  const std::pair<const char*, const Replay*> runs[] = {
      {"lockstep_euler", &euler}, {"lockstep_rk4", &rk4}, {"lockstep_implicit", &implicit}};
  for (const auto& [name, own] : runs) {
    INFO(name);
    const json::Value& report = path[name];
    // RK4 adds its stages' velocities; its step is compared with MuJoCo's along lever's stages
    // (lever/diff/rk4.hpp), whose values are not MuJoCo's own run's: only the forward's are
    const bool is_rk4 = own == &rk4;
    REQUIRE(report.size() == (is_rk4 ? 5u : 4u));
    for (const json::Value& q : report.array) {
      const std::string quantity = q["quantity"].string;
      INFO(quantity);
      CHECK(q["pass"].boolean);
      const int n = quantity == "qpos" ? model.nq : model.nv;
      const int per_step = quantity == "qvel at an RK4 stage" ? 3 : 1;
      CHECK(q["compared"].number == static_cast<double>(steps) * n * per_step);
      if (is_rk4 && quantity != "qacc" && quantity != "qfrc_constraint") continue;
      // MuJoCo's value where the command saw its largest ratio is this test's own MuJoCo run's
      const auto state = static_cast<size_t>(q["state"].number);
      const auto index = static_cast<size_t>(q["index"].number);
      REQUIRE(state < static_cast<size_t>(steps));
      CHECK(q["mujoco"].number == (*own)[quantity][state][index]);
    }
  }
  // and the two integrators differ there: the implicit lockstep did not run Euler
  const json::Value* qvel = nullptr;
  for (const json::Value& q : path["lockstep_implicit"].array) {
    if (q["quantity"].string == "qvel") qvel = &q;
  }
  REQUIRE(qvel != nullptr);
  const auto state = static_cast<size_t>((*qvel)["state"].number);
  const auto index = static_cast<size_t>((*qvel)["index"].number);
  CHECK(implicit.qvel[state][index] != euler.qvel[state][index]);
  std::filesystem::remove(file);
}

TEST_CASE("cli: lever diff --trajectory starts from the first keyframe without --key",
          "[diff][key]") {
  const Run run = run_lever("diff " + quoted(model_path("models/panda7.xml")) +
                            " --trajectory --json --states 1 --path engine");
  REQUIRE(run.status == 0);
  CHECK(json::parse(run.out)["models"][0]["paths"][0]["start"].string == "keyframe 'home'");
}

TEST_CASE("cli: lever diff --key refuses a keyframe the model does not have", "[diff][key]") {
  const std::string file = panda_with_two_keys();
  // exit 2 before anything is compared: nothing on standard output
  const Run quiet = run_lever("diff " + quoted(file) + " --trajectory --key nosuch");
  CHECK(quiet.status == 2);
  CHECK(quiet.out.empty());
  const Run said = run_lever("diff " + quoted(file) + " --trajectory --key nosuch", true);
  CHECK(said.status == 2);
  INFO(said.out);
  CHECK(said.out.find("--key") != std::string::npos);
  CHECK(said.out.find("'nosuch'") != std::string::npos);
  CHECK(said.out.find("'home', 'reach'") != std::string::npos);  // the model's keyframes
  // a model with no keyframes at all, among others that have it
  const Run none = run_lever("diff " + quoted(file) + " " + quoted(model_path("models/arm2.xml")) +
                                 " --trajectory --key home",
                             true);
  CHECK(none.status == 2);
  CHECK(none.out.find("arm2.xml") != std::string::npos);
  CHECK(none.out.find("no named keyframes") != std::string::npos);
  // --key only says where the trajectories start
  const Run alone = run_lever("diff " + quoted(file) + " --key home", true);
  CHECK(alone.status == 2);
  CHECK(alone.out.find("--trajectory") != std::string::npos);
  std::filesystem::remove(file);
}

// box_drop with room for two contacts: a box lying in the table makes four. MuJoCo keeps two and
// warns (on standard output, unless routed); lever refuses such a state. `lever diff` compares
// the others, says how many it skipped and why, and --json stays JSON.
TEST_CASE("lever diff skips the states with more contacts than nconmax, and --json stays JSON",
          "[cli][diff][contact]") {
  std::ifstream in(model_path("models/box_drop.xml"));
  std::stringstream text;
  text << in.rdbuf();
  std::string xml = text.str();
  const std::string option = "<option timestep=\"0.002\"/>";
  REQUIRE(xml.find(option) != std::string::npos);
  xml.insert(xml.find(option) + option.size(), "\n  <size nconmax=\"2\"/>");
  const std::string file = temporary_file("lever-diff-nconmax-2.xml", xml);
  const std::string command = "diff " + quoted(file) + " --states 40 --path engine";

  const Run json_run = run_lever(command + " --json");
  INFO(json_run.out);
  CHECK(json_run.status == 0);
  const json::Value out = json::parse(json_run.out);  // throws on anything but one JSON document
  const json::Value& path = out["models"][0]["paths"][0];
  CHECK(path["loaded"].boolean);
  CHECK(path["pass"].boolean);
  const double skipped = path["skipped_states"].number;
  CHECK(skipped > 0);
  CHECK(skipped < 40);  // the others were compared
  CHECK_THAT(path["first_skipped"].string, Catch::Contains("more than nconmax = 2 contacts"));
  CHECK_THAT(path["first_skipped"].string, !Catch::StartsWith("--key"));

  // MuJoCo warned, on standard error: standard output above was one JSON document
  const Run both = run_lever(command + " --json", true);
  CHECK_THAT(both.out, Catch::Contains("MuJoCo warns") && Catch::Contains("contact buffer"));

  const Run text_run = run_lever(command);
  CHECK(text_run.status == 0);
  CHECK_THAT(text_run.out, Catch::Contains(std::to_string(static_cast<int>(skipped)) +
                                           " of 40 random states skipped"));
  CHECK_THAT(text_run.out, !Catch::Contains("--key") && !Catch::Contains("could not load"));
}

TEST_CASE("cli: lever diff stops with a message when MuJoCo itself stops with an error",
          "[diff]") {
  // MuJoCo 2.2.2 stops with mju_error when its data stack overflows (the sample particle.xml
  // does at lever diff's random states: its particles make thousands of contacts); its default
  // handler would print "Press Enter to exit" and wait for a key. Here a stack of 1000 doubles:
  // enough to load the model (nothing touches at qpos0), too small once a random state puts
  // the boxes in contact
  const std::string xml = R"(<mujoco>
  <size nstack="1000"/>
  <worldbody>
    <geom type="plane" size="1 1 .1"/>
    <body pos="0 0 2"><freejoint/><geom type="box" size=".1 .1 .1"/></body>
    <body pos="0.5 0 3"><freejoint/><geom type="box" size=".1 .1 .1"/></body>
  </worldbody>
</mujoco>)";
  const std::string file = temporary_file("lever-diff-small-stack.xml", xml);
  const Run run = run_lever("diff --states 3 --path loader " + quoted(file) + " < /dev/null", true);
  CHECK(run.status == 2);
  CHECK_THAT(run.out, Catch::Contains("lever diff: MuJoCo 2.2.2 stopped with an error") &&
                          Catch::Contains("Stack overflow") && !Catch::Contains("Press Enter"));
}

}  // namespace lever::test
