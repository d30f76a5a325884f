// Lesson 5.1: a two-link arm, checked the way you would check any robot model.
//
// INPUT   arm2.xml (planar arm, explicit inertias, joint stops, torque motors)
// PROCESS (1) print what the compiled model contains: joints, axes, ranges, motors, sites;
//         (2) compare the end-effector site with the planar forward-kinematics formula;
//         (3) compare gravity torque (qfrc_bias at rest) with the hand formula, and size the
//             motors: margin over gravity, payload, peak acceleration;
//         (4) compare the explicit inertias with what lever infers from the geoms, and show that
//             a visual-only geom still adds mass;
//         (5) let the arm fall onto its shoulder stop and measure the soft limit;
//         (6) command more torque than ctrlrange allows
// OUTPUT  printed tables
//
// Run: l5_1_two_link [path/to/arm2.xml]     (default: arm2.xml of the installed lever)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include <lever/lever.hpp>
#include <lever/mjcf.hpp>

namespace {

// The hand calculation's numbers: what the model claims, written down independently of it.
constexpr double G = 9.81;
constexpr double L1 = 0.5, L2 = 0.4;   // link lengths (m)
constexpr double M1 = 1.0, M2 = 0.8;   // link masses (kg)
constexpr double C1 = 0.25, C2 = 0.2;  // centre-of-mass distance from each joint (m)

// x rounded to a number of decimals, as numpy's round: printed with %g it shows no trailing zeros.
double round_to(double x, int decimals) {
  const double scale = std::pow(10.0, decimals);
  return std::round(x * scale) / scale;
}

std::string vec(const Eigen::Ref<const Eigen::VectorXd>& v, int decimals = 6) {
  std::string s = "(";
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%s%g", i > 0 ? ", " : "", round_to(v[i], decimals));
    s += buf;
  }
  return s + ")";
}

// A pose drawn uniformly within the joint ranges.
Eigen::VectorXd random_pose(const lever::Model& model, std::mt19937& rng) {
  Eigen::VectorXd q(model.nq);
  for (int j = 0; j < model.njnt; ++j) {
    const auto [lo, hi] = model.jnt_range[j];
    q[model.jnt_qposadr[j]] = std::uniform_real_distribution<double>(lo, hi)(rng);
  }
  return q;
}

void structure(const lever::Model& model) {
  for (int j = 0; j < model.njnt; ++j) {
    std::printf("  joint %-9s axis %s range [%g, %g] rad limited %s damping %g N m s/rad\n",
                model.jnt_name[j].c_str(), vec(model.jnt_axis[j]).c_str(), model.jnt_range[j][0],
                model.jnt_range[j][1], model.jnt_limited[j] ? "true" : "false",
                model.dof_damping[model.jnt_dofadr[j]]);
  }
  for (int a = 0; a < model.nu; ++a) {
    std::printf("  motor %-9s gear %g ctrlrange [%g, %g] N m ctrllimited %s\n",
                model.actuator_name[a].c_str(), model.actuator_gear[a][0],
                model.actuator_ctrlrange[a][0], model.actuator_ctrlrange[a][1],
                model.actuator_ctrllimited[a] ? "true" : "false");
  }
  std::printf("  sites:");
  for (const std::string& name : model.site_name) std::printf(" %s", name.c_str());
  std::printf("\n");
}

void forward_kinematics(const lever::Model& model, lever::Data& data) {
  std::mt19937 rng(0);
  const int ee = model.site("ee");
  const Eigen::Vector3d base = model.body_pos[model.body("link1")];  // the shoulder axis
  double worst = 0.0;
  for (int i = 0; i < 1000; ++i) {
    const Eigen::VectorXd q = random_pose(model, rng);
    data.qpos = q;
    lever::kinematics(model, data);
    const double x = L1 * std::cos(q[0]) + L2 * std::cos(q[0] + q[1]);
    const double z = L1 * std::sin(q[0]) + L2 * std::sin(q[0] + q[1]);
    const Eigen::Vector3d formula = base + Eigen::Vector3d(x, 0.0, z);
    worst = std::max(worst, (data.site_xpos[ee] - formula).cwiseAbs().maxCoeff());
  }
  std::printf("  1000 random poses within the joint ranges: max |site_xpos - formula| = %.1e m\n",
              worst);
}

