// lever simulate: step a model from a start state and print, save or plot the trajectory.
//
//   lever simulate MODEL [--steps N | --duration T] [--qpos ..] [--qvel ..]
//                        [--ctrl .. | --torque ..] [--gravity-compensation] [--excite F]
//                        [--json] [--csv FILE] [--plot FILE.svg]
//
// The controller and the loop are lesson 5.1's lab (lever/lab/lab.hpp): the trajectory has one row
// per state visited, the start state and the state after every step (N + 1 rows for N steps).
//
// Clamping is silent in the physics (as in MuJoCo); this command counts, per motor, the steps
// whose command was clamped to ctrlrange (or its force to forcerange) and reports it on stderr.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <lever/io/serialize.hpp>
#include <lever/lab/lab.hpp>
#include <lever/lever.hpp>
#include <lever/mjcf.hpp>
#include <lever/plot.hpp>

#include "cli.hpp"
#include "commands.hpp"
#include "forward_state.hpp"

namespace lever::cli {

namespace {

using lab::Controller;

// One JSON line per state: time and the lab's readouts, by their names in the field table, and
// the sensors' numbers when the model has sensors.
void json_row(const Model& model, const Data& d) {
  static const std::vector<std::string> arrays = {
      "qpos", "qvel", "qacc", "qfrc_bias", "qfrc_constraint", "ctrl", "actuator_force"};
  static const std::vector<std::string> sensors = {"sensordata"};
  Json json(stdout);
  json.begin_object();
  json.key("time").value(d.time);
  write_data_arrays(json, model, d, arrays);
  if (model.nsensor > 0) write_data_arrays(json, model, d, sensors);
  write_contacts(json, model, d);  // ncon and each contact with its force
  json.end_object();
  json.newline();
}

// ---- the plot ------------------------------------------------------------------------------

// What the plot needs, recorded while the simulation runs (every `stride`-th row, and the last).
struct PlotRecord {
  std::vector<int> sites;  // the trail: the site named "ee", or every site
  std::vector<double> time;
  std::vector<std::vector<double>> qpos;              // [joint][row]
  std::vector<std::vector<double>> site_x, site_z;    // [trail site][row]
  std::vector<Eigen::Vector3d> start_body, end_body;  // body origins at the first and last row
  std::vector<Eigen::Vector3d> start_site, end_site;  // site positions at the first and last row

