// lever derivatives and lever identify as a user runs them: the JSON matches the library's
// numbers exactly (printed with 17 digits), and a run excited by `lever simulate --excite`
// identifies the model it came from.
#include <catch2/catch.hpp>

#include <lever/derivatives.hpp>
#include <lever/lever.hpp>
#include <lever/mjcf.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <lever/harness/models.hpp>

#include "json_reader.hpp"
#include "run_lever.hpp"

namespace lever::test {

TEST_CASE("cli: lever derivatives --json holds the library's A and B", "[cli][derivatives]") {
  const std::string arm2 = model_path("models/arm2.xml");
  const Run run = run_lever("derivatives " + quoted(arm2) + " --qpos 0.6,-1.2 --qvel 0.3,-0.4 " +
                            "--ctrl 2,40 --json");
  REQUIRE(run.status == 0);
  const json::Value out = json::parse(run.out);
  const Model model = mjcf::load_file(arm2);
  Data data(model);
  Derivatives deriv(model);
  data.qpos << 0.6, -1.2;
  data.qvel << 0.3, -0.4;
  data.ctrl << 2, 40;  // the elbow's 40 is clamped to 15: its B column is zero
  step_derivatives(model, data, deriv);
  const json::Value& A = out["A"];
  const json::Value& B = out["B"];
  REQUIRE(A.size() == 16);
  REQUIRE(B.size() == 8);
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c)
      CHECK(A[static_cast<std::size_t>(4 * r + c)].number == deriv.A(r, c));
    for (int c = 0; c < 2; ++c)
      CHECK(B[static_cast<std::size_t>(2 * r + c)].number == deriv.B(r, c));
    CHECK(B[static_cast<std::size_t>(2 * r + 1)].number == 0.0);
  }
  CHECK(run_lever("derivatives " + quoted(arm2) + " --qpos 1,2,3").status == 2);
}

TEST_CASE("cli: lever derivatives on panda7 (position servos, implicit integrator)",
          "[cli][derivatives]") {
  // at the home keyframe's pose with the servos' targets a little off it (no force clamped):
  // the step's A and B under MuJoCo's implicit integrator, as the library computes them
  const std::string panda7 = model_path("models/panda7.xml");
  const std::string qpos = "0,0,0,-1.57079,0,1.57079,-0.7853";
  const std::string ctrl = "0.001,-0.002,0.001,-1.569,0.002,1.5715,-0.786";
  const Run run = run_lever("derivatives " + quoted(panda7) + " --qpos " + qpos +
                            " --qvel 0.01,0,0,0,0,0,-0.01 --ctrl " + ctrl + " --json");
  REQUIRE(run.status == 0);
  const json::Value out = json::parse(run.out);
  CHECK(out["integrator"].string == "implicit");
  const Model model = mjcf::load_file(panda7);
  Data data(model);
  Derivatives deriv(model);
  data.qpos << 0, 0, 0, -1.57079, 0, 1.57079, -0.7853;
  data.qvel << 0.01, 0, 0, 0, 0, 0, -0.01;
  data.ctrl << 0.001, -0.002, 0.001, -1.569, 0.002, 1.5715, -0.786;
  step_derivatives(model, data, deriv);
  const json::Value& A = out["A"];
  const json::Value& B = out["B"];
  REQUIRE(A.size() == 14 * 14);
  REQUIRE(B.size() == 14 * 7);
  for (int r = 0; r < 14; ++r) {
    for (int c = 0; c < 14; ++c)
      CHECK(A[static_cast<std::size_t>(14 * r + c)].number == deriv.A(r, c));
    for (int c = 0; c < 7; ++c)
      CHECK(B[static_cast<std::size_t>(7 * r + c)].number == deriv.B(r, c));
  }
  // the servos pass ctrl on (no clamp binds): d qvel'_i / d ctrl_i is positive on every joint
  for (int i = 0; i < 7; ++i) CHECK(deriv.B(7 + i, i) > 0);
}

