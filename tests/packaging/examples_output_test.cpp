// The lesson programs in examples/, built against the installed lever, print what lever computes.
//
// Each test runs one program (from the separate examples build the fixture made), finds each
// line of its output by a phrase, reads every number on it, and compares them in order with the
// values computed here with lever, to the digits printed: a number printed with d decimals must
// lie within half a unit of its last digit. No expected value is typed in. The two rounding-noise
// figures of lesson 5.1 (forward kinematics and gravity torque against the formulas) are checked
// to be rounding noise, below 1e-12.
#include <catch2/catch.hpp>

#include <Eigen/Core>

#include <lever/lever.hpp>
#include <lever/mjcf.hpp>

#include <lever/harness/models.hpp>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "spectra.hpp"

namespace {

// ---- running a program and reading its output -------------------------------------------------

struct Run {
  int status = -1;
  std::vector<std::string> lines;
};

Run run(const std::string& command) {
  Run r;
  std::FILE* pipe = popen(command.c_str(), "r");
  REQUIRE(pipe != nullptr);
  std::string text;
  std::array<char, 4096> buf{};
  size_t n = 0;
  while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0) text.append(buf.data(), n);
  r.status = pclose(pipe);
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) r.lines.push_back(line);
  return r;
}

std::string example(const std::string& name) {
  return std::string(LEVER_EXAMPLES_BINARY_DIR) + "/" + name;
}

/// A number as printed, and half a unit of its last printed digit.
struct Printed {
  double value;
  double half_unit;
  std::string text;
};

/// Where a number stands on its own on a line: after the line's start, a space, a bracket, a
/// comma, '=', '>' or a quote, so that the 1 in "link1" or the 2 in "m^2" are not numbers.
/// A number is -?D+(.D+)?(e[-+]?D+)? (D a digit); `decimals` and `exponent` are as printed.
struct NumberSpan {
  std::size_t begin, end;
  int decimals, exponent;
};

std::vector<NumberSpan> number_spans(const std::string& line) {
  const auto digit = [&](std::size_t i) {
    return i < line.size() && std::isdigit(static_cast<unsigned char>(line[i]));
  };
  const auto digits_from = [&](std::size_t i) {
    while (digit(i)) ++i;
    return i;
  };
  const auto opens = [&](std::size_t i) {  // may a number start at i?
    if (i == 0) return true;
    const char c = line[i - 1];
    return std::isspace(static_cast<unsigned char>(c)) ||
           (c != '\0' && std::strchr("([,=>\"", c) != nullptr);
  };
  std::vector<NumberSpan> spans;
  std::size_t i = 0;
  while (i < line.size()) {
    const std::size_t first_digit = line[i] == '-' ? i + 1 : i;
    if (!opens(i) || !digit(first_digit)) {
      ++i;
      continue;
    }
    NumberSpan n{i, digits_from(first_digit), 0, 0};
    if (n.end < line.size() && line[n.end] == '.' && digit(n.end + 1)) {
      const std::size_t after = digits_from(n.end + 1);
      n.decimals = static_cast<int>(after - n.end - 1);
      n.end = after;
    }
    if (n.end < line.size() && line[n.end] == 'e') {
      const std::size_t sign = n.end + 1;
      const std::size_t first =
          sign < line.size() && (line[sign] == '-' || line[sign] == '+') ? sign + 1 : sign;
      if (digit(first)) {
        const std::size_t after = digits_from(first);
        n.exponent = std::stoi(line.substr(sign, after - sign));
        n.end = after;
      }
    }
    spans.push_back(n);
    i = n.end;
  }
  return spans;
}

/// Every number on a line that stands on its own (number_spans).
std::vector<Printed> numbers_in(const std::string& line) {
  std::vector<Printed> out;
  for (const NumberSpan& n : number_spans(line)) {
    const std::string text = line.substr(n.begin, n.end - n.begin);
    out.push_back({std::stod(text), 0.5 * std::pow(10.0, n.exponent - n.decimals), text});
  }
  return out;
}

/// The one line that contains `phrase`.
const std::string& line_with(const Run& r, const std::string& phrase) {
  const std::string* found = nullptr;
  int count = 0;
  for (const std::string& line : r.lines) {
    if (line.find(phrase) != std::string::npos) {
      found = &line;
      ++count;
    }
  }
  INFO("looking for a line with: " << phrase);
  REQUIRE(count == 1);
  return *found;
}