  void add(const Model& m, const Data& d) {
    time.push_back(d.time);
    for (int j = 0; j < m.njnt; ++j) qpos[j].push_back(d.qpos[m.jnt_qposadr[j]]);
    for (size_t i = 0; i < sites.size(); ++i) {
      site_x[i].push_back(d.site_xpos[sites[i]].x());
      site_z[i].push_back(d.site_xpos[sites[i]].z());
    }
  }
};

// The arm drawn as segments: each body's origin to its parent's (bodies hanging from the world
// start at their own origin), and each site to its body's origin.
void add_skeleton(plot::Chart& chart, const Model& m, const std::vector<Eigen::Vector3d>& body,
                  const std::vector<Eigen::Vector3d>& site, const std::string& label,
                  const std::string& color, bool dashed) {
  bool labelled = false;  // one legend entry for all the segments
  auto segment = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    plot::Series s;
    s.label = labelled ? "" : label;
    s.x = {a.x(), b.x()};
    s.y = {a.z(), b.z()};
    s.color = color;
    s.dashed = dashed;
    chart.series.push_back(s);
    labelled = true;
  };
  for (int b = 1; b < m.nbody; ++b) {
    if (m.body_parentid[b] != 0) segment(body[m.body_parentid[b]], body[b]);
  }
  for (int s = 0; s < m.nsite; ++s) segment(body[m.site_bodyid[s]], site[s]);
}

// Fix the chart's ranges to its data with a margin, and extra room at the top for the legend
// (the charts draw it inside the plotting area, top right).
void leave_room_for_legend(plot::Chart& chart, int entries) {
  double xlo = 1e300, xhi = -1e300, ylo = 1e300, yhi = -1e300;
  for (const plot::Series& s : chart.series) {
    for (size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      xlo = std::min(xlo, s.x[i]);
      xhi = std::max(xhi, s.x[i]);
      ylo = std::min(ylo, s.y[i]);
      yhi = std::max(yhi, s.y[i]);
    }
  }
  for (const plot::RefLine& l : chart.lines) {
    if (l.axis == plot::RefLine::Axis::kHorizontal) {
      ylo = std::min(ylo, l.at);
      yhi = std::max(yhi, l.at);
    }
  }
  if (!(xlo <= xhi && ylo <= yhi)) return;  // no data: the chart's defaults
  const double xspan = std::max(xhi - xlo, 1e-3), yspan = std::max(yhi - ylo, 0.1);
  const double legend = 0.07 * entries + 0.04;  // of the height, per legend line
  chart.xrange = {{xlo - 0.03 * xspan, xhi + 0.03 * xspan}};
  chart.yrange = {{ylo - 0.05 * yspan, yhi + yspan * legend / (1 - legend)}};
}

std::string describe(const Model& m, const Controller& c, const Eigen::VectorXd& qpos0) {
  std::string s = m.name + ": ctrl = " + vec_text(c.torque, "%g");
  if (c.gravity_compensation) s += " + gravity compensation";
  return s + ", start qpos = " + vec_text(qpos0, "%g");
}

plot::Figure make_figure(const Model& m, const PlotRecord& r, const std::string& title) {
  plot::Figure fig;
  fig.title = title;

  // joint angles over time, with any joint stop the trace comes near
  plot::Chart angles;
  angles.title = "joint positions";
  angles.xlabel = "time (s)";
  bool all_hinges = true;
  for (int j = 0; j < m.njnt; ++j) all_hinges = all_hinges && m.jnt_type[j] == JointType::kHinge;
  angles.ylabel = all_hinges ? "angle (rad)" : "qpos (rad or m)";
  angles.width = 600;
  angles.height = 420;
  for (int j = 0; j < m.njnt; ++j) {
    plot::Series s;
    s.label = label_of(m.jnt_name[j], j) + " (" + joint_units(m, j).pos + ")";
    s.x = r.time;
    s.y = r.qpos[j];
    s.dashed = j % 2 == 1;
    angles.series.push_back(s);
    if (!m.jnt_limited[j] || s.y.empty()) continue;
    const auto [lo, hi] = m.jnt_range[j];
    const double near = 0.1 * (hi - lo);
    const auto [min_it, max_it] = std::minmax_element(s.y.begin(), s.y.end());
    char text[96];
    if (*min_it < lo + near) {
      std::snprintf(text, sizeof text, "%s stop %g", label_of(m.jnt_name[j], j).c_str(), lo);
      angles.lines.push_back({plot::RefLine::Axis::kHorizontal, lo, text, "#888888"});
    }
    if (*max_it > hi - near) {
      std::snprintf(text, sizeof text, "%s stop %g", label_of(m.jnt_name[j], j).c_str(), hi);
      angles.lines.push_back({plot::RefLine::Axis::kHorizontal, hi, text, "#888888"});
    }
  }
  leave_room_for_legend(angles, static_cast<int>(angles.series.size()));
  fig.charts.push_back(angles);

  // the trail in the x-z plane, the arm at the start and at the end, and the first joint
  plot::Chart trail;
  trail.title =
      r.sites.size() == 1
          ? std::string("trail of site ").append(label_of(m.site_name[r.sites[0]], r.sites[0]))
          : "trails of the sites";
  trail.xlabel = "x (m)";
  trail.ylabel = "z (m)";
  trail.equal_aspect = true;
  trail.width = 460;
  trail.height = 420;
  add_skeleton(trail, m, r.start_body, r.start_site, "arm at start", "#999999", true);
  add_skeleton(trail, m, r.end_body, r.end_site, "arm at end", "#222222", false);
  const char* const kTrailColors[] = {"#E69F00", "#009E73", "#CC79A7", "#56B4E9"};
  for (size_t i = 0; i < r.sites.size(); ++i) {
    plot::Series s;
    s.label = std::string("trail of ").append(label_of(m.site_name[r.sites[i]], r.sites[i]));
    s.x = r.site_x[i];
    s.y = r.site_z[i];
    s.color = kTrailColors[i % 4];
    trail.series.push_back(s);
  }
  if (m.nv > 0) {
    // the first joint's anchor (the shoulder), where the arm is fixed to the world
    plot::Series s;
    s.label = label_of(m.jnt_name[m.dof_jntid[0]], m.dof_jntid[0]) + " axis";
    s.style = plot::Series::Style::kPoints;
    s.point_radius = 4.5;
    s.color = "#0072B2";
    s.x = {r.start_body[m.dof_bodyid[0]].x()};
    s.y = {r.start_body[m.dof_bodyid[0]].z()};
    trail.series.push_back(s);
  }
  leave_room_for_legend(trail, 4);
  fig.charts.push_back(trail);
  return fig;
}

// ---- the text summary ----------------------------------------------------------------------

void print_summary_row(const Model& m, const Data& d) {
  std::printf("  %8.3f", d.time);
  for (int j = 0; j < m.njnt; ++j)
    std::printf(" %11s", num(d.qpos[m.jnt_qposadr[j]], "%.5f").c_str());
  for (int a = 0; a < m.nu; ++a) std::printf(" %11s", num(d.actuator_force[a], "%.4f").c_str());
  std::printf("\n");
}

void print_summary_header(const Model& m) {
  std::printf("  %8s", "time (s)");
  for (int j = 0; j < m.njnt; ++j) {
    std::printf(" %11s",
                std::string("q ").append(label_of(m.jnt_name[j], j)).substr(0, 11).c_str());
  }
  for (int a = 0; a < m.nu; ++a) {
    std::printf(" %11s",
                std::string("f ").append(label_of(m.actuator_name[a], a)).substr(0, 11).c_str());
  }
  std::printf("\n  (q: qpos in rad or m; f: actuator_force in N m or N)\n");
}

// The lab's readouts at the last state.
void print_readouts(const Model& m, const Data& d) {
  std::printf("\nat t = %g s (the last state):\n", d.time);
  std::printf("  %-10s %12s %12s %12s %12s %15s\n", "joint", "qpos", "qvel", "qfrc_bias",
              "actuator_force", "qfrc_constraint");
  for (int j = 0; j < m.njnt; ++j) {
    const int v = m.jnt_dofadr[j];
    std::string force = "-";
    for (int a = 0; a < m.nu; ++a) {
      if (actuator_scalar_dof(m, a) < 0 || m.actuator_trnid[a][0] != j) continue;
      force = num(d.actuator_force[a]);
    }
    std::printf("  %-10s %12s %12s %12s %12s %15s\n", label_of(m.jnt_name[j], j).c_str(),
                num(d.qpos[m.jnt_qposadr[j]]).c_str(), num(d.qvel[v]).c_str(),
                num(d.qfrc_bias[v]).c_str(), force.c_str(), num(d.qfrc_constraint[v]).c_str());
  }
}

struct FileCloser {
  void operator()(std::FILE* f) const {
    if (f && f != stdout) std::fclose(f);
  }
};

}  // namespace

