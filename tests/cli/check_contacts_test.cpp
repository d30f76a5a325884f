// `lever check`'s section (9), lesson 5.3's hand calculations, run as a user runs them: the
// resting depth of a free body on a plane against solref/solimp's steady state, and the grip
// force two finger servos need against the force at which the simulated box slips.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include <lever/lever.hpp>
#include <lever/mjcf.hpp>

#include <lever/harness/models.hpp>
#include "json_reader.hpp"
#include "run_lever.hpp"

namespace lever::test {

namespace {

json::Value check_json(const std::string& path) {
  const Run run = run_lever("check --json " + quoted(path));
  REQUIRE((run.status == 0 || run.status == 1));
  return json::parse(run.out);
}

int geom_id(const Model& m, const std::string& name) {
  const auto at = std::find(m.geom_name.begin(), m.geom_name.end(), name);
  REQUIRE(at != m.geom_name.end());
  return static_cast<int>(at - m.geom_name.begin());
}

int body_id(const Model& m, const std::string& name) {
  const auto at = std::find(m.body_name.begin(), m.body_name.end(), name);
  REQUIRE(at != m.body_name.end());
  return static_cast<int>(at - m.body_name.begin());
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  REQUIRE(text.find(from) != std::string::npos);
  for (size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
    text.replace(at, from.size(), to);
  return text;
}

}  // namespace

TEST_CASE("check (9): a free box rests as deep as solref/solimp predict", "[check][contacts]") {
  const std::string file = model_path("models/box_drop.xml");
  const Model model = mjcf::load_file(file);
  const json::Value r = check_json(file)["contacts"]["resting_depth"];
  REQUIRE(!r.has("skipped"));
  CHECK(r["settled"].boolean);
  CHECK(r["body"].string == "box");
  CHECK(r["mass"].number == model.body_subtreemass[body_id(model, "box")]);
  // the box lands on a face: four corners, a condim-3 pyramid of four edges at each
  CHECK(r["contacts"].number == 4);
  CHECK(r["rows_per_contact"].number == 4);
  // the predicted depth balances the weight: n rows K d^2 p / ((1 - d) A) = m g, with d from
  // solimp at p (the test evaluates the balance itself, the check solved it by bisection)
  const double p = r["predicted"].number, d = r["impedance"].number;
  const double force = r["contacts"].number * r["rows_per_contact"].number * r["K"].number * d * d *
                       p / ((1 - d) * r["A"].number);
  CHECK(force == Approx(r["mass"].number * 9.81).epsilon(1e-12));
  // both geoms have the default solref/solimp, so the contact has the box geom's
  const int box = geom_id(model, "box");
  const double dmax = model.geom_solimp[box][1], timeconst = model.geom_solref[box][0];
  const double dampratio = model.geom_solref[box][1];
  CHECK(r["K"].number ==
        Approx(1 / (dmax * dmax * timeconst * timeconst * dampratio * dampratio)).epsilon(1e-14));
  // the simulation at rest: within the bound the check reasons (the speed left and the spread);
  // a bound of a millionth of the depth says the rest was reached, not assumed
  CHECK(std::abs(r["simulated"].number - p) <= r["bound"].number);
  CHECK(r["bound"].number <= 1e-6 * p);
  CHECK(r["agrees"].boolean);
}

TEST_CASE("check (9): a softer contact sinks deeper, by the same balance", "[check][contacts]") {
  // the box's timeconst 0.04 s, the table's 0.02 s: the contact's is their solmix-weighted mean
  // (equal weights: 0.03 s), K = 1 / (dmax timeconst)^2 falls to 4/9; the depth grows (not by
  // 9/4: d(p) climbs its sigmoid)
  const std::string soft = temporary_file(
      "lever_box_soft.xml", replaced(read_text(model_path("models/box_drop.xml")),
                                     "type=\"box\" size", "solref=\"0.04 1\" type=\"box\" size"));
  const json::Value stiff = check_json(model_path("models/box_drop.xml"))["contacts"];
  const json::Value r = check_json(soft)["contacts"]["resting_depth"];
  std::filesystem::remove(soft);
  CHECK(r["solref"][0].number == Approx(0.03).epsilon(1e-15));
  CHECK(r["K"].number == Approx(stiff["resting_depth"]["K"].number * 4 / 9).epsilon(1e-14));
  CHECK(r["predicted"].number > 1.5 * stiff["resting_depth"]["predicted"].number);
  CHECK(r["settled"].boolean);
  CHECK(std::abs(r["simulated"].number - r["predicted"].number) <= r["bound"].number);
}

TEST_CASE("check (9): the gripper's pairs, grip force and slip", "[check][contacts]") {
  const std::string file = model_path("models/gripper.xml");
  const Model model = mjcf::load_file(file);
  const json::Value c = check_json(file)["contacts"];
  // every tip and the box can touch the table and the box; the finger boxes and the carriage
  // (contype 0) cannot; the tips of one finger are one body
  for (const json::Value& p : c["pairs"].array) {
    CHECK(p["geom1"].string.find("finger") == std::string::npos);
    CHECK(p["geom2"].string != p["geom1"].string);
    CHECK(p["agrees"].boolean);
  }
  CHECK(c["pairs"].size() == 13);  // table with 5 geoms, box with 4 tips, 4 tip pairs across
  CHECK(c["strays"].size() == 0);

  const json::Value g = c["grip"];
  REQUIRE(!g.has("skipped"));
  CHECK(g["body"].string == "box");
  CHECK(g["fingers"].size() == 2);
  // the hand calculation from the model: mu the larger friction of tip and box, m the box
  const int tip = geom_id(model, "left_tip_front"), box = geom_id(model, "box");
  const double mu = std::max(model.geom_friction[tip][0], model.geom_friction[box][0]);
  const double m = model.body_subtreemass[body_id(model, "box")];
  const double needed = m * model.opt.gravity.norm() / (2 * mu);
  CHECK(g["mu"].number == mu);
  CHECK(g["needed_force"].number == Approx(needed).epsilon(1e-14));
  // the servo at full command: kp (command - where it holds the box), within forcerange
  const double kp = model.actuator_gainprm[1][0];
  const double servo = std::min(kp * (g["full_command"].number - g["touch"].number),
                                model.actuator_forcerange[1][1]);
  CHECK(g["servo_force"].number == Approx(servo).epsilon(1e-12));
  // at rest the servo pushes what the hand calculation says (kv = 0, the fingers stopped)
  CHECK(g["servo_force_simulated"].number == Approx(servo).epsilon(1e-6));
  CHECK(g["holds_by_hand"].boolean);
  // the touch pads on the fingers read the normal force the box presses them with: at rest, what
  // each finger's servo pushes along its slide (the box face's normal is the slide's axis)
  REQUIRE(g["pads"].size() == 2);
  for (const json::Value& p : g["pads"].array) {
    INFO(p["sensor"].string);
    CHECK(p["agrees"].boolean);
    CHECK(p["closed"].number == Approx(p["servo_closed"].number).epsilon(0.01));
    CHECK(p["closed"].number == Approx(servo).epsilon(0.01));
    CHECK(p["held"].number == Approx(p["servo_held"].number).epsilon(0.01));
  }
  CHECK(g["pads"][0]["sensor"].string == "left_touch");
  CHECK(g["pads"][0]["finger"].string == "left");
  // the simulation: held at the full grip, slipped once lowered; the slip lies within 5 % of
  // m g / (2 mu) (the check's tolerance: search resolution 1 %, the speed-up threshold 0.5 %,
  // the finger force changing while the slip is judged)
  REQUIRE(std::isfinite(g["hold_force"].number));
  REQUIRE(g["slip_force"].number > 0);
  CHECK(g["slip_force"].number <= g["hold_force"].number);
  CHECK(g["slip_force"].number < needed * 1.05);
  CHECK(g["hold_force"].number > needed * 0.95);
  bool first = true;
  for (const json::Value& t : g["trials"].array) {
    if (first) CHECK(!t["slipped"].boolean);
    first = false;
  }
}

TEST_CASE("check (9): elliptic cones: one normal row carries the weight, the grip as by hand",
          "[check][contacts]") {
  // the same two lesson models with cone="elliptic": at rest each contact's normal row alone
  // pushes (its friction rows have aref = -B v = 0), with A = t, the normal row's diagApprox
  const std::string drop = temporary_file(
      "lever_box_elliptic.xml",
      replaced(read_text(model_path("models/box_drop.xml")), "<option timestep=\"0.002\"",
               "<option cone=\"elliptic\" timestep=\"0.002\""));
  const std::string grip = temporary_file(
      "lever_gripper_elliptic.xml",
      replaced(read_text(model_path("models/gripper.xml")), "<option timestep=\"0.002\"",
               "<option cone=\"elliptic\" timestep=\"0.002\""));
  const json::Value r = check_json(drop)["contacts"]["resting_depth"];
  const json::Value g = check_json(grip)["contacts"]["grip"];
  const json::Value pyramid = check_json(model_path("models/box_drop.xml"))["contacts"];
  std::filesystem::remove(drop);
  std::filesystem::remove(grip);
  REQUIRE(!r.has("skipped"));
  CHECK(r["cone"].string == "elliptic");
  CHECK(r["rows_per_contact"].number == 1);
  CHECK(r["A"].number == r["invweight"].number);
  const double p = r["predicted"].number, d = r["impedance"].number;
  CHECK(r["contacts"].number * r["K"].number * d * d * p / ((1 - d) * r["A"].number) ==
        Approx(r["mass"].number * 9.81).epsilon(1e-12));
  CHECK(r["settled"].boolean);
  CHECK(std::abs(r["simulated"].number - p) <= r["bound"].number);
  CHECK(r["agrees"].boolean);
  // the pyramid's four edges of A = 2 mu^2 (1 + mu^2) t / impratio push as one normal row of
  // A = t when mu = 1 and impratio = 1 (4 / 4t = 1 / t): the same depth, both cones
  REQUIRE(pyramid["resting_depth"]["friction"].number == 1);
  CHECK(p == Approx(pyramid["resting_depth"]["predicted"].number).epsilon(1e-12));
  // the grip: the same hand calculation, the same 5 % (check.md)
  REQUIRE(!g.has("skipped"));
  const double needed = g["needed_force"].number;
  CHECK(g["holds_by_hand"].boolean);
  REQUIRE(g["slip_force"].number > 0);
  CHECK(g["slip_force"].number < needed * 1.05);
  CHECK(g["hold_force"].number > needed * 0.95);
}

TEST_CASE("check (9): friction too low for the finger servos is a finding", "[check][contacts]") {
  // mu 0.02: holding the 0.1 kg box needs 24.5 N, the servos' forcerange allows 10 N
  const std::string low = temporary_file("lever_gripper_slippery.xml",
                                         replaced(read_text(model_path("models/gripper.xml")),
                                                  "friction=\"1 0.005", "friction=\"0.02 0.005"));
  const Run run = run_lever("check " + quoted(low));
  const json::Value g = check_json(low)["contacts"]["grip"];
  std::filesystem::remove(low);
  CHECK(run.status == 1);
  CHECK(run.out.find("holding it needs m g / (2 mu) = 24.525 N (mu 0.02)") != std::string::npos);
  CHECK(!g["holds_by_hand"].boolean);
  // and the simulation agrees: the box slips out of the full grip
  REQUIRE(g["trials"].size() == 1);
  CHECK(g["trials"][0]["slipped"].boolean);
}

TEST_CASE("check (9): a model without contacts or fingers says what it skipped",
          "[check][contacts]") {
  const json::Value arm = check_json(model_path("models/arm2.xml"))["contacts"];
  CHECK(arm["skipped"].string == "no two geoms can touch");
  const json::Value drop = check_json(model_path("models/box_drop.xml"))["contacts"]["grip"];
  CHECK(drop["skipped"].string.find("no free body with exactly two servo-driven fingers") == 0);
}

TEST_CASE("check --svg on the gripper: the grip's trials as bars, the skipped sections drawn empty",
          "[check][contacts]") {
  const std::string svg = temporary_file("lever_check_gripper.svg", "");
  const Run run =
      run_lever("check --svg " + quoted(svg) + " " + quoted(model_path("models/gripper.xml")));
  CHECK(run.status == 1);  // the model's bodies have no <inertial>: findings, not a failure
  const std::string stem = svg.substr(0, svg.size() - 4);
  const json::Value g = check_json(model_path("models/gripper.xml"))["contacts"]["grip"];
  for (const std::string& file :
       {svg, stem + "-singular-poses.svg", stem + "-step-stability.svg", stem + "-grip.svg"}) {
    INFO(file);
    const std::string picture = read_text(file);
    CHECK(picture.rfind("<?xml", 0) == 0);
    if (file == stem + "-grip.svg") {
      // one bar per trial, labelled with its force, the slipped ones marked
      for (const json::Value& t : g["trials"].array) {
        CHECK(picture.find(format("%.3f", t["force"].number) + " N") != std::string::npos);
      }
      CHECK(picture.find(" slip") != std::string::npos);
    }
    std::filesystem::remove(file);
  }
}

TEST_CASE("docs/lesson-5.3.md's block is what lever check prints for the gripper",
          "[check][contacts]") {
  const std::string text = read_text(model_path("docs/lesson-5.3.md"));
  const size_t open = text.find("```text\n");
  REQUIRE(open != std::string::npos);
  const size_t start = open + 8, end = text.find("```", start);
  const Run run = run_lever("check " + quoted(model_path("models/gripper.xml")));
  const size_t from = run.out.find("(9) contacts");
  const size_t to = run.out.find("findings");
  REQUIRE(from != std::string::npos);
  CHECK(text.substr(start, end - start) == run.out.substr(from, to - from));
}

}  // namespace lever::test
