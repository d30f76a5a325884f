// The installed `lever` command: `lever forward` and `lever simulate` print what the engine
// computes, in mjData's names and layouts, and refuse bad input with exit status 2.
//
// The command runs from the install prefix the packaging fixture made; the expected values are
// computed here with lever (the same sources, linked directly).
#include <catch2/catch.hpp>

#include <lever/lever.hpp>
#include <lever/mjcf.hpp>

#include <lever/harness/models.hpp>

#include <sys/wait.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace {

struct Run {
  int status = -1;
  std::string out;
};

// Run a shell command; its standard output, and its exit status.
Run run(const std::string& command) {
  Run r;
  std::FILE* pipe = popen(command.c_str(), "r");
  REQUIRE(pipe != nullptr);
  std::array<char, 4096> buf{};
  size_t n = 0;
  while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0) r.out.append(buf.data(), n);
  const int status = pclose(pipe);
  r.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

std::string lever_command() { return std::string(LEVER_INSTALL_PREFIX) + "/bin/lever"; }

std::string arm2() { return lever::test::model_path("models/arm2.xml"); }

// The values of a flat JSON object as lever writes it: every key to its numbers (a number is a
// list of one; null is NaN). Strings are skipped.
std::map<std::string, std::vector<double>> parse_flat_json(const std::string& text) {
  static const std::regex member(R"re("(\w+)":(\[[^\]]*\]|[-+0-9.eE]+|null|true|false|"[^"]*"))re");
  std::map<std::string, std::vector<double>> out;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), member);
       it != std::sregex_iterator(); ++it) {
    const std::string key = (*it)[1].str();
    std::string value = (*it)[2].str();
    if (value.front() == '"') continue;
    if (value.front() == '[') value = value.substr(1, value.size() - 2);
    std::vector<double>& numbers = out[key];
    std::stringstream ss(value);
    for (std::string item; std::getline(ss, item, ',');) {
      numbers.push_back(item == "null"    ? std::numeric_limits<double>::quiet_NaN()
                        : item == "true"  ? 1.0
                        : item == "false" ? 0.0
                                          : std::stod(item));
    }
  }
  return out;
}

void check_equal(const std::map<std::string, std::vector<double>>& json, const std::string& key,
                 const std::vector<double>& expected) {
  INFO("key " << key);
  REQUIRE(json.count(key) == 1);
  const std::vector<double>& got = json.at(key);
  REQUIRE(got.size() == expected.size());
  for (size_t i = 0; i < got.size(); ++i) {
    INFO("element " << i);
    CHECK(std::abs(got[i] - expected[i]) <= 1e-12 * std::max(1.0, std::abs(expected[i])));
  }
}

template <class Rows>  // a std::vector of Eigen vectors, or a Data's array of them
std::vector<double> flat(const Rows& rows) {
  std::vector<double> out;
  for (const auto& v : rows) {
    for (Eigen::Index i = 0; i < v.size(); ++i) out.push_back(v[i]);
  }
  return out;
}

template <class Mats>  // a std::vector of Mat3, or a Data's array of them
std::vector<double> row_major(const Mats& ms) {
  std::vector<double> out;
  for (const lever::Mat3& m : ms) {
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) out.push_back(m(r, c));
    }
  }
  return out;
}

std::vector<double> vec(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }

}  // namespace

TEST_CASE("lever forward --json: mjData's names and layouts, as the engine computes them",
          "[packaging][cli]") {
  const Run r = run(lever_command() + " forward '" + arm2() +
                    "' --qpos -1.3,0.2 --qvel 0.5,-0.3 --ctrl 30,-2 --json");
  REQUIRE(r.status == 0);
  const auto json = parse_flat_json(r.out);

  const lever::Model model = lever::mjcf::load_file(arm2());
  lever::Data data(model);
  data.qpos << -1.3, 0.2;  // past the shoulder's lower stop
  data.qvel << 0.5, -0.3;
  data.ctrl << 30, -2;  // the shoulder's command is clamped to 25
  lever::forward(model, data);
  lever::compute_energy(model, data);
  REQUIRE(data.nefc == 1);

  check_equal(json, "xpos", flat(data.xpos));
  check_equal(json, "xquat", flat(data.xquat));
  check_equal(json, "xmat", row_major(data.xmat));
  check_equal(json, "xipos", flat(data.xipos));
  check_equal(json, "site_xpos", flat(data.site_xpos));
  check_equal(json, "site_xmat", row_major(data.site_xmat));
  for (const auto& [key, v] : {std::pair{"qfrc_bias", &data.qfrc_bias},
                               {"qfrc_passive", &data.qfrc_passive},
                               {"actuator_force", &data.actuator_force},
                               {"qfrc_actuator", &data.qfrc_actuator},
                               {"qacc_smooth", &data.qacc_smooth},
                               {"qacc", &data.qacc},
                               {"qfrc_constraint", &data.qfrc_constraint}}) {
    check_equal(json, key, vec(*v));
  }
  check_equal(json, "nefc", {1.0});
  check_equal(json, "efc_id", {static_cast<double>(data.efc_id[0])});
  for (const auto& [key, v] : {std::pair{"efc_pos", &data.efc_pos},
                               {"efc_force", &data.efc_force},
                               {"efc_aref", &data.efc_aref},
                               {"efc_R", &data.efc_R},
                               {"efc_D", &data.efc_D}}) {
    check_equal(json, key, {(*v)[0]});
  }
  std::vector<double> mass;
  for (int i = 0; i < model.nv; ++i) {
    for (int k = 0; k < model.nv; ++k) mass.push_back(data.M(i, k));
  }
  check_equal(json, "M", mass);
  Eigen::MatrixXd jacp(3, model.nv), jacr(3, model.nv);
  lever::jac_site(model, data, 0, jacp, jacr);
  std::vector<double> jp, jr;
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < model.nv; ++k) {
      jp.push_back(jacp(i, k));
      jr.push_back(jacr(i, k));
    }
  }
  check_equal(json, "site_jacp", jp);
  check_equal(json, "site_jacr", jr);
  check_equal(json, "energy", {data.energy[0], data.energy[1]});
  check_equal(json, "actuator_force", {25.0, -2.0});
}