/// The numbers on the line with `phrase` are `expected`, to the digits printed.
void check_line(const Run& r, const std::string& phrase, const std::vector<double>& expected) {
  const std::string& line = line_with(r, phrase);
  const std::vector<Printed> printed = numbers_in(line);
  INFO("line: " << line);
  REQUIRE(printed.size() == expected.size());
  for (size_t i = 0; i < printed.size(); ++i) {
    INFO("number " << i << " printed " << printed[i].text << ", lever computes " << expected[i]);
    CHECK(std::abs(printed[i].value - expected[i]) <= printed[i].half_unit * (1 + 1e-9) + 1e-12);
  }
}

double round_to(double x, int decimals) {
  const double scale = std::pow(10.0, decimals);
  return std::round(x * scale) / scale;
}

std::vector<double> sorted(const Eigen::Vector3d& v) {
  std::vector<double> s(v.data(), v.data() + 3);
  std::sort(s.begin(), s.end());
  return s;
}

// ---- lever's own values ------------------------------------------------------------------------

/// Link lengths of a planar chain in its horizontal pose (qpos0 = 0), from the model: joint to
/// joint, and the last joint to the ee site.
std::vector<double> link_lengths(const lever::Model& model) {
  lever::Data data(model);
  lever::kinematics(model, data);
  std::vector<Eigen::Vector3d> points;
  points.reserve(static_cast<size_t>(model.njnt) + 1);
  for (int j = 0; j < model.njnt; ++j) points.push_back(data.xpos[model.jnt_bodyid[j]]);
  points.push_back(data.site_xpos[model.site("ee")]);
  std::vector<double> lengths;
  for (size_t i = 0; i + 1 < points.size(); ++i)
    lengths.push_back((points[i + 1] - points[i]).norm());
  return lengths;
}

}  // namespace

TEST_CASE("l5_1_two_link prints lesson 5.1's output, every number as lever computes it",
          "[packaging]") {
  const Run out = run(example("l5_1_two_link"));  // no argument: the installed arm2.xml
  REQUIRE(out.status == 0);

  const std::string path = lever::test::model_path("models/arm2.xml");
  const lever::Model model = lever::mjcf::load_file(path);
  lever::Data data(model);
  const double g = -model.opt.gravity.z();

  // (1) structure
  for (int j = 0; j < model.njnt; ++j) {
    const Eigen::Vector3d& axis = model.jnt_axis[j];
    check_line(out, "joint " + model.jnt_name[j] + " ",
               {axis.x(), axis.y(), axis.z(), model.jnt_range[j][0], model.jnt_range[j][1],
                model.dof_damping[model.jnt_dofadr[j]]});
  }
  for (int a = 0; a < model.nu; ++a) {
    check_line(out, "motor " + model.actuator_name[a] + " ",
               {model.actuator_gear[a][0], model.actuator_ctrlrange[a][0],
                model.actuator_ctrlrange[a][1]});
  }
  CHECK(line_with(out, "sites:").find(model.site_name[0]) != std::string::npos);

  // (2) and (3): agreement with the formulas is rounding noise
  for (const char* phrase : {"max |site_xpos - formula|", "max |qfrc_bias - formula|"}) {
    const std::vector<Printed> printed = numbers_in(line_with(out, phrase));
    REQUIRE(!printed.empty());
    CHECK(printed.back().value < 1e-12);
  }

  // (3) the horizontal pose: gravity torque, ratios, payload, M, acceleration
  data.qpos.setZero();
  data.qvel.setZero();
  lever::forward(model, data);
  const Eigen::Vector2d tau = data.qfrc_bias;
  const Eigen::Vector2d limit(model.actuator_ctrlrange[0][1], model.actuator_ctrlrange[1][1]);
  const std::vector<double> length = link_lengths(model);
  const double reach = length[0] + length[1];
  check_line(out, "gravity torque, arm horizontal:", {tau[0], tau[1]});
  check_line(out, "motor limit / gravity torque:", {limit[0] / tau[0], limit[1] / tau[1]});
  const double payload_shoulder = (limit[0] - tau[0]) / (g * reach);
  const double payload_elbow = (limit[1] - tau[1]) / (g * length[1]);
  check_line(out, "largest point payload",
             {payload_shoulder, payload_elbow, std::min(payload_shoulder, payload_elbow)});
  check_line(out, "M(q) at this pose:",
             {round_to(data.M(0, 0), 4), round_to(data.M(0, 1), 4), round_to(data.M(1, 0), 4),
              round_to(data.M(1, 1), 4)});
  const double acc = (limit[0] - tau[0]) / data.M(0, 0);
  check_line(out, "spare shoulder torque", {limit[0] - tau[0], acc, data.M(1, 0) * acc + tau[1]});

  // (4) inertias inferred from the geoms
  const lever::Model inferred =
      lever::mjcf::load_file(path, lever::mjcf::LoadOptions{.infer_inertia_from_geoms = true});
  for (const char* name : {"link1", "link2"}) {
    const int a = model.body(name), b = inferred.body(name);
    std::vector<double> expected{model.body_mass[a]};
    for (const double x : sorted(model.body_inertia[a])) expected.push_back(round_to(x, 5));
    expected.push_back(inferred.body_mass[b]);
    for (const double x : sorted(inferred.body_inertia[b])) expected.push_back(round_to(x, 5));
    check_line(out, std::string(name) + ": explicit", expected);
  }
  lever::Data inferred_data(inferred);
  lever::forward(inferred, inferred_data);
  check_line(out, "gravity torque at the horizontal pose:", {tau[0], inferred_data.qfrc_bias[0]});

  // (4) a visual-only geom: built here the same way, loaded with lever
  for (const bool narrow : {false, true}) {
    const lever::Model m = lever::mjcf::load_string(
        std::string("<mujoco>") + (narrow ? "<compiler inertiagrouprange='0 2'/>" : "") +
        "<worldbody><body name='b'><joint type='slide' axis='0 0 1'/>"
        "<geom type='box' size='0.05 0.05 0.05' mass='1'/>"
        "<geom type='sphere' size='0.05' mass='2' contype='0' conaffinity='0' group='3'/>"
        "</body></worldbody></mujoco>");
    check_line(out, narrow ? "inertiagrouprange=\"" : "default inertiagrouprange",
               {m.geom_mass[0], m.geom_mass[1], static_cast<double>(m.geom_group[1]),
                static_cast<double>(m.compiler.inertiagrouprange[0]),
                static_cast<double>(m.compiler.inertiagrouprange[1]), m.body_mass[m.body("b")]});
  }

  // (5) 60 s with zero torque: resting on the shoulder stop
  lever::reset(model, data);
  const double seconds = 60.0;
  for (long i = 0; i < std::lround(seconds / model.opt.timestep); ++i) lever::step(model, data);
  const double lo = model.jnt_range[0][0];
  check_line(
      out, "after 60 s with zero torque:", {seconds, data.qpos[0], lo, 1000 * (lo - data.qpos[0])});
  check_line(out, "active limit rows:",
             {static_cast<double>(data.nefc), data.qfrc_constraint[0], data.qfrc_bias[0]});

  // (6) clamping
  lever::reset(model, data);
  data.ctrl << 100.0, -100.0;
  lever::forward(model, data);
  check_line(out, "actuator_force =",
             {data.ctrl[0], data.ctrl[1], data.actuator_force[0], data.actuator_force[1]});
}

