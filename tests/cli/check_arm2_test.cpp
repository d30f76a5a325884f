// `lever check models/arm2.xml` against lesson 5.1's Output block: every number the lesson prints
// must appear, to the lesson's printed digits. The expected numbers are computed here, from the
// lesson's hand formulas with the model's own constants (link lengths, masses, limits), or from
// the engine where the lesson has no formula (the rest on the soft stop); none is typed in.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <string>

#include <lever/lever.hpp>
#include <lever/mjcf.hpp>

#include "json_reader.hpp"
#include "run_lever.hpp"
#include <lever/harness/models.hpp>
#include "two_link.hpp"

namespace lever::test {

namespace {

double capsule_mass(double r, double L) {
  return 1000.0 * std::numbers::pi * r * r * (L + 4.0 * r / 3.0);
}

// np.round(x, 4) as Python prints it: 0.486, 0.1227.
std::string python_round4(double x) {
  std::string s = format("%.4f", x);
  s.erase(s.find_last_not_of('0') + 1);
  if (s.back() == '.') s += '0';
  return s;
}

// The shoulder resting on its lower stop with the elbow hanging straight down: the shoulder angle
// where the engine's qacc vanishes at rest, by bisection (independent of how `check` finds it).
double shoulder_rest_angle(const Model& model, Data& data) {
  const auto qacc_at = [&](double q1) {
    data.qpos << q1, -std::numbers::pi / 2 - q1;
    data.qvel.setZero();
    data.ctrl.setZero();
    forward(model, data);
    return data.qacc[0];
  };
  const double stop = model.jnt_range[0][0];
  double inside = stop, past = stop - 0.01;  // falling at the stop, pushed back 10 mrad past it
  REQUIRE(qacc_at(inside) < 0);
  REQUIRE(qacc_at(past) > 0);
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (inside + past);
    (qacc_at(mid) < 0 ? inside : past) = mid;
  }
  qacc_at(past);
  return past;
}

struct Arm2 {
  Model model = mjcf::load_file(model_path("models/arm2.xml"));
  TwoLink p = two_link(model);
  Run text = run_lever("check " + quoted(model_path("models/arm2.xml")));
};

const Arm2& arm2() {
  static const Arm2 a;
  return a;
}

void contains(const std::string& text, const std::string& expected) {
  INFO("expected in the output: " << expected);
  CHECK(text.find(expected) != std::string::npos);
}

}  // namespace

TEST_CASE("check arm2: exits 0 with no findings", "[check][arm2]") {
  CHECK(arm2().text.status == 0);
  contains(arm2().text.out, "findings: none: every claim checks out");
}

TEST_CASE("check arm2: (1) structure, and the masses and principal moments", "[check][arm2]") {
  const TwoLink& p = arm2().p;
  const std::string& out = arm2().text.out;
  contains(out, "motor shoulder gear 1 ctrlrange [" + format("%g", -p.limit1) + " " +
                    format("%g", p.limit1) + "] N m ctrllimited true");
  contains(out, "sites: ee");
  // explicit thin rods: m L^2 / 12 about the perpendicular axes
  contains(out, "body link1 mass " + format("%.3f", p.m1) + " kg, principal moments [0.0001 " +
                    format("%.5f", p.m1 * p.L1 * p.L1 / 12) + " " +
                    format("%.5f", p.m1 * p.L1 * p.L1 / 12) + "]");
  contains(out, "body link2 mass " + format("%.3f", p.m2) + " kg, principal moments [0.0001 " +
                    format("%.5f", p.m2 * p.L2 * p.L2 / 12) + " " +
                    format("%.5f", p.m2 * p.L2 * p.L2 / 12) + "]");
}

TEST_CASE("check arm2: (2) forward kinematics agrees with the planar formula to rounding",
          "[check][arm2]") {
  const std::string& out = arm2().text.out;
  const std::string key = "max |site_xpos - formula| = ";
  const size_t at = out.find(key);
  REQUIRE(at != std::string::npos);
  // the figure is lever's own rounding error (the lesson printed MuJoCo's, 4.4e-16 m)
  CHECK(std::stod(out.substr(at + key.size())) < 1e-14);
  contains(out, "links 0.5 m, 0.4 m");
}