TEST_CASE("cli: lever identify recovers the model an excited run came from",
          "[cli][derivatives][identify]") {
  const std::string arm2 = model_path("models/arm2.xml");
  const std::string csv =
      (std::filesystem::temp_directory_path() / "lever_cli_identify.csv").string();
  const std::string written =
      (std::filesystem::temp_directory_path() / "lever_cli_identified.xml").string();
  REQUIRE(run_lever("simulate " + quoted(arm2) + " --excite 0.8 --duration 4 --csv " + quoted(csv))
              .status == 0);
  const Run run = run_lever("identify " + quoted(arm2) + " " + quoted(csv) + " --json " +
                            "--write-model " + quoted(written));
  REQUIRE(run.status == 0);  // every base parameter excited, a physical model written
  const json::Value out = json::parse(run.out);
  const json::Value& base = out["base"];
  REQUIRE(base.size() == 9);
  for (std::size_t k = 0; k < base.size(); ++k) {
    INFO(base[k].str("name"));
    const double prior = base[k]["prior"].number, estimate = base[k]["estimate"].number;
    // 1e-8: the recovery target for noise-free data (a least-squares fit over a
    // conditioned regressor, not two evaluations of one quantity: not the 1e-12 agreement bound)
    CHECK(std::abs(estimate - prior) <= 1e-8 * std::max(1.0, std::abs(prior)));
  }
  CHECK(out["unexcited"].size() == 0);
  // the written model is arm2 again
  const Model original = mjcf::load_file(arm2), identified = mjcf::load_file(written);
  for (int b = 1; b < original.nbody; ++b) {
    CHECK(std::abs(identified.body_mass[b] - original.body_mass[b]) <= 1e-8);
  }
  // a file from another model is refused with the column it lacks
  const Run other =
      run_lever("identify " + quoted(model_path("models/arm3.xml")) + " " + quoted(csv), true);
  CHECK(other.status == 2);
  CHECK_THAT(other.out, Catch::Contains("no column 'qpos[wrist]'"));
  std::filesystem::remove(csv);
  std::filesystem::remove(written);
}

TEST_CASE("cli: lever identify --identify-gain finds a motor's gain",
          "[cli][derivatives][identify]") {
  // arm2 whose elbow motor is 1.3 times as strong as arm2.xml says, excited by `lever simulate`;
  // identified from arm2.xml with the elbow's gain estimated (the shoulder's known fixes the scale)
  const std::string arm2 = model_path("models/arm2.xml");
  const auto temp = [](const std::string& name) {
    return (std::filesystem::temp_directory_path() / ("lever_cli_gain_" + name)).string();
  };
  std::stringstream text;
  text << std::ifstream(arm2).rdbuf();
  std::string xml = text.str();
  const std::string motor = "<motor name=\"elbow\" joint=\"elbow\"";
  const auto at = xml.find(motor);
  REQUIRE(at != std::string::npos);
  xml.replace(at, motor.size(),
              "<general name=\"elbow\" joint=\"elbow\" gainprm=\"1.3\" gear=\"1\"");
  const std::string truth = temp("truth.xml"), csv = temp("run.csv"), written = temp("out.xml");
  std::ofstream(truth) << xml;
  REQUIRE(run_lever("simulate " + quoted(truth) + " --excite 0.8 --duration 4 --csv " + quoted(csv))
              .status == 0);
  const Run run = run_lever("identify " + quoted(arm2) + " " + quoted(csv) +
                            " --identify-gain elbow --json --write-model " + quoted(written));
  INFO(run.out);
  REQUIRE(run.status == 0);
  const json::Value out = json::parse(run.out);
  REQUIRE(out["gains"].size() == 1);
  CHECK(out["gains"][0].string == "elbow");
  CHECK(out["dropped"].number == 0);
  bool found = false;
  for (std::size_t k = 0; k < out["base"].size(); ++k) {
    if (out["base"][k].str("name") != "elbow.gain") continue;
    found = true;
    CHECK(std::abs(out["base"][k]["estimate"].number - 1.3) <= 1e-8);
  }
  CHECK(found);
  const Model identified = mjcf::load_file(written);
  CHECK(std::abs(identified.actuator_gainprm[1][0] - 1.3) <= 1e-8);
  // all gains: nothing absolute is left, a clear error (exit 2)
  const Run all =
      run_lever("identify " + quoted(arm2) + " " + quoted(csv) + " --identify-gain all", true);
  CHECK(all.status == 2);
  CHECK_THAT(all.out, Catch::Contains("scale together"));
  for (const std::string& f : {truth, csv, written}) std::filesystem::remove(f);
}