TEST_CASE("l5_1_exercise1_arm3: the torque budget by hand and by qfrc_bias", "[packaging]") {
  const Run out = run(example("l5_1_exercise1_arm3"));
  REQUIRE(out.status == 0);

  // the hand formula from the model's own masses, centres of mass and link lengths
  const lever::Model model = lever::mjcf::load_file(lever::test::model_path("models/arm3.xml"));
  const double g = -model.opt.gravity.z();
  const std::vector<double> length = link_lengths(model);
  std::vector<double> mass, com;
  for (int j = 0; j < model.njnt; ++j) {
    const int b = model.jnt_bodyid[j];
    mass.push_back(model.body_mass[b]);
    com.push_back(model.body_ipos[b].norm());
  }
  lever::Data data(model);
  lever::forward(model, data);  // qpos0: every link horizontal, at rest
  for (int j = 0; j < model.njnt; ++j) {
    double hand = 0.0, offset = 0.0;  // links beyond joint j, at their distance from it
    for (int k = j; k < model.njnt; ++k) {
      hand += g * mass[k] * (offset + com[k]);
      offset += length[k];
    }
    const double limit = model.actuator_ctrlrange[j][1];
    const std::string& line = line_with(out, "  " + model.jnt_name[j] + " ");
    const std::vector<Printed> printed = numbers_in(line);
    REQUIRE(printed.size() == 5);
    INFO(line);
    CHECK(std::abs(printed[0].value - hand) <= printed[0].half_unit);
    CHECK(std::abs(printed[1].value - data.qfrc_bias[j]) <= printed[1].half_unit);
    CHECK(std::abs(printed[2].value - limit) <= std::abs(limit) * 1e-3);  // %.4g
    CHECK(std::abs(printed[3].value - limit / data.qfrc_bias[j]) <= printed[3].half_unit);
    CHECK(printed[4].value <= data.qfrc_bias[j] + printed[4].half_unit);  // horizontal is worst
  }
  const double limit = model.actuator_ctrlrange[0][1];
  const std::vector<Printed> ratio = numbers_in(line_with(out, "shoulder torque ratio:"));
  REQUIRE(ratio.size() == 3);
  CHECK(std::abs(ratio[0].value - limit / data.qfrc_bias[0]) <= ratio[0].half_unit);
  CHECK(std::abs(ratio[1].value - limit / data.qfrc_bias[0]) <= ratio[1].half_unit);
  CHECK(ratio[2].value < 1e-12);
}

