// Lesson 5.1, exercise 1: a third link, and the shoulder's torque budget again.
//
// INPUT   arm3.xml: arm2 plus a wrist link 0.15 m long, 0.3 kg, explicit thin-rod inertia, a hinge
//         about -y with range +-2 rad, a motor limited to three times its worst-case gravity
//         torque, and the ee site at its tip
// PROCESS (1) the gravity torque of each joint with the arm horizontal, by hand: each joint
//             carries the weight of every link beyond it, at that link's centre-of-mass distance;
//         (2) the same from qfrc_bias at rest;
//         (3) the motor limit over the gravity torque, and the check that the horizontal pose is
//             the worst case (1000 random poses never need more)
// OUTPUT  a table per joint, and the shoulder's ratio by both routes
//
// Run: l5_1_exercise1_arm3 [path/to/arm3.xml]     (default: arm3.xml of the installed lever)
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include <lever/lever.hpp>
#include <lever/mjcf.hpp>

namespace {

// The hand calculation's numbers: arm2's two links and the exercise's wrist link.
constexpr double G = 9.81;
constexpr double L1 = 0.5, L2 = 0.4, L3 = 0.15;          // link lengths (m)
constexpr double M1 = 1.0, M2 = 0.8, M3 = 0.3;           // link masses (kg)
constexpr double C1 = L1 / 2, C2 = L2 / 2, C3 = L3 / 2;  // thin rods: centre of mass mid-link

// Gravity torque of each joint with the whole arm horizontal, where every cosine is 1: the joint
// holds each link beyond it at the horizontal distance from the joint to that link's centre.
Eigen::Vector3d gravity_torque_horizontal() {
  const double wrist = G * M3 * C3;
  const double elbow = G * (M2 * C2 + M3 * (L2 + C3));
  const double shoulder = G * (M1 * C1 + M2 * (L1 + C2) + M3 * (L1 + L2 + C3));
  return {shoulder, elbow, wrist};
}

// The same for arm2, without the wrist link: the lesson's 7.946 N m.
double arm2_shoulder_torque_horizontal() { return G * (M1 * C1 + M2 * (L1 + C2)); }

}  // namespace

int main(int argc, char** argv) try {
  const std::string path = argc > 1 ? argv[1] : LEVER_MODELS_DIR "/arm3.xml";
  const lever::Model model = lever::mjcf::load_file(path);
  lever::Data data(model);

  const Eigen::Vector3d by_hand = gravity_torque_horizontal();
  data.qpos.setZero();  // every link horizontal
  data.qvel.setZero();
  lever::forward(model, data);
  const Eigen::Vector3d by_bias = data.qfrc_bias;  // at rest: gravity torque only

  // the largest |qfrc_bias| over random poses at rest, to confirm the horizontal is the worst case
  std::mt19937 rng(2);
  Eigen::Vector3d largest = Eigen::Vector3d::Zero();
  for (int i = 0; i < 1000; ++i) {
    for (int j = 0; j < model.njnt; ++j) {
      const auto [lo, hi] = model.jnt_range[j];
      data.qpos[j] = std::uniform_real_distribution<double>(lo, hi)(rng);
    }
    lever::forward(model, data);
    largest = largest.cwiseMax(data.qfrc_bias.cwiseAbs());
  }

  std::printf("arm3, arm horizontal: gravity torque of each joint (N m)\n");
  std::printf("  %-9s %10s %10s %12s %8s %11s\n", "joint", "by hand", "qfrc_bias", "motor limit",
              "ratio", "random max");
  for (int a = 0; a < model.nu; ++a) {
    const int j = model.actuator_trnid[a][0];  // each motor drives one joint, in joint order
    const double limit = model.actuator_ctrlrange[a][1] * model.actuator_gear[a][0];
    std::printf("  %-9s %10.3f %10.3f %12.4g %8.2f %11.3f\n", model.jnt_name[j].c_str(), by_hand[j],
                by_bias[j], limit, limit / by_bias[j], largest[j]);
  }
  std::printf(
      "  (ratio: motor limit / qfrc_bias; random max: the largest |qfrc_bias| over 1000 random "
      "poses at rest)\n");
  const double shoulder_limit = model.actuator_ctrlrange[0][1];
  // cppcheck-suppress invalidPrintfArgType_float // std::abs(double) is a double (<cmath>)
  std::printf(
      "shoulder torque ratio: by hand %.2f, by qfrc_bias %.2f (|difference| %.1e N m in the "
      "torque)\n",
      shoulder_limit / by_hand[0], shoulder_limit / by_bias[0], std::abs(by_hand[0] - by_bias[0]));
  std::printf(
      "without the wrist (arm2) the hand formula gives %.2f: the 0.3 kg link at the end of "
      "the arm costs the shoulder %.3f N m\n",
      shoulder_limit / arm2_shoulder_torque_horizontal(),
      by_hand[0] - arm2_shoulder_torque_horizontal());
  return 0;
} catch (const lever::Error& e) {
  std::fprintf(stderr, "%s\n", e.what());
  return 1;
}