TEST_CASE("cli: lever identify --known-mass pins the scale for every gain",
          "[cli][derivatives][identify]") {
  // arm2 whose motors are 1.3 and 0.8 times as strong as arm2.xml says and whose link 2 weighs
  // 1.6 kg (twice the prior's, same shape): with every gain estimated the command refuses
  // (nothing absolute), and with --known-mass link2=1.6 it recovers both gains
  const std::string arm2 = model_path("models/arm2.xml");
  const auto temp = [](const std::string& name) {
    return (std::filesystem::temp_directory_path() / ("lever_cli_known_" + name)).string();
  };
  std::stringstream text;
  text << std::ifstream(arm2).rdbuf();
  std::string xml = text.str();
  const auto replace = [&](const std::string& from, const std::string& to) {
    const auto at = xml.find(from);
    REQUIRE(at != std::string::npos);
    xml.replace(at, from.size(), to);
  };
  replace("<motor name=\"shoulder\" joint=\"shoulder\"",
          "<general name=\"shoulder\" joint=\"shoulder\" gainprm=\"1.3\"");
  replace("<motor name=\"elbow\" joint=\"elbow\"",
          "<general name=\"elbow\" joint=\"elbow\" gainprm=\"0.8\"");
  replace("mass=\"0.8\" diaginertia=\"0.0001 0.0106666666666667 0.0106666666666667\"",
          "mass=\"1.6\" diaginertia=\"0.0002 0.0213333333333334 0.0213333333333334\"");
  const std::string truth = temp("truth.xml"), csv = temp("run.csv"), written = temp("out.xml");
  std::ofstream(truth) << xml;
  REQUIRE(run_lever("simulate " + quoted(truth) + " --excite 0.8 --duration 4 --csv " + quoted(csv))
              .status == 0);
  const std::string command =
      "identify " + quoted(arm2) + " " + quoted(csv) + " --identify-gain all";
  CHECK(run_lever(command, true).status == 2);  // the scale is not pinned
  const Run run =
      run_lever(command + " --known-mass link2=1.6 --json --write-model " + quoted(written));
  INFO(run.out);
  REQUIRE(run.status == 0);
  const json::Value out = json::parse(run.out);
  REQUIRE(out["known_masses"].size() == 1);
  CHECK(out["known_masses"][0].str("body") == "link2");
  CHECK(out["known_masses"][0]["mass"].number == 1.6);
  CHECK(out["estimate_physical"].boolean);
  // noise-free data: the physical fit keeps the exact fit, so its residual is rounding (N m)
  CHECK(out["physical_residual_rms"].number < 1e-9);
  int gains = 0;
  for (std::size_t k = 0; k < out["base"].size(); ++k) {
    const json::Value& p = out["base"][k];
    const double want = p.str("name") == "shoulder.gain" ? 1.3 : 0.8;
    if (p.str("name") != "shoulder.gain" && p.str("name") != "elbow.gain") continue;
    ++gains;
    CHECK(std::abs(p["estimate"].number - want) <= 1e-8);  // the noise-free target
    CHECK(std::abs(p["physical"].number - want) <= 1e-8);
  }
  CHECK(gains == 2);
  const Model identified = mjcf::load_file(written);
  CHECK(std::abs(identified.actuator_gainprm[0][0] - 1.3) <= 1e-8);
  CHECK(std::abs(identified.actuator_gainprm[1][0] - 0.8) <= 1e-8);
  CHECK(std::abs(identified.body_mass[2] - 1.6) <= 1e-12);
  // the text names the known mass and says the estimate is physical
  const Run text_run = run_lever(command + " --known-mass link2=1.6");
  CHECK_THAT(text_run.out, Catch::Contains("known: link2's mass 1.6 kg"));
  CHECK_THAT(text_run.out, Catch::Contains("least-squares estimate is a rigid-body model's"));
  // a body that is not there
  const Run bad = run_lever(command + " --known-mass link9=1", true);
  CHECK(bad.status == 2);
  CHECK_THAT(bad.out, Catch::Contains("no body 'link9'"));
  for (const std::string& f : {truth, csv, written}) std::filesystem::remove(f);
}