void declare_simulate(CLI::App& command) {
  command.add_option("MODEL", "the model file (MJCF)")->type_name("FILE")->required();
  add_value(command, "steps", "N", "number of steps of the model's timestep")
      ->check(whole_number_check());
  add_value(command, "duration", "T", "simulated time in s, rounded to whole steps (default: 1 s)")
      ->check(number_check())
      ->excludes("--steps");
  add_state_options(command, {"start from keyframe NAME: its time, qpos, qvel and ctrl (the\n"
                              "lists below override them)",
                              "start positions, nq numbers (default: qpos0)",
                              "start velocities, nv numbers (default: zeros)",
                              "constant motor commands, nu numbers (default: zeros, or the\n"
                              "keyframe's with --key)"});
  add_value(command, "torque", "LIST",
            "the same as --ctrl, under the name lesson 5.1's lab gives it")
      ->check(number_list_check())
      ->excludes("--ctrl");
  add_switch(command, "gravity-compensation",
             "add qfrc_bias of the current state to every command (the lab's\n"
             "gc switch): ctrl = torque + qfrc_bias[dof] / gear, every step");
  add_value(command, "excite", "F",
            "excitation for `lever identify`: each motor's joint tracks a sum\n"
            "of three sines sweeping the fraction F of its range, PD-tracked\n"
            "(added to the other commands)")
      ->check(number_check());
  add_switch(command, "json",
             "one JSON line per state (start, then after each step): time qpos\n"
             "qvel qacc qfrc_bias qfrc_constraint ctrl actuator_force, ncon\n"
             "and contact (each contact's geoms, dist, pos, frame, ... and\n"
             "force in its frame, as lever forward --json), and sensordata\n"
             "when the model has sensors");
  add_value(command, "csv", "FILE",
            "the trajectory as CSV with a header row ('-': standard output);\n"
            "a sensor's numbers are columns name[0], name[1], ...")
      ->check(not_empty_check());
  add_value(command, "plot", "FILE.svg",
            "joint angles over time and the site trail in the x-z plane")
      ->check(not_empty_check());
  command.footer(
      "Without --json, a short table of the run is printed. Steps whose command was clamped are\n"
      "counted per motor and reported on stderr.\n"
      "Exit status: 0; 1 when the engine warned or a number came out non-finite; 2 for bad input.");
}

