// Lesson 5.1, exercise 2: where can a weaker arm hold its tip still?
//
// INPUT   arm2.xml, with the shoulder motor limited to 6 N m (less than the 7.946 N m the straight
//         arm weighs at the horizontal); the elbow keeps its 15 N m
// PROCESS (1) sample the joint ranges densely; at each pose, at rest, the motors must supply
//             qfrc_bias (the gravity torque): the pose is holdable when every motor can;
//         (2) map the tip positions (x, z) relative to the shoulder: a 2 cm cell is holdable when
//             some sampled pose with its tip in the cell is (elbow up or elbow down);
//         (3) find the farthest horizontal distance from the shoulder among holdable poses, and
//             refine it with a finer grid around the best sample
// OUTPUT  the workspace map as SVG, and the farthest holdable reach with its pose
//
// Run: l5_1_exercise2_workspace [map.svg] [path/to/arm2.xml]
//
// Why the region has this shape. At rest the shoulder's torque is
//     tau_g1 = g [(m1 c1 + m2 L1) cos q1 + m2 c2 cos(q1 + q2)] = g (m1 + m2) x_com,
// the arm's weight times the horizontal distance x_com of its centre of mass from the shoulder.
// 6 N m allows |x_com| <= 6 / (9.81 * 1.8) = 0.34 m; the straight horizontal arm has it 0.45 m
// out. The elbow never binds: tau_g2 = g m2 c2 cos(q1 + q2) is at most 1.57 N m against 15.
// Link 1 counts m1 c1 + m2 L1 = 0.65 kg m per unit of cos q1, link 2 only m2 c2 = 0.16 kg m per
// unit of cos(q1 + q2), so the limit is mostly on how far link 1 leans out, and the elbow angle
// decides how much of the budget link 2 takes: level and pointing outward it takes all 0.16,
// folded back (cos(q1 + q2) < 0) it gives some back and link 1 may come down to the horizontal.
// On the map (each dot a 2 cm cell of tip positions):
//   - near the vertical through the shoulder everything is holdable: both cosines are small;
//   - the outer rim on either side is not: reaching further out needs link 1 lower than the
//     budget allows. The farthest holdable reach puts link 2 level and link 1 as low as it may go,
//         cos q1 = (6 / g - m2 c2) / (m1 c1 + m2 L1) = 0.695 (46 degrees),
//         reach = L1 cos q1 + L2 = 0.747 m,
//     above or below the shoulder's height on the right, above it on the left;
//   - the grey island right of and below the shoulder: those tips can be reached two ways, but
//     elbow-down needs the shoulder below its -1.2 rad stop, and elbow-up holds link 1 level,
//     6.4 N m. The joint range, not the motor, takes away the holdable way of reaching them;
//   - the hole round the shoulder (the elbow folds at most 2.6 rad, so the tip stays 0.26 m away)
//     and the missing wedge down and to the left (the shoulder stop) are the reachable
//     workspace's own edges, the same with any motor.
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <utility>

#include <lever/lever.hpp>
#include <lever/mjcf.hpp>
#include <lever/plot.hpp>