TEST_CASE("cli: lever identify says when the estimate is not physical and how far the fit moved",
          "[cli][derivatives][identify]") {
  // panda7 whose hand is nearly a point mass (inertia about its centre a fiftieth of the
  // prior's), excited by `lever simulate --excite`, its actuator_force columns given 1 N m of
  // Gaussian noise: the least-squares estimate leaves the physical set, the command says so
  // with the residual before and after, and writes the physical fit
  const std::string panda7 = model_path("models/panda7.xml");
  const auto temp = [](const std::string& name) {
    return (std::filesystem::temp_directory_path() / ("lever_cli_noisy_" + name)).string();
  };
  std::stringstream text;
  text << std::ifstream(panda7).rdbuf();
  std::string xml = text.str();
  const std::string hand =
      "fullinertia=\"1.2516e-2 1.0027e-2 4.815e-3 -4.28e-4 -1.196e-3 -7.41e-4\"";
  const auto at = xml.find(hand);
  REQUIRE(at != std::string::npos);
  xml.replace(at, hand.size(),
              "fullinertia=\"2.5032e-4 2.0054e-4 9.63e-5 -8.56e-6 -2.392e-5 -1.482e-5\"");
  const std::string truth = temp("truth.xml"), clean = temp("clean.csv"), noisy = temp("run.csv"),
                    written = temp("out.xml");
  std::ofstream(truth) << xml;
  REQUIRE(
      run_lever("simulate " + quoted(truth) + " --excite 0.4 --duration 10 --csv " + quoted(clean))
          .status == 0);
  {  // the noise, on every actuator_force column
    std::ifstream in(clean);
    std::ofstream out(noisy);
    out.precision(17);
    std::string line;
    std::getline(in, line);
    out << line << "\n";
    std::vector<bool> force;
    std::stringstream header(line);
    for (std::string name; std::getline(header, name, ',');) {
      force.push_back(name.rfind("actuator_force[", 0) == 0);
    }
    std::mt19937_64 rng(1);
    std::normal_distribution<double> normal(0.0, 1.0);
    while (std::getline(in, line)) {
      std::stringstream fields(line);
      std::size_t column = 0;
      for (std::string field; std::getline(fields, field, ','); ++column) {
        if (column > 0) out << ",";
        if (column < force.size() && force[column]) {
          out << std::stod(field) + normal(rng);
        } else {
          out << field;
        }
      }
      out << "\n";
    }
  }
  const std::string command = "identify " + quoted(panda7) + " " + quoted(noisy);
  const Run run = run_lever(command + " --json --write-model " + quoted(written));
  REQUIRE(run.status == 0);
  const json::Value out = json::parse(run.out);
  CHECK_FALSE(out["estimate_physical"].boolean);
  const double before = out["residual_rms"].number, after = out["physical_residual_rms"].number;
  CHECK(before == Approx(1.0).epsilon(0.05));  // the noise's rms
  CHECK(after > before);
  CHECK(after < 1.01 * before);
  bool moved = false;
  for (std::size_t k = 0; k < out["base"].size(); ++k) {
    moved = moved || out["base"][k]["physical"].number != out["base"][k]["estimate"].number;
  }
  CHECK(moved);
  CHECK(out["not_physical"].kind == json::Value::Kind::kNull);
  const Model identified = mjcf::load_file(written);  // physical, or it would not load
  CHECK(identified.nbody == 9);
  const Run text_run = run_lever(command);
  CHECK_THAT(text_run.out, Catch::Contains("the least-squares estimate is NOT a rigid-body "
                                           "model's; the nearest physical fit raises the "
                                           "residual rms from"));
  CHECK_THAT(text_run.out, Catch::Contains("moved (SE)"));
  for (const std::string& f : {truth, clean, noisy, written}) std::filesystem::remove(f);
}

}  // namespace lever::test