TEST_CASE("l5_1_exercise2_workspace: the map exists and the farthest reach is recomputed",
          "[packaging]") {
  const std::string svg = std::string(LEVER_PACKAGING_WORK_DIR) + "/exercise2-workspace.svg";
  std::filesystem::remove(svg);
  const Run out = run(example("l5_1_exercise2_workspace") + " '" + svg + "'");
  REQUIRE(out.status == 0);

  // the SVG is there and is an SVG document
  REQUIRE(std::filesystem::exists(svg));
  std::ifstream in(svg);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  CHECK(text.find("<svg") != std::string::npos);
  CHECK(text.find("</svg>") != std::string::npos);
  CHECK(text.find("<circle") != std::string::npos);

  lever::Model model = lever::mjcf::load_file(lever::test::model_path("models/arm2.xml"));
  const int shoulder_motor = model.actuator("shoulder");
  model.actuator_ctrlrange[shoulder_motor] = {-6.0, 6.0};
  lever::Data data(model);
  const int ee = model.site("ee");
  const Eigen::Vector3d shoulder = model.body_pos[model.body("link1")];
  auto holds = [&]() {
    for (int a = 0; a < model.nu; ++a) {
      const double need = data.qfrc_bias[model.jnt_dofadr[model.actuator_trnid[a][0]]];
      if (need < model.actuator_ctrlrange[a][0] || need > model.actuator_ctrlrange[a][1])
        return false;
    }
    return true;
  };

  // the printed pose: its tip and torque recomputed, and it holds (to the rounding of the pose)
  const std::vector<Printed> pose = numbers_in(line_with(out, "pose: shoulder"));
  REQUIRE(pose.size() == 5);
  const std::vector<Printed> distance = numbers_in(line_with(out, "farthest horizontal distance"));
  REQUIRE(distance.size() == 1);
  data.qpos << pose[0].value, pose[1].value;
  lever::forward(model, data);
  const Eigen::Vector3d tip = data.site_xpos[ee] - shoulder;
  const double pose_rounding = 1e-3;  // the pose is printed to 0.1 mrad; the tip moves < 0.1 mm
  CHECK(std::abs(pose[2].value - tip.x()) <= pose[2].half_unit + pose_rounding);
  CHECK(std::abs(pose[3].value - tip.z()) <= pose[3].half_unit + pose_rounding);
  CHECK(std::abs(pose[4].value - data.qfrc_bias[0]) <= pose[4].half_unit + pose_rounding);
  CHECK(std::abs(distance[0].value - std::abs(tip.x())) <= distance[0].half_unit + pose_rounding);
  CHECK(std::abs(data.qfrc_bias[0]) <= 6.0 + pose_rounding);

  // an independent search on another grid finds no holdable pose reaching farther
  const int n = 601;
  double best = 0.0;
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < n; ++k) {
      const double q1 =
          model.jnt_range[0][0] + (model.jnt_range[0][1] - model.jnt_range[0][0]) * i / (n - 1);
      const double q2 =
          model.jnt_range[1][0] + (model.jnt_range[1][1] - model.jnt_range[1][0]) * k / (n - 1);
      data.qpos << q1, q2;
      data.qvel.setZero();
      lever::forward(model, data);
      if (holds()) best = std::max(best, std::abs(data.site_xpos[ee].x() - shoulder.x()));
    }
  }
  CHECK(distance[0].value >= best - distance[0].half_unit);
  CHECK(distance[0].value <= best + 5e-3);  // a 601-point grid is within a few mm of the optimum
}