namespace {

constexpr double kShoulderLimit = 6.0;  // N m, the exercise's weaker shoulder motor
constexpr int kSamples = 801;           // per joint: 4.5 mrad apart on the shoulder's 3.6 rad
constexpr double kCell = 0.02;          // m: the map's resolution

// A pose at rest is holdable when every motor can supply its joint's gravity torque.
// @pre forward() at this pose with qvel = 0, so qfrc_bias is the gravity torque.
bool holdable(const lever::Model& model, const lever::Data& data) {
  for (int a = 0; a < model.nu; ++a) {
    const int dof = model.jnt_dofadr[model.actuator_trnid[a][0]];
    const double ctrl = data.qfrc_bias[dof] / model.actuator_gear[a][0];  // what it must command
    const auto [lo, hi] = model.actuator_ctrlrange[a];
    if (ctrl < lo || ctrl > hi) return false;
  }
  return true;
}

struct Reach {
  double distance = -1.0;  // |x| of the tip from the shoulder (m)
  Eigen::Vector2d q = Eigen::Vector2d::Zero();
  Eigen::Vector3d tip = Eigen::Vector3d::Zero();  // relative to the shoulder
};

// Evaluate the pose q at rest; return the tip relative to the shoulder and whether it holds.
std::pair<Eigen::Vector3d, bool> evaluate(const lever::Model& model, lever::Data& data,
                                          const Eigen::Vector2d& q, int ee,
                                          const Eigen::Vector3d& shoulder) {
  data.qpos = q;
  data.qvel.setZero();
  lever::forward(model, data);
  return {data.site_xpos[ee] - shoulder, holdable(model, data)};
}

// Search an n x n grid of poses over [lo, hi] per joint; keep the farthest holdable reach.
// on_pose(tip, holds) sees every pose.
template <class OnPose>
Reach search(const lever::Model& model, lever::Data& data, const Eigen::Vector2d& lo,
             const Eigen::Vector2d& hi, int n, int ee, const Eigen::Vector3d& shoulder,
             OnPose on_pose) {
  Reach best;
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < n; ++k) {
      const Eigen::Vector2d q(lo[0] + (hi[0] - lo[0]) * i / (n - 1),
                              lo[1] + (hi[1] - lo[1]) * k / (n - 1));
      const auto [tip, holds] = evaluate(model, data, q, ee, shoulder);
      on_pose(tip, holds);
      if (holds && std::abs(tip.x()) > best.distance) best = {std::abs(tip.x()), q, tip};
    }
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) try {
  const std::string svg_path = argc > 1 ? argv[1] : "l5_1_exercise2_workspace.svg";
  const std::string path = argc > 2 ? argv[2] : LEVER_MODELS_DIR "/arm2.xml";
  lever::Model model = lever::mjcf::load_file(path);
  const int shoulder_motor = model.actuator("shoulder");
  model.actuator_ctrlrange[shoulder_motor] = {-kShoulderLimit, kShoulderLimit};  // the weaker motor
  lever::Data data(model);
  const int ee = model.site("ee");
  const Eigen::Vector3d shoulder = model.body_pos[model.body("link1")];  // the shoulder axis

  // (1) and (2): every sampled pose, binned by where it puts the tip
  const Eigen::Vector2d lo(model.jnt_range[0][0], model.jnt_range[1][0]);
  const Eigen::Vector2d hi(model.jnt_range[0][1], model.jnt_range[1][1]);
  std::map<std::pair<int, int>, bool> cells;  // (x, z) cell -> some pose holds there
  long poses = 0, holding = 0;
  const Reach coarse = search(
      model, data, lo, hi, kSamples, ee, shoulder, [&](const Eigen::Vector3d& tip, bool holds) {
        const std::pair<int, int> cell{static_cast<int>(std::floor(tip.x() / kCell)),
                                       static_cast<int>(std::floor(tip.z() / kCell))};
        cells[cell] = cells[cell] || holds;
        ++poses;
        holding += holds;
      });

  // (3): refine around the best sample, one coarse step either side, 50 times finer
  const Eigen::Vector2d step = (hi - lo) / (kSamples - 1);
  const Reach best =
      search(model, data, (coarse.q - step).cwiseMax(lo), (coarse.q + step).cwiseMin(hi), 101, ee,
             shoulder, [](const Eigen::Vector3d&, bool) {});
  const Reach farthest = best.distance > coarse.distance ? best : coarse;
  evaluate(model, data, farthest.q, ee, shoulder);
  const double tau_shoulder = data.qfrc_bias[0];

  std::printf(
      "arm2 with the shoulder motor limited to %g N m (elbow %g N m), %d x %d poses over "
      "the joint ranges\n",
      kShoulderLimit, model.actuator_ctrlrange[model.actuator("elbow")][1], kSamples, kSamples);
  std::printf("  holdable: %.1f%% of the sampled poses\n", 100.0 * holding / poses);
  std::printf("  farthest horizontal distance from the shoulder among holdable poses: %.3f m\n",
              farthest.distance);
  std::printf(
      "    pose: shoulder %.4f rad, elbow %.4f rad; tip at x = %.3f m, z = %.3f m from the "
      "shoulder; shoulder gravity torque %.3f N m\n",
      farthest.q[0], farthest.q[1], farthest.tip.x(), farthest.tip.z(), tau_shoulder);

  // the map: holdable cells over the unholdable ones, the shoulder, and the farthest pose
  lever::plot::Chart map;
  map.title = "tip positions arm2 can hold still, shoulder limited to 6 N m";
  map.xlabel = "x from the shoulder (m)";
  map.ylabel = "z from the shoulder (m)";
  map.equal_aspect = true;
  map.width = 720;
  map.height = 680;
  auto dots = [](const std::string& label, const std::string& color, double radius) {
    lever::plot::Series s;
    s.label = label;
    s.color = color;
    s.style = lever::plot::Series::Style::kPoints;
    s.point_radius = radius;
    return s;
  };
  lever::plot::Series no = dots("not holdable", "#c8c8c8", 3.2);
  lever::plot::Series yes = dots("holdable", "#0072B2", 3.2);
  for (const auto& [cell, holds] : cells) {
    lever::plot::Series& s = holds ? yes : no;
    s.x.push_back((cell.first + 0.5) * kCell);
    s.y.push_back((cell.second + 0.5) * kCell);
  }
  map.series = {no, yes};
  evaluate(model, data, farthest.q, ee, shoulder);
  const Eigen::Vector3d elbow = data.xpos[model.body("link2")] - shoulder;
  lever::plot::Series arm;
  char reach[64];
  std::snprintf(reach, sizeof reach, "farthest: x = %.3f m", farthest.tip.x());
  arm.label = reach;
  arm.x = {0.0, elbow.x(), farthest.tip.x()};
  arm.y = {0.0, elbow.z(), farthest.tip.z()};
  arm.color = "#D55E00";
  map.series.push_back(arm);
  lever::plot::Series axis = dots("shoulder", "#000000", 5);
  axis.x = {0.0};
  axis.y = {0.0};
  map.series.push_back(axis);
  map.lines.push_back({lever::plot::RefLine::Axis::kVertical, farthest.tip.x(), "", "#D55E00"});
  map.xrange = {{-1.0, 1.45}};  // room on the right for the legend
  map.yrange = {{-0.95, 0.95}};
  lever::plot::write_file(svg_path, lever::plot::to_svg(map));
  std::printf("  workspace map: %s (each dot a %.0f cm cell of tip positions)\n", svg_path.c_str(),
              100 * kCell);
  return 0;
} catch (const std::exception& e) {  // a model that does not load, a file that cannot be written
  std::fprintf(stderr, "%s\n", e.what());
  return 1;
}
