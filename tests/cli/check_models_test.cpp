// `lever check` on every model of the repository, and its exit statuses: 0 when every claim
// checks out, 1 with findings, 2 when the model cannot be loaded; never a crash.
#include <catch2/catch.hpp>

#include <filesystem>
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

size_t count(const std::string& text, const std::string& piece) {
  size_t n = 0;
  for (size_t at = text.find(piece); at != std::string::npos; at = text.find(piece, at + 1)) ++n;
  return n;
}

}  // namespace

TEST_CASE("check: every model loads, exits 0 or 1, and --json agrees with the text", "[check]") {
  for (const std::string& file : all_model_files()) {
    SECTION(std::filesystem::path(file).filename().string()) {
      const Run text = run_lever("check " + quoted(file));
      INFO(text.out);
      const Model model = mjcf::load_file(file);
      // a floating body or a ball joint: the sections that vary hinges and slides say they skip
      const bool floating = model.nq != model.nv;
      CHECK((text.status == 0 || text.status == 1));
      for (const char* section : {"(1)", "(2)", "(3)", "(4)", "(5)", "(6)", "(7)", "(8)", "(9)"}) {
        CHECK(text.out.find(std::string("\n") + section + " ") != std::string::npos);
      }
      for (const char* section : {"(2)", "(3)", "(5)", "(7)", "(8)"}) {
        const size_t at = text.out.find(std::string("\n") + section + " ");
        const size_t end = text.out.find('\n', at + 1);
        const bool skipped = text.out.substr(at, end - at).find(": skipped: ") != std::string::npos;
        CHECK(skipped == floating);
      }
      const Run data = run_lever("check --json " + quoted(file));
      CHECK(data.status == text.status);
      const json::Value report = json::parse(data.out);  // throws if it is not JSON
      CHECK(report["exit_status"].number == text.status);
      const size_t findings = report["findings"].size();
      CHECK((findings == 0) == (text.status == 0));
      CHECK(count(text.out, "\n  - ") == findings);
      for (const json::Value& finding : report["findings"].array) {
        CHECK(text.out.find(finding.string) != std::string::npos);
      }
      if (floating) {
        for (const char* section :
             {"kinematics", "torque_budget", "soft_stops", "singular_poses", "step_stability"}) {
          CHECK(report[section]["skipped"].string.find("ball or free joints") != std::string::npos);
        }
      } else {
        CHECK(report["torque_budget"]["joints"].size() == static_cast<size_t>(model.njnt));
      }
    }
  }
}

TEST_CASE("check: a motor that cannot hold its own arm is a finding (exit 1)", "[check]") {
  // arm2 with the shoulder motor limited to 6 N m, less than the 7.946 N m the straight arm weighs
  std::string xml = read_text(model_path("models/arm2.xml"));
  const std::string from = "ctrlrange=\"-25 25\"";
  REQUIRE(xml.find(from) != std::string::npos);
  xml.replace(xml.find(from), from.size(), "ctrlrange=\"-6 6\"");
  const std::string path = temporary_file("lever_check_weak_shoulder.xml", xml);
  const Model model = mjcf::load_file(path);
  Data data(model);
  data.qpos.setZero();
  forward(model, data);  // the worst pose is the arm horizontal
  const double ratio = 6.0 / data.qfrc_bias[0];

  const Run run = run_lever("check " + quoted(path));
  INFO(run.out);
  CHECK(run.status == 1);
  CHECK(run.out.find("joint shoulder: its motor cannot hold its own arm") != std::string::npos);
  CHECK(run.out.find("(ratio " + format("%.2f", ratio) + ")") != std::string::npos);
  CHECK(run.out.find("motor limit / gravity torque: shoulder " + format("%.2f", ratio)) !=
        std::string::npos);
  const json::Value report = json::parse(run_lever("check --json " + quoted(path)).out);
  CHECK(report["exit_status"].number == 1);
  REQUIRE(report["findings"].size() == 1);
  CHECK(report["findings"][0].string.find("cannot hold its own arm") != std::string::npos);
  std::filesystem::remove(path);
}