TEST_CASE(
    "l5_2_seven_dof prints lesson 5.2's keyframe, Jacobian and step figures as lever computes",
    "[packaging]") {
  const Run out = run(example("l5_2_seven_dof"));  // no argument: the installed panda7.xml
  REQUIRE(out.status == 0);
  const lever::Model model = lever::mjcf::load_file(lever::test::model_path("models/panda7.xml"));
  const int home = model.key("home");
  check_line(out, "keyframe home:", {1.0, static_cast<double>(model.njnt), model.opt.timestep});
  const Eigen::VectorXd qpos = model.key_qpos.row(home).transpose();
  check_line(out, "    qpos [", std::vector<double>(qpos.data(), qpos.data() + qpos.size()));

  // the ee Jacobian at home, by another SVD than the program's; manipulability as the product
  // of the singular values rather than sqrt(det(J J^T))
  lever::Data data(model);
  lever::reset_keyframe(model, data, home);
  lever::forward(model, data);
  Eigen::MatrixXd jacp(3, model.nv), jacr(3, model.nv), J(6, model.nv);
  lever::jac_site(model, data, model.site("ee"), jacp, jacr);
  J << jacp, jacr;
  const Eigen::VectorXd sigma = lever::test::singular_values_from_gram(J);
  std::vector<double> expected{2.0, 6.0, static_cast<double>(model.nv)};
  for (Eigen::Index i = 0; i < sigma.size(); ++i) expected.push_back(sigma[i]);
  check_line(out, "singular values", expected);
  check_line(out, "manipulability", {sigma.prod(), sigma[0] / sigma[sigma.size() - 1]});

  // the step's spectral radius at home, linearised here with another difference step
  const auto radius = [&](lever::Integrator integrator) {
    lever::Model m = model;
    m.opt.integrator = integrator;
    const int n = m.nq + m.nv;
    const double eps = 1e-7;
    Eigen::MatrixXd A(n, n);
    for (int i = 0; i < n; ++i) {
      Eigen::VectorXd x[2];
      for (int side = 0; side < 2; ++side) {
        lever::Data d(m);
        lever::reset_keyframe(m, d, home);
        (i < m.nq ? d.qpos[i] : d.qvel[i - m.nq]) += side ? -eps : eps;
        lever::step(m, d);
        x[side].resize(n);
        x[side] << d.qpos, d.qvel;
      }
      A.col(i) = (x[0] - x[1]) / (2 * eps);
    }
    return lever::test::spectral_radius(A);
  };
  check_line(out, "spectral radius of the step at home",
             {3.0, radius(model.opt.integrator), radius(lever::Integrator::kEuler), 1.0});
}

#ifdef LEVER_INSTALLED_PYTHON_EXAMPLES
namespace {

// A line with every standalone number replaced by '#': the words two programs must share.
std::string words_of(const std::string& line) {
  std::string words;
  std::size_t copied = 0;
  for (const NumberSpan& n : number_spans(line)) {
    words += line.substr(copied, n.begin - copied) + "#";
    copied = n.end;
  }
  return words + line.substr(copied);
}

}  // namespace

TEST_CASE("l5_2_seven_dof.py prints what the C++ l5_2_seven_dof prints, line for line",
          "[packaging][python]") {
  // both installed, both run here: the C++ program on lever::step and Eigen, the Python one on
  // lever.mujoco's mj_step and numpy, both on lever check's report for sections (7) and (8)
  const Run cpp = run(example("l5_2_seven_dof"));
  const Run py = run(std::string("PYTHONPATH='") + LEVER_INSTALLED_PYTHONPATH +
                     "' PYTHONDONTWRITEBYTECODE=1 '" + LEVER_PYTHON_EXECUTABLE + "' '" +
                     LEVER_INSTALLED_PYTHON_EXAMPLES + "/l5_2_seven_dof.py'");
  REQUIRE(cpp.status == 0);
  REQUIRE(py.status == 0);
  REQUIRE(cpp.lines.size() >= 10);
  REQUIRE(py.lines.size() == cpp.lines.size());
  for (size_t i = 0; i < cpp.lines.size(); ++i) {
    INFO("C++:    " << cpp.lines[i] << "\nPython: " << py.lines[i]);
    CHECK(words_of(py.lines[i]) == words_of(cpp.lines[i]));
    const std::vector<Printed> ours = numbers_in(py.lines[i]), theirs = numbers_in(cpp.lines[i]);
    REQUIRE(ours.size() == theirs.size());
    for (size_t k = 0; k < ours.size(); ++k) {
      INFO("number " << k << ": Python " << ours[k].text << ", C++ " << theirs[k].text);
      // each printed figure lies within half a unit of its last digit of the value it rounds;
      // two roundings of values that agree far better than that differ by at most both halves
      CHECK(std::abs(ours[k].value - theirs[k].value) <=
            (ours[k].half_unit + theirs[k].half_unit) * (1 + 1e-9));
    }
  }
}
#endif
