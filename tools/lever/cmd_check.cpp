// lever check MODEL: lesson 5.1's six checks of a robot model and lesson 5.2's two more (the
// library in check/, lever/check.hpp). Exit status: 0 when every claim checks out, 1 with findings,
// 2 when the model cannot be loaded.
#include <cstdio>
#include <filesystem>
#include <string>

#include <lever/check.hpp>
#include <lever/mjcf.hpp>
#include <lever/plot.hpp>

#include "cli.hpp"
#include "commands.hpp"

namespace lever::cli {

namespace {

// FILE.svg -> FILE-<suffix>.svg
std::string beside(const std::string& path, const std::string& suffix) {
  std::filesystem::path p(path);
  const std::string stem = p.stem().string() + "-" + suffix + ".svg";
  return (p.parent_path() / stem).string();
}

void write_svg(const check::Report& report, const Args& args) {
  std::string path = args.get("svg");
  if (args.has("plot-dir")) {
    std::filesystem::create_directories(args.get("plot-dir"));
    const std::string name = report.model.empty() ? "model" : report.model;
    const std::string in_dir = args.get("plot-dir") + "/" + name;
    plot::write_file(in_dir + "-torque-budget.svg", check::torque_budget_svg(report));
    plot::write_file(in_dir + "-singular-poses.svg", check::singular_poses_svg(report));
    plot::write_file(in_dir + "-step-stability.svg", check::step_stability_svg(report));
    plot::write_file(in_dir + "-grip.svg", check::grip_svg(report));
  }
  if (!path.empty()) {
    plot::write_file(path, check::torque_budget_svg(report));
    plot::write_file(beside(path, "singular-poses"), check::singular_poses_svg(report));
    plot::write_file(beside(path, "step-stability"), check::step_stability_svg(report));
    plot::write_file(beside(path, "grip"), check::grip_svg(report));
  }
}

}  // namespace

void declare_check(CLI::App& command) {
  command.add_option("MODEL", "the model file (MJCF)")->type_name("FILE")->required();
  add_value(command, "key", "NAME",
            "sections (7) and (8) at keyframe NAME only (besides qpos0 in (7))")
      ->check(not_empty_check());
  add_switch(command, "json", "print the same content as one JSON object instead of text");
  add_value(command, "svg", "FILE",
            "also write the torque budget as a bar chart (SVG), and beside it\n"
            "FILE's stem + -singular-poses.svg, -step-stability.svg, -grip.svg")
      ->check(not_empty_check());
  add_value(command, "plot-dir", "DIR",
            "also write DIR/<model>-torque-budget.svg, -singular-poses.svg,\n"
            "-step-stability.svg and -grip.svg")
      ->check(not_empty_check());
  command.footer(
      "Check every claim a model makes, as lesson 5.1 does for arm2, and print section by "
      "section:\n"
      "  (1) what the compiled model contains (joints, motors, sites, bodies)\n"
      "  (2) forward kinematics of every site against independent formulas, at 1000 random poses\n"
      "  (3) the torque budget: worst-case gravity torque per joint, motor limit / gravity "
      "torque,\n"
      "      payloads, M(q), and the acceleration the spare torque gives\n"
      "  (4) explicit inertias against those inferred from the geoms\n"
      "  (5) soft joint stops: rest on each stop gravity can load and measure how far past it\n"
      "  (6) commands beyond ctrlrange, and motors that cannot hold their own arm\n"
      "  (7) singular poses: the site Jacobian's singular values over the joint ranges, the most\n"
      "      singular poses, manipulability and condition number at qpos0 and the keyframes, and\n"
      "      which joint axes align there\n"
      "  (8) stability of the step at each keyframe (else qpos0): spectral radius of the step's\n"
      "      linearisation for the model's integrator and explicit Euler, the largest stable\n"
      "      timestep, the smallest armature that keeps Euler stable (each searched on a log "
      "grid,\n"
      "      every change of stability found bisected and listed), confirmed by simulation\n"
      "  (9) contacts (lesson 5.3): the geom pairs that can touch and their mixed parameters, the\n"
      "      depth a free body rests at on a plane against solref/solimp's steady state, and the\n"
      "      force two finger servos need to hold a box (2 mu F >= m g) against a simulation that\n"
      "      lowers the grip until the box slips\n"
      "  A model with ball or free joints skips (2), (3), (5), (7) and (8), saying why.\n"
      "\n"
      "Exit status: 0 every claim checks out, 1 findings (listed at the end), 2 the model cannot "
      "be\n"
      "loaded.");
}

int cmd_check(const Args& args) {
  const std::string& path = args.positional()[0];

  check::Report report;
  try {
    report = check::check_file(path, args.get("key"));
  } catch (const StateError& e) {  // the only state check_file takes is --key
    std::fprintf(stderr, "lever check: --key: %s\n", e.what());
    return kBadInput;
  } catch (const Error& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return kBadInput;
  }
  write_svg(report, args);
  if (args.has("json")) {
    check::write_json(stdout, report);
  } else {
    std::fputs(check::to_text(report).c_str(), stdout);
  }
  for (const std::string& f : report.findings) {
    if (f.find("engine warnings") != std::string::npos) {
      std::fprintf(stderr, "lever check: warning: %s\n", f.c_str());
    }
  }
  return report.exit_status();
}

}  // namespace lever::cli