TEST_CASE("check: with position servos, ctrl 0 in the stop runs is a target of 0, not zero torque",
          "[check]") {
  // arm2 with its shoulder motor made a position servo: its ctrl is a target angle
  std::string xml = read_text(model_path("models/arm2.xml"));
  const std::string from = "<motor name=\"shoulder\" joint=\"shoulder\" ctrlrange=\"-25 25\"/>";
  REQUIRE(xml.find(from) != std::string::npos);
  xml.replace(xml.find(from), from.size(),
              "<position name=\"shoulder\" joint=\"shoulder\" kp=\"200\" ctrlrange=\"-2 2\"/>");
  const std::string path = temporary_file("lever_check_shoulder_servo.xml", xml);
  const Run run = run_lever("check " + quoted(path));
  INFO(run.out);
  const size_t at = run.out.find("\n(5) ");
  const size_t end = run.out.find("\n(6) ");
  REQUIRE(at != std::string::npos);
  const std::string section = run.out.substr(at, end - at);
  CHECK(section.find("(zero torque") == std::string::npos);
  CHECK(section.find("with zero torque") == std::string::npos);
  CHECK(section.find("(ctrl 0: relaxed") != std::string::npos);
  CHECK(section.find("ctrl 0 is a target of 0") != std::string::npos);
  CHECK(section.find(": shoulder (0 rad)\n") != std::string::npos);  // the elbow is a motor
  CHECK(section.find("with ctrl 0") != std::string::npos);
  std::filesystem::remove(path);
  // arm2 as it is, motors only: zero torque
  const Run motors = run_lever("check " + quoted(model_path("models/arm2.xml")));
  CHECK(motors.out.find("(5) joint stops are soft constraints (zero torque: ") !=
        std::string::npos);
  CHECK(motors.out.find("ctrl 0 is not zero torque") == std::string::npos);
}

TEST_CASE("check: a model that cannot be loaded exits 2 with the loader's message", "[check]") {
  const std::string path = temporary_file(
      "lever_check_bad.xml",
      "<mujoco>\n<worldbody>\n<body>\n<joint rnage=\"0 1\"/>\n</body>\n</worldbody>\n</mujoco>\n");
  const Run run = run_lever("check " + quoted(path), true);
  CHECK(run.status == 2);
  CHECK(run.out.find("lever_check_bad.xml:4: error:") != std::string::npos);
  CHECK(run.out.find("rnage") != std::string::npos);
  CHECK(run_lever("check " + quoted(path + ".missing")).status == 2);
  std::filesystem::remove(path);
}

TEST_CASE("check: a user actuator (a callback's force) exits 2 naming it", "[check]") {
  const std::string path = temporary_file(
      "lever_check_user.xml",
      "<mujoco>\n<worldbody>\n<body><joint name=\"j\" range=\"-1 1\" limited=\"true\"/>\n"
      "<geom type=\"capsule\" size=\"0.05\" fromto=\"0 0 0 0.3 0 0\"/></body>\n</worldbody>\n"
      "<actuator><general name=\"custom\" joint=\"j\" biastype=\"user\"/></actuator>\n"
      "</mujoco>\n");
  const Run run = run_lever("check " + quoted(path), true);
  CHECK(run.status == 2);
  CHECK(run.out.find("lever check: actuator 'custom' has biastype \"user\"") !=
        std::string::npos);
  std::filesystem::remove(path);
}

TEST_CASE("check: --help, usage errors and --svg", "[check]") {
  const Run help = run_lever("check --help");
  CHECK(help.status == 0);
  CHECK(help.out.find("Usage: lever check [OPTIONS] MODEL") != std::string::npos);
  CHECK(run_lever("check").status == 2);
  CHECK(run_lever("check --no-such-option " + quoted(model_path("models/arm2.xml"))).status == 2);

  const std::string svg =
      (std::filesystem::temp_directory_path() / "lever_check_arm2.svg").string();
  CHECK(run_lever("check --svg " + quoted(svg) + " " + quoted(model_path("models/arm2.xml")))
            .status == 0);
  const std::string picture = read_text(svg);
  CHECK(picture.rfind("<?xml", 0) == 0);
  const Model model = mjcf::load_file(model_path("models/arm2.xml"));
  Data data(model);
  data.qpos.setZero();
  forward(model, data);  // the arm horizontal, where gravity loads the shoulder most
  const double ratio = model.actuator_ctrlrange[0][1] / data.qfrc_bias[0];
  CHECK(picture.find("shoulder " + format("%.2f", ratio) + "x") != std::string::npos);
  std::filesystem::remove(svg);
}

}  // namespace lever::test