// Torque the motors must supply to hold the arm still at q (the derivative of potential energy).
Eigen::Vector2d gravity_torque(const Eigen::VectorXd& q) {
  const double t2 = G * M2 * C2 * std::cos(q[0] + q[1]);
  const double t1 = G * (M1 * C1 + M2 * L1) * std::cos(q[0]) + t2;
  return {t1, t2};
}

void motor_sizing(const lever::Model& model, lever::Data& data) {
  std::mt19937 rng(1);
  double worst = 0.0;
  for (int i = 0; i < 1000; ++i) {
    const Eigen::VectorXd q = random_pose(model, rng);
    data.qpos = q;
    data.qvel.setZero();
    lever::forward(model, data);
    worst = std::max(worst, (data.qfrc_bias - gravity_torque(q)).cwiseAbs().maxCoeff());
  }
  std::printf("  1000 random poses at rest: max |qfrc_bias - formula| = %.1e N m\n", worst);

  data.qpos.setZero();  // arm horizontal: the largest gravity torque at both joints
  data.qvel.setZero();
  lever::forward(model, data);
  const Eigen::Vector2d tau_g = data.qfrc_bias;
  const Eigen::Vector2d limit(model.actuator_ctrlrange[0][1], model.actuator_ctrlrange[1][1]);
  std::printf("  gravity torque, arm horizontal: shoulder %.3f N m, elbow %.3f N m\n", tau_g[0],
              tau_g[1]);
  std::printf("  motor limit / gravity torque: shoulder %.2f, elbow %.2f\n", limit[0] / tau_g[0],
              limit[1] / tau_g[1]);
  // a point mass m_p at the tip adds g m_p (L1 + L2) at the shoulder and g m_p L2 at the elbow
  const Eigen::Vector2d payload((limit[0] - tau_g[0]) / (G * (L1 + L2)),
                                (limit[1] - tau_g[1]) / (G * L2));
  std::printf(
      "  largest point payload at the tip, arm horizontal: shoulder allows %.2f kg, "
      "elbow allows %.2f kg -> %.2f kg\n",
      payload[0], payload[1], payload.minCoeff());

  const Eigen::MatrixXd& mass = data.M;                   // full and symmetric, armature included
  const double acc = (limit[0] - tau_g[0]) / mass(0, 0);  // elbow held rigid: qacc_elbow = 0
  const double elbow = mass(1, 0) * acc + tau_g[1];       // elbow torque that keeps it rigid
  std::printf("  M(q) at this pose: [%s, %s] kg m^2\n", vec(mass.row(0).transpose(), 4).c_str(),
              vec(mass.row(1).transpose(), 4).c_str());
  std::printf(
      "  spare shoulder torque %.2f N m gives %.1f rad/s^2 with the elbow rigid, "
      "which needs %.2f N m at the elbow\n",
      limit[0] - tau_g[0], acc, elbow);
}

void inferred_inertia(const lever::Model& model, const std::string& path) {
  const lever::Model inferred =
      lever::mjcf::load_file(path, lever::mjcf::LoadOptions{.infer_inertia_from_geoms = true});
  for (const char* name : {"link1", "link2"}) {
    const int a = model.body(name), b = inferred.body(name);
    Eigen::Vector3d ia = model.body_inertia[a], ib = inferred.body_inertia[b];
    std::sort(ia.begin(), ia.end());
    std::sort(ib.begin(), ib.end());
    std::printf("  %s: explicit %.3f kg, principal moments %s | from geoms %.3f kg, %s kg m^2\n",
                name, model.body_mass[a], vec(ia, 5).c_str(), inferred.body_mass[b],
                vec(ib, 5).c_str());
  }
  lever::Data explicit_data(model), inferred_data(inferred);  // both at qpos0: arm horizontal
  lever::forward(model, explicit_data);
  lever::forward(inferred, inferred_data);
  std::printf(
      "  gravity torque at the horizontal pose: explicit %.3f N m, from geoms %.3f N m "
      "(shoulder)\n",
      explicit_data.qfrc_bias[0], inferred_data.qfrc_bias[0]);
}