TEST_CASE("check arm2: (3) gravity torque and motor sizing, the lesson's numbers",
          "[check][arm2]") {
  const TwoLink& p = arm2().p;
  const std::string& out = arm2().text.out;
  // the arm horizontal: tau_g1 = g (m1 c1 + m2 (L1 + c2)) = 9.81 (0.25 + 0.4 + 0.16)
  const double tau1 = p.g * (p.m1 * p.c1 + p.m2 * (p.L1 + p.c2)), tau2 = p.g * p.m2 * p.c2;
  contains(out, "    shoulder " + format("%.3f", tau1) + " N m at q = [0 0]\n");
  contains(out, "    elbow " + format("%.3f", tau2) + " N m at q = [0 0]\n");
  contains(out, "motor limit / gravity torque: shoulder " + format("%.2f", p.limit1 / tau1) + " (" +
                    format("%g", p.limit1) + " N m), elbow " + format("%.2f", p.limit2 / tau2));
  const double pay1 = (p.limit1 - tau1) / (p.g * (p.L1 + p.L2));
  const double pay2 = (p.limit2 - tau2) / (p.g * p.L2);
  contains(out, "shoulder allows " + format("%.2f", pay1) + " kg, elbow allows " +
                    format("%.2f", pay2) + " kg -> " + format("%.2f", std::min(pay1, pay2)) +
                    " kg");
  // M(q) with the arm horizontal (q2 = 0), from the lesson's closed form
  const Eigen::Matrix2d M = mass_matrix(p, 0.0);
  const double M11 = M(0, 0), M12 = M(0, 1), M22 = M(1, 1);
  contains(out, "M(q) at this pose: [[" + python_round4(M11) + ", " + python_round4(M12) + "], [" +
                    python_round4(M12) + ", " + python_round4(M22) + "]] kg m^2");
  const double spare = p.limit1 - tau1, acc = spare / M11, elbow = M12 * acc + tau2;
  contains(out, "spare shoulder torque " + format("%.2f", spare) + " N m gives " +
                    format("%.1f", acc) + " rad/s^2 with the elbow rigid, which needs " +
                    format("%.2f", elbow) + " N m at the elbow");
}

TEST_CASE("check arm2: (4) explicit versus inferred inertia, and the visual geom's mass",
          "[check][arm2]") {
  const TwoLink& p = arm2().p;
  const std::string& out = arm2().text.out;
  const double inferred1 = capsule_mass(p.r1, p.L1), inferred2 = capsule_mass(p.r2, p.L2);
  contains(out, "link1: explicit " + format("%.3f", p.m1) + " kg");
  contains(out, "from geoms " + format("%.3f", inferred1) + " kg");
  contains(out, "link2: explicit " + format("%.3f", p.m2) + " kg");
  contains(out, "from geoms " + format("%.3f", inferred2) + " kg");
  // the inferred principal moments, from the engine's own inference
  const Model inferred =
      mjcf::load_file(model_path("models/arm2.xml"), {.infer_inertia_from_geoms = true});
  Eigen::Vector3d I = inferred.body_inertia[inferred.body("link1")];
  std::sort(I.data(), I.data() + 3);
  contains(out, "[" + format("%.5f", I[0]) + " " + format("%.5f", I[1]) + " " +
                    format("%.5f", I[2]) + "] kg m^2");
  // capsules' centres of mass at the middle of each link
  const double tau_explicit = p.g * (p.m1 * p.c1 + p.m2 * (p.L1 + p.c2));
  const double tau_inferred = p.g * (inferred1 * p.L1 / 2 + inferred2 * (p.L1 + p.L2 / 2));
  contains(out, "gravity torque at the worst pose: explicit " + format("%.3f", tau_explicit) +
                    " N m, from geoms " + format("%.3f", tau_inferred) + " N m (shoulder)");
  contains(out, "default inertiagrouprange (0 5): body mass " + format("%.3f", 1.0 + 2.0) + " kg");
  contains(out, "inertiagrouprange=\"0 2\": body mass " + format("%.3f", 1.0) + " kg");
}