int cmd_simulate(const Args& command_line) {
  const auto [args, model_path, model] = begin("simulate", command_line, [](const Args& given) {
    if (given.has("json") && given.get("csv") == "-") {
      throw UsageError{"--json and --csv - both write to standard output: give a file to --csv"};
    }
  });
  Data data(model);
  set_state_from_args(args, model, data);  // --qpos, --qvel (and --ctrl, replaced below)

  // one run is bounded: a mistyped --steps or --duration must not run for days
  constexpr long kMaxSteps = 10'000'000;
  long steps = 0;
  if (args.has("steps")) {
    steps = args.get_long("steps", 0);
    if (steps < 0) throw UsageError{"--steps must not be negative"};
    if (steps > kMaxSteps) {
      throw UsageError{"--steps " + std::to_string(steps) + " is more than one run's limit of " +
                       std::to_string(kMaxSteps) + " steps"};
    }
  } else {
    const double duration = args.get_double("duration", 1.0);
    if (duration < 0) throw UsageError{"--duration must not be negative"};
    const double whole_steps = std::round(duration / model.opt.timestep);
    if (!(whole_steps <= static_cast<double>(kMaxSteps))) {
      throw UsageError{"--duration " + num(duration, "%g") + " s is more than one run's limit of " +
                       std::to_string(kMaxSteps) + " steps of " + num(model.opt.timestep, "%g") +
                       " s"};
    }
    steps = static_cast<long>(whole_steps);
  }

  Controller controller;
  controller.torque = args.get_vector(args.has("torque") ? "torque" : "ctrl", model.nu,
                                      data.ctrl);  // zeros, or the keyframe's with --key
  controller.gravity_compensation = args.has("gravity-compensation");
  controller.excite = args.get_double("excite", 0.0);
  try {
    lab::validate(model, controller);
  } catch (const StateError& e) {
    throw UsageError{e.what()};
  }

  std::unique_ptr<std::FILE, FileCloser> csv;
  const CsvWriter csv_writer(model, simulate_csv_arrays());
  if (args.has("csv")) {
    const std::string path = args.get("csv");
    csv.reset(path == "-" ? stdout : std::fopen(path.c_str(), "w"));
    if (!csv) throw std::runtime_error(std::string("cannot open '").append(path) + "' for writing");
    std::fputs(csv_writer.header().c_str(), csv.get());
  }

  PlotRecord record;
  const bool plotting = args.has("plot");
  if (plotting) plot::write_file(args.get("plot"), "");  // fail now rather than after the run
  const long rows = steps + 1;
  const long stride = std::max(1L, (rows + 1999) / 2000);  // at most about 2000 points a trace
  if (plotting) {
    for (int s = 0; s < model.nsite; ++s) {
      if (model.site_name[s] == "ee") record.sites = {s};
    }
    if (record.sites.empty()) {
      for (int s = 0; s < model.nsite; ++s) record.sites.push_back(s);
    }
    record.qpos.resize(model.njnt);
    record.site_x.resize(record.sites.size());
    record.site_z.resize(record.sites.size());
  }

  const bool text = !args.has("json") && !(csv && csv.get() == stdout);
  const long every = std::max(1L, steps / 10);
  const Eigen::VectorXd start_qpos = data.qpos;
  if (text) {
    std::printf("%s, %ld steps of %g s (%g s)\n", describe(model, controller, start_qpos).c_str(),
                steps, model.opt.timestep, static_cast<double>(steps) * model.opt.timestep);
    print_summary_header(model);
  }

  const lab::RunLog log = lab::run(model, data, controller, steps, [&](long k, const Data& d) {
    if (args.has("json")) json_row(model, d);
    if (csv) std::fputs(csv_writer.row(d).c_str(), csv.get());
    if (text && (k % every == 0 || k == steps)) print_summary_row(model, d);
    if (plotting) {
      if (k == 0) {
        record.start_body = d.xpos.to_vector();
        record.start_site = d.site_xpos.to_vector();
      }
      if (k == steps) {
        record.end_body = d.xpos.to_vector();
        record.end_site = d.site_xpos.to_vector();
      }
      if (k % stride == 0 || k == steps) record.add(model, d);
    }
  });
  if (text) print_readouts(model, data);
  if (csv && csv.get() != stdout && std::ferror(csv.get())) {
    throw std::runtime_error(std::string("cannot write '").append(args.get("csv")) + "'");
  }
  csv.reset();

  if (plotting) {
    plot::write_file(
        args.get("plot"),
        plot::to_svg(make_figure(model, record, describe(model, controller, start_qpos))));
  }

  // what the physics does silently: states reset after a blow-up (and other engine warnings),
  // numbers that came out non-finite, clamped commands
  print_warnings("simulate", log.warnings);
  if (log.non_finite_rows > 0) print_non_finite("simulate");
  long total = 0;
  for (const long n : log.clamped) total += n;
  if (total > 0) {
    std::string line = "lever simulate: commands clamped to ctrlrange/forcerange in";
    for (int a = 0; a < model.nu; ++a) {
      char buf[160];
      std::snprintf(buf, sizeof buf, "%s %s %ld of %ld steps", a ? "," : "",
                    label_of(model.actuator_name[a], a).c_str(),
                    log.clamped[static_cast<size_t>(a)], steps);
      line += buf;
    }
    std::fprintf(stderr, "%s\n", line.c_str());
  }
  return log.warnings.count() > 0 || log.non_finite_rows > 0 ? kFindings : kOk;
}

}  // namespace lever::cli