// A body with a 1 kg collision geom and a 2 kg geom that collides with nothing, in group 3.
void visual_geom_mass() {
  auto body_mass = [](const std::string& compiler) {
    const std::string xml =
        "<mujoco>" + compiler +
        "  <worldbody><body name='b'><joint type='slide' axis='0 0 1'/>"
        "    <geom type='box' size='0.05 0.05 0.05' mass='1'/>"
        "    <geom type='sphere' size='0.05' mass='2' contype='0' conaffinity='0' group='3'/>"
        "  </body></worldbody></mujoco>";
    const lever::Model m = lever::mjcf::load_string(xml, "visual_geom.xml");
    return std::pair{m.body_mass[m.body("b")], m.compiler.inertiagrouprange};
  };
  const auto [default_mass, default_range] = body_mass("");
  std::printf(
      "  1 kg collision geom + 2 kg non-colliding geom in group 3, default inertiagrouprange"
      " (%d %d): body mass %.3f kg\n",
      default_range[0], default_range[1], default_mass);
  const auto [narrow_mass, narrow_range] = body_mass("<compiler inertiagrouprange='0 2'/>");
  std::printf(
      "  1 kg collision geom + 2 kg non-colliding geom in group 3, inertiagrouprange=\"%d %d\":"
      " body mass %.3f kg\n",
      narrow_range[0], narrow_range[1], narrow_mass);
}

void joint_stop(const lever::Model& model, lever::Data& data) {
  lever::reset(model, data);
  // damping is light: give the elbow a minute to settle
  const long steps = std::lround(60.0 / model.opt.timestep);
  for (long i = 0; i < steps; ++i) lever::step(model, data);
  const double lo = model.jnt_range[0][0];
  // every constraint row in lever is a joint limit; after step(), as after MuJoCo's mj_step,
  // the rows and forces describe the start of the last step
  std::printf(
      "  after 60 s with zero torque: shoulder at %.5f rad, stop at %g rad -> %.2f mrad past "
      "the stop\n",
      data.qpos[0], lo, 1000 * (lo - data.qpos[0]));
  std::printf(
      "  active limit rows: %d; qfrc_constraint[shoulder] = %.4f N m, gravity torque "
      "qfrc_bias[shoulder] = %.4f N m\n",
      data.nefc, data.qfrc_constraint[0], data.qfrc_bias[0]);
}

void clamping(const lever::Model& model, lever::Data& data) {
  lever::reset(model, data);
  data.ctrl << 100.0, -100.0;
  lever::forward(model, data);
  std::printf("  ctrl = %s: actuator_force = %s N m (no warning is raised)\n",
              vec(data.ctrl).c_str(), vec(data.actuator_force).c_str());
}

}  // namespace

int main(int argc, char** argv) try {
  const std::string path = argc > 1 ? argv[1] : LEVER_MODELS_DIR "/arm2.xml";
  const lever::Model model = lever::mjcf::load_file(path);
  lever::Data data(model);
  std::printf("(1) what the compiled model contains:\n");
  structure(model);
  std::printf("(2) forward kinematics of the ee site:\n");
  forward_kinematics(model, data);
  std::printf("(3) gravity torque and motor sizing:\n");
  motor_sizing(model, data);
  std::printf("(4) explicit inertias versus inertias inferred from the geoms:\n");
  inferred_inertia(model, path);
  visual_geom_mass();
  std::printf("(5) the shoulder stop is a soft constraint:\n");
  joint_stop(model, data);
  std::printf("(6) commands beyond ctrlrange are clamped:\n");
  clamping(model, data);
  return 0;
} catch (const lever::Error& e) {  // a model that does not load: the message names file and line
  std::fprintf(stderr, "%s\n", e.what());
  return 1;
}