TEST_CASE("lever simulate: the lab's controller, one row per state, clamping reported",
          "[packaging][cli]") {
  const lever::Model model = lever::mjcf::load_file(arm2());
  const std::string args = " --torque 5,0 --gravity-compensation --steps 500 --qpos 0.6,-1.2";

  // the same loop here: forward for qfrc_bias, ctrl = torque + qfrc_bias, forward, step
  lever::Data data(model);
  data.qpos << 0.6, -1.2;
  std::vector<std::vector<double>> rows;  // time, qpos, actuator_force, qfrc_constraint
  for (int k = 0; k <= 500; ++k) {
    lever::forward(model, data);
    data.ctrl << 5 + data.qfrc_bias[0], data.qfrc_bias[1];
    lever::forward(model, data);
    rows.push_back({data.time, data.qpos[0], data.qpos[1], data.actuator_force[0],
                    data.actuator_force[1], data.qfrc_constraint[0], data.qfrc_constraint[1]});
    if (k < 500) lever::step(model, data);
  }

  SECTION("--json: N + 1 lines, each the state and what acts on it") {
    const Run r = run(lever_command() + " simulate '" + arm2() + "'" + args + " --json");
    REQUIRE(r.status == 0);
    std::vector<std::string> lines;
    std::istringstream in(r.out);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    REQUIRE(lines.size() == rows.size());
    for (const size_t k : {size_t{0}, size_t{1}, size_t{250}, size_t{500}}) {
      const auto json = parse_flat_json(lines[k]);
      INFO("row " << k);
      check_equal(json, "time", {rows[k][0]});
      check_equal(json, "qpos", {rows[k][1], rows[k][2]});
      check_equal(json, "actuator_force", {rows[k][3], rows[k][4]});
      check_equal(json, "qfrc_constraint", {rows[k][5], rows[k][6]});
    }
  }

  SECTION("--csv and --plot: a header with names, N + 1 rows, an SVG; the clamp line on stderr") {
    const std::string dir = LEVER_PACKAGING_WORK_DIR;
    const std::string csv = dir + "/simulate.csv", svg = dir + "/simulate.svg";
    std::filesystem::remove(csv);
    std::filesystem::remove(svg);
    const Run r = run(lever_command() + " simulate '" + arm2() + "'" + args + " --csv '" + csv +
                      "' --plot '" + svg + "' 2>&1 >/dev/null");
    REQUIRE(r.status == 0);
    CHECK(r.out.empty());  // 5 N m plus compensation stays within 25 N m: nothing to report
    std::ifstream in(csv);
    std::string header;
    std::getline(in, header);
    CHECK(header.rfind("time,qpos[shoulder],qpos[elbow],qvel[shoulder]", 0) == 0);
    CHECK(header.find("qfrc_bias[shoulder]") != std::string::npos);
    CHECK(header.find("actuator_force[elbow]") != std::string::npos);
    CHECK(header.find("qfrc_constraint[shoulder]") != std::string::npos);
    int count = 0;
    for (std::string line; std::getline(in, line);) ++count;
    CHECK(count == static_cast<int>(rows.size()));
    REQUIRE(std::filesystem::exists(svg));
    std::ifstream s(svg);
    const std::string text((std::istreambuf_iterator<char>(s)), std::istreambuf_iterator<char>());
    CHECK(text.find("</svg>") != std::string::npos);
    CHECK(text.find("polyline") != std::string::npos);

    const Run clamped = run(lever_command() + " simulate '" + arm2() +
                            "' --torque 30,0 --steps 10 --csv '" + csv + "' 2>&1 >/dev/null");
    CHECK(clamped.status == 0);
    CHECK(clamped.out.find("clamped") != std::string::npos);
    CHECK(clamped.out.find("shoulder 10 of 10 steps") != std::string::npos);
    CHECK(clamped.out.find("elbow 0 of 10 steps") != std::string::npos);
  }
}

TEST_CASE("lever forward and simulate refuse bad input with exit status 2", "[packaging][cli]") {
  const std::string model = " '" + arm2() + "'";
  for (const std::string& bad : std::vector<std::string>{
           "forward" + model + " --qpos 1,2,3", "forward" + model + " --qpos nan,0",
           "forward" + model + " --ctrl x,0", "forward" + model + " --qvel 1,inf",
           "forward" + model + " --unknown", "forward", "forward no-such-model.xml",
           "simulate" + model + " --steps 5 --duration 1", "simulate" + model + " --steps -1",
           "simulate" + model + " --duration -1", "simulate" + model + " --ctrl 1,1 --torque 1,1",
           "simulate" + model + " --qpos 0.6", "simulate" + model + " --json --csv -",
           "simulate" + model + " --steps 1 --csv /no/such/dir/x.csv"}) {
    INFO("lever " << bad);
    const Run r = run(lever_command() + " " + bad + " 2>/dev/null");
    CHECK(r.status == 2);
  }
}