TEST_CASE("check arm2: (5) the shoulder rests on its soft stop", "[check][arm2]") {
  const Model& model = arm2().model;
  const TwoLink& p = arm2().p;
  Data data(model);
  const double q1 = shoulder_rest_angle(model, data);
  const std::string& out = arm2().text.out;
  contains(out, "shoulder at " + format("%.5f", q1) + " rad, stop at " + format("%g", p.lower1) +
                    " rad -> " + format("%.2f", 1000 * (p.lower1 - q1)) + " mrad past the stop");
  // at rest on the stop the limit force equals gravity's torque, g (m1 c1 + m2 L1) cos q1 with
  // the elbow hanging straight down. The bisection leaves q1 within an ulp or two of the point
  // where qacc changes sign, and the stop's stiffness (about 4e3 N m/rad: 2.3 N m over 0.53 mrad)
  // turns that into a force residual: 1.2e-13 N m measured. The bound, 1e-9, sits well above that
  // and far below any missing term (a wrong cos q1 or a lost mass moves the torque by > 1e-3 N m).
  const double gravity = p.g * (p.m1 * p.c1 + p.m2 * p.L1) * std::cos(q1);
  CHECK(std::abs(data.qfrc_constraint[0] - gravity) < 1e-9);
  contains(out, "active limit rows: 1; qfrc_constraint[shoulder] = " + format("%.4f", gravity) +
                    " N m, gravity torque qfrc_bias[shoulder] = " + format("%.4f", gravity) +
                    " N m");
}

TEST_CASE("check arm2: (6) commands beyond ctrlrange are clamped silently", "[check][arm2]") {
  const TwoLink& p = arm2().p;
  contains(arm2().text.out, "ctrl = [100 -100]: actuator_force = [" + format("%g", p.limit1) + " " +
                                format("%g", -p.limit2) + "] N m (no warning is raised)");
}

TEST_CASE("check arm2: --json parses and agrees with the text", "[check][arm2][json]") {
  const Run run = run_lever("check --json " + quoted(model_path("models/arm2.xml")));
  REQUIRE(run.status == 0);
  const json::Value report = json::parse(run.out);
  const std::string& out = arm2().text.out;
  CHECK(report["exit_status"].number == 0);
  CHECK(report["findings"].size() == 0);
  const json::Value& joints = report["torque_budget"]["joints"];
  REQUIRE(joints.size() == 2);
  for (size_t j = 0; j < 2; ++j) {
    const std::string name = joints[j]["joint"].string;
    contains(out, name + " " + format("%.3f", joints[j]["worst_gravity_torque"].number) + " N m");
    contains(out, name + " " + format("%.2f", joints[j]["ratio"].number));
  }
  contains(out,
           "-> " + format("%.2f", report["torque_budget"]["payload"][0]["min"].number) + " kg");
  const json::Value& M = report["torque_budget"]["mass_matrices"][0]["M"];
  contains(out, "[[" + python_round4(M[0][0].number) + ", " + python_round4(M[0][1].number));
  const json::Value& stop = report["soft_stops"]["stops"][0];
  CHECK(stop["from_qpos0"].boolean);
  contains(out, "shoulder at " + format("%.5f", stop["qpos"].number) + " rad");
  contains(out, "qfrc_constraint[shoulder] = " + format("%.4f", stop["qfrc_constraint"].number));
  const json::Value& inertia = report["inertia"]["bodies"][1];
  contains(out, "from geoms " + format("%.3f", inertia["inferred_mass"].number) + " kg");
  const json::Value& force = report["clamping"]["actuator_force"];
  contains(out, "actuator_force = [" + format("%g", force[0].number) + " " +
                    format("%g", force[1].number) + "]");
}

}  // namespace lever::test
