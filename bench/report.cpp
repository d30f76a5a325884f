// lever_bench_report: Google Benchmark's JSON output of lever_bench -> docs/performance.md.
//
//   lever_bench_report RESULTS.json [--check CHECK.md] [--instructions INSTRUCTIONS.json]
//                      [--web WEB.json] > docs/performance.md
//
// For every <operation>/<model>/<peer>, the median of the repetitions' CPU times and their spread
// (interquartile range over the median); lever's median over each peer's; beside them, when
// bench/instructions.py's counts are given, the instructions per call (callgrind) and their
// ratio, which do not depend on the machine's load; the browser peer (web/bench/
// peer_step_time.mjs, `make web-bench`); and whether the speed targets (forward and step a tenth
// to a quarter of MuJoCo's, the kernels at or below MuJoCo's own, the browser, the batches) are
// met, by time and by instructions. No dependency besides the C++ standard library and the tests'
// small JSON reader (tests/support/json_reader.hpp).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "json_reader.hpp"

namespace {

using Json = lever::test::json::Value;

// ---- the measurements ---------------------------------------------------------------------------

struct Stats {
  double median = NAN;  // ns (time) or states/s (throughput)
  double iqr = NAN;     // interquartile range / median
  int repetitions = 0;
};

double quantile(std::vector<double> v, double q) {  // linear interpolation, v not empty
  std::sort(v.begin(), v.end());
  const double pos = q * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(pos));
  const std::size_t hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (pos - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

Stats stats_of(const std::vector<double>& samples) {
  Stats s;
  if (samples.empty()) return s;
  s.median = quantile(samples, 0.5);
  s.iqr = (quantile(samples, 0.75) - quantile(samples, 0.25)) / s.median;
  s.repetitions = static_cast<int>(samples.size());
  return s;
}

double to_ns(double t, const std::string& unit) {
  if (unit == "us") return t * 1e3;
  if (unit == "ms") return t * 1e6;
  if (unit == "s") return t * 1e9;
  return t;
}

struct Results {
  std::map<std::string, std::vector<double>> times;       // run name -> CPU ns per repetition
  std::map<std::string, std::vector<double>> throughput;  // run name -> items/s per repetition
  std::map<std::string, Stats> times_stats, throughput_stats;

  std::optional<Stats> time(const std::string& op, const std::string& model,
                            const std::string& peer) const {
    const auto it = times_stats.find(op + "/" + model + "/" + peer);
    if (it == times_stats.end()) return std::nullopt;
    return it->second;
  }
};

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string part;
  std::istringstream in(s);
  while (std::getline(in, part, sep)) out.push_back(part);
  return out;
}

Json read_json(const std::string& path) {  // throws std::runtime_error naming the file
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::stringstream text;
  text << in.rdbuf();
  try {
    return lever::test::json::parse(text.str());
  } catch (const std::exception& e) {
    throw std::runtime_error(path + ": " + e.what());
  }
}

// bench/instructions.py's counts: instructions per call by model, peer and operation, and the
// stages of forward for a few models
struct Instructions {
  const Json* root = nullptr;

  std::optional<double> count(const std::string& op, const std::string& model,
                              const std::string& peer) const {
    if (root == nullptr) return std::nullopt;
    const Json* models = root->find("models");
    const Json* m = models != nullptr ? models->find(model) : nullptr;
    const Json* p = m != nullptr ? m->find(peer) : nullptr;
    const Json* c = p != nullptr ? p->find(op) : nullptr;
    if (c == nullptr || c->kind != Json::Kind::kNumber) return std::nullopt;
    return c->number;
  }
  // [[function, instructions per call], ...] of one peer's forward on one model
  std::vector<std::pair<std::string, double>> stages(const std::string& model,
                                                     const std::string& peer) const {
    std::vector<std::pair<std::string, double>> out;
    const Json* all = root != nullptr ? root->find("stages") : nullptr;
    const Json* m = all != nullptr ? all->find(model) : nullptr;
    const Json* p = m != nullptr ? m->find(peer) : nullptr;
    if (p == nullptr) return out;
    for (const Json& row : p->array) {
      if (row.kind == Json::Kind::kArray && row.array.size() == 2)
        out.emplace_back(row.array[0].string, row.array[1].number);
    }
    return out;
  }
};

// web/bench/peer_step_time.mjs's result: one lab step in WebAssembly, lever against MuJoCo's
// official build
struct WebBench {
  const Json* root = nullptr;

  const Json* model(const std::string& name) const {
    const Json* models = root != nullptr ? root->find("models") : nullptr;
    return models != nullptr ? models->find(name) : nullptr;
  }
};

// ---- formatting ---------------------------------------------------------------------------------

std::string fmt(const char* format, double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, x);
  return buf;
}

std::string time_cell(const std::optional<Stats>& s) {
  if (!s) return "—";
  const double t = s->median;
  const std::string value = t < 10    ? fmt("%.2f", t)
                            : t < 100 ? fmt("%.1f", t)
                            : t < 1e5 ? fmt("%.0f", t)
                                      : fmt("%.3g", t);
  return value + " ±" + fmt("%.0f", 100 * s->iqr) + "%";
}

std::string ratio_text(double r) { return fmt(r < 0.1 ? "%.3f" : "%.2f", r); }

std::string ratio_cell(const std::optional<Stats>& lever, const std::optional<Stats>& peer) {
  if (!lever || !peer) return "—";
  return ratio_text(lever->median / peer->median);
}

std::string count_text(double n) { return fmt("%.0f", n); }  // instructions per call

std::string count_cell(const std::optional<double>& n) { return n ? count_text(*n) : "—"; }

std::string count_ratio_cell(const std::optional<double>& lever,
                             const std::optional<double>& peer) {
  if (!lever || !peer) return "—";
  return ratio_text(*lever / *peer);
}

// ---- what each operation times ------------------------------------------------------------------

struct Operation {
  const char* name;
  const char* lever;
  const char* mujoco;
  const char* kdl;
};

const Operation kOperations[] = {
    {"fk",
     "all frames: `poses`, every body's frame and centre-of-mass frame, every geom's and site's "
     "frame and each joint's anchor and axis, as (R, p) (all of `mj_kinematics` but `xquat`)",
     "`mj_kinematics` (the same, and `xquat`)",
     "`ChainFkSolverPos_recursive`: the tip frame (R, p) alone"},
    {"fk_tip",
     "`place_site` of the tip site: the frames (R, p) of the bodies from the tip to the world, "
     "then the site's",
     "`mj_kinematics` (MuJoCo has no call that places one frame)",
     "`ChainFkSolverPos_recursive`: the tip frame (R, p)"},
    {"kinematics",
     "`kinematics`: `poses`, `xquat`, then subtree centres of mass, com-frame inertias and dof "
     "axes",
     "`mj_kinematics` + `mj_comPos`", ""},
    {"jac_site", "`jac_site` (kinematics done)", "`mj_jacSite` (kinematics, comPos done)",
     "`ChainJntToJacSolver` (from q)"},
    {"bias", "`bias` (kinematics done)",
     "`mj_rne(flg_acc=0)` alone (kinematics, comPos, comVel done)", ""},
    {"bias_from_q", "`body_kinematics` (`kinematics` without geom and site frames) + `bias`",
     "`mj_kinematics` + `mj_comPos` + `mj_comVel` + `mj_rne(0)`", "`ChainIdSolver_RNE`, qddot = 0"},
    {"rnea", "`rnea(qacc)` (kinematics done)",
     "`mj_rne(flg_acc=1)` alone (kinematics, comPos, comVel done)", ""},
    {"rnea_from_q", "`body_kinematics` + `rnea(qacc)`",
     "`mj_kinematics` + `mj_comPos` + `mj_comVel` + `mj_rne(1)`", "`ChainIdSolver_RNE`"},
    {"crba", "`crba` (kinematics done)", "`mj_crb` alone (kinematics, comPos done)", ""},
    {"crba_factor", "`crba` + `factor_mass`", "`mj_crb` + `mj_factorM`", ""},
    {"crba_from_q", "`body_kinematics` + `crba`", "`mj_kinematics` + `mj_comPos` + `mj_crb`",
     "`ChainDynParam::JntToMass`"},
    {"inverse", "`inverse` (whole pipeline + RNEA)", "`mj_inverse`", ""},
    {"forward", "`forward`", "`mj_forward`", "`ChainFdSolver_RNE` (M, RNE, LDL only)"},
    {"forward_limit", "`forward`, one limit row", "`mj_forward`, one limit row", ""},
    {"step", "`step` (state restored each time)", "`mj_step` (state restored each time)", ""},
    {"step_limit", "`step`, one limit row", "`mj_step`, one limit row", ""},
    {"step_jacobian_centred", "`step_derivatives` (analytic A and B)",
     "`mjd_transitionFD`, centred", ""},
    {"step_jacobian_forward", "`step_derivatives` (analytic A and B)",
     "`mjd_transitionFD`, forward", ""},
};

// ---- Pinocchio (bench/pinocchio_ops.hpp): the operations and what each peer's row times ---------

struct PinocchioOperation {
  const char* name;
  const char* lever;
  const char* pinocchio;
};

const PinocchioOperation kPinocchioOperations[] = {
    {"fk_bodies", "`body_poses`: every body's frame", "`forwardKinematics`: every joint's placement"},
    {"bias_from_q", "`body_kinematics` (`kinematics` without geom and site frames) + `bias`",
     "`nonLinearEffects`"},
    {"rnea_from_q", "`body_kinematics` + `rnea(qacc)`", "`rnea`"},
    {"crba_from_q", "`body_kinematics` + `crba`", "`crba` (upper triangle)"},
    {"jac_site_from_q",
     "`jac_site_from_q` of the tip site: the bodies of its tree, the site's frame, its Jacobian",
     "`computeFrameJacobian` of the tip frame, `LOCAL_WORLD_ALIGNED` (the joints of its support, "
     "the frame's placement, its Jacobian)"},
    {"aba", "`body_kinematics` + `bias` + `crba` + `factor_mass` + `solve_mass` (lever has no ABA)",
     "`aba`"},
    {"rnea_derivatives", "`body_kinematics` + `crba` + `rnea_derivatives`",
     "`computeRNEADerivatives` (d tau / d q, d v and M)"},
    {"aba_derivatives",
     "`forward_derivatives` on the model without damping and actuator forces, tau as "
     "`qfrc_applied` (forward() included)",
     "`computeABADerivatives` (d a / d q, d v and M^-1)"},
};

// ---- the targets: each a ratio against its goal -------------------------------------------------

// One target: a ratio against a goal, measured in time and (where callgrind can count it) in
// instructions. Each ratio is lever's over the peer's: numerator over denominator.
struct Ratio {
  std::optional<double> numerator, denominator;
  std::string numerator_unit;  // "ns", "instructions", "states/s"
  bool known() const { return numerator && denominator && *denominator > 0; }
  double value() const { return *numerator / *denominator; }
};

struct Target {
  std::string text;
  double goal;
  bool at_least;  // the ratio must reach the goal (a speed-up), not stay below it
  Ratio time, instructions;

  std::string goal_text() const {
    return (at_least ? ">= " : "<= ") + fmt(goal < 1 ? "%.2f" : "%.1f", goal);
  }
};

std::string measured_cell(const Ratio& r, const char* unit_format) {
  if (!r.known()) return "—";
  return fmt(unit_format, *r.numerator) + " / " + fmt(unit_format, *r.denominator) + " = **" +
         ratio_text(r.value()) + "**";
}

// "met", or by how much it is missed: the ratio over the goal (at most), the goal over the ratio
// (at least)
std::string verdict(const Ratio& r, double goal, bool at_least) {
  if (!r.known()) return "not measured";
  const double v = r.value();
  const bool met = at_least ? v >= goal : v <= goal;
  if (met) return "met";
  const double by = at_least ? goal / v : v / goal;
  return "**missed** by " + fmt(by < 1.01 ? "%.3fx" : "%.2fx", by);
}

// true where the ratio is measured and misses its goal
bool missed(const Ratio& ratio, double goal, bool at_least) {
  return ratio.known() && (at_least ? ratio.value() < goal : ratio.value() > goal);
}

// the goals for the whole forward dynamics, per model (the targets and the explanation of a missed
// one read them)
std::map<std::string, double> forward_goals() {
  return {{"arm2", 0.10}, {"panda7", 0.20}, {"chain20", 0.25}};
}

// ---- the inputs ---------------------------------------------------------------------------------

struct Arguments {
  std::string json_path, check_path, instructions_path, web_path;
};

// the command line, or nothing (the usage said on stderr)
std::optional<Arguments> parse_arguments(int argc, char** argv) {
  const char* usage =
      "usage: lever_bench_report RESULTS.json [--check CHECK.md] [--instructions "
      "INSTRUCTIONS.json] [--web WEB.json]\n";
  Arguments a;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--check" && i + 1 < argc) {
      a.check_path = argv[++i];
    } else if (arg == "--instructions" && i + 1 < argc) {
      a.instructions_path = argv[++i];
    } else if (arg == "--web" && i + 1 < argc) {
      a.web_path = argv[++i];
    } else if (a.json_path.empty() && arg.rfind("--", 0) != 0) {
      a.json_path = arg;
    } else {
      std::cerr << usage;
      return std::nullopt;
    }
  }
  if (a.json_path.empty()) {
    std::cerr << usage;
    return std::nullopt;
  }
  return a;
}

// What every section reads: the benchmarks' repetitions and the run's context, the models in
// order, and the optional instruction counts, browser peer and checks. Not copied: counts and web
// point into the documents held here.
struct Inputs {
  Json root, instructions_root, web_root;
  const Json* context = nullptr;  // Google Benchmark's context (machine, build, models)
  Results results;
  std::vector<std::string> model_order;  // fewest joints first
  int repetitions = 0;                   // the most any benchmark ran
  Instructions counts;                   // empty without --instructions
  WebBench web;                          // empty without --web
  std::string check_path;                // empty without --check

  Inputs() = default;
  Inputs(const Inputs&) = delete;
  Inputs& operator=(const Inputs&) = delete;
};

// reads the files named on the command line into `in`; false (the error said on stderr) when one
// cannot be read or is not what it should be
bool read_inputs(const Arguments& a, Inputs& in) {
  const std::string& json_path = a.json_path;
  const std::string& instructions_path = a.instructions_path;
  const std::string& web_path = a.web_path;
  in.check_path = a.check_path;
  Json& root = in.root;
  Json& instructions_root = in.instructions_root;
  Json& web_root = in.web_root;
  try {
    root = read_json(json_path);
    if (!instructions_path.empty()) instructions_root = read_json(instructions_path);
    if (!web_path.empty()) web_root = read_json(web_path);
  } catch (const std::exception& e) {
    std::cerr << "lever_bench_report: " << e.what() << "\n";
    return false;
  }
  if (!instructions_path.empty()) {
    if (instructions_root.find("models") == nullptr) {
      std::cerr << "lever_bench_report: " << instructions_path
                << " is not bench/instructions.py's output\n";
      return false;
    }
    in.counts.root = &instructions_root;
  }
  if (!web_path.empty()) {
    if (web_root.find("models") == nullptr) {
      std::cerr << "lever_bench_report: " << web_path
                << " is not web/bench/peer_step_time.mjs's output\n";
      return false;
    }
    in.web.root = &web_root;
  }
  const Json* context = root.find("context");
  const Json* benchmarks = root.find("benchmarks");
  if (context == nullptr || benchmarks == nullptr) {
    std::cerr << "lever_bench_report: " << json_path << " is not Google Benchmark JSON output\n";
    return false;
  }
  in.context = context;

  // the repetitions of each benchmark (aggregates are recomputed here)
  Results& r = in.results;
  std::vector<std::string> order;  // run names in the order of their first appearance
  for (const Json& b : benchmarks->array) {
    if (b.str("run_type") != "iteration" || b.find("error_occurred") != nullptr) continue;
    std::string name = b.str("run_name", b.str("name"));
    const std::string real_time = "/real_time";  // UseRealTime() benchmarks carry this suffix
    if (name.size() > real_time.size() &&
        name.compare(name.size() - real_time.size(), real_time.size(), real_time) == 0) {
      name.resize(name.size() - real_time.size());
    }
    if (r.times.find(name) == r.times.end()) order.push_back(name);
    r.times[name].push_back(to_ns(b.num("cpu_time"), b.str("time_unit", "ns")));
    const double items = b.num("items_per_second");
    if (!std::isnan(items)) r.throughput[name].push_back(items);
  }
  for (const auto& [name, samples] : r.times) r.times_stats[name] = stats_of(samples);
  for (const auto& [name, samples] : r.throughput) r.throughput_stats[name] = stats_of(samples);
  // the models, fewest joints first (lever_bench records "nv=<n> ..." for each in the context)
  std::vector<std::pair<int, std::string>> by_nv;
  for (const std::string& name : order) {
    const auto parts = split(name, '/');
    if (parts.size() < 3) continue;
    const std::string about = context->str("model." + parts[1]);
    const int nv = about.rfind("nv=", 0) == 0 ? std::atoi(about.c_str() + 3) : 0;
    if (std::find(by_nv.begin(), by_nv.end(), std::pair{nv, parts[1]}) == by_nv.end())
      by_nv.emplace_back(nv, parts[1]);
  }
  std::sort(by_nv.begin(), by_nv.end());
  std::vector<std::string>& model_order = in.model_order;
  model_order.reserve(by_nv.size());
  for (const auto& [nv, model] : by_nv) model_order.push_back(model);
  for (const auto& [name, s] : r.times_stats)
    in.repetitions = std::max(in.repetitions, s.repetitions);
  return true;
}

// ---- the document, section by section -----------------------------------------------------------

// the title, how to read the figures, and the run: date, commit, machine, build, peers, models
void write_header(std::ostream& out, const Inputs& in) {
  const Json* context = in.context;
  const Json& instructions_root = in.instructions_root;
  const Json& web_root = in.web_root;
  const int repetitions = in.repetitions;
  const std::vector<std::string>& model_order = in.model_order;
  out << "# Performance: lever against MuJoCo 2.2.2 and Orocos KDL\n\n";
  out << "_Generated by `make bench` (bench/report.cpp from Google Benchmark's JSON); do not edit "
         "by hand._\n\n";
  out << "Every figure is the **median CPU time of one call** over " << repetitions
      << " repetitions, run in one process with Google Benchmark's random interleaving; `±` is the "
         "interquartile range of the repetitions over their median. **Ratios are lever's median "
         "over "
         "the peer's** (below 1: lever is faster; 0.10 = ten times faster). Absolute times depend "
         "on "
         "the machine; the ratios are what the targets are about.\n\n";

  out << "| | |\n|---|---|\n";
  out << "| date | " << context->str("date") << " |\n";
  out << "| lever commit | " << context->str("lever_commit", "(not recorded)") << " |\n";
  out << "| machine | " << context->str("cpu_model") << ", " << context->str("num_cpus")
      << " CPUs, " << context->str("mhz_per_cpu") << " MHz |\n";
  if (const Json* load = context->find("load_avg");
      load != nullptr && load->kind == Json::Kind::kArray) {
    out << "| load average at start | ";
    for (std::size_t i = 0; i < load->array.size(); ++i)
      out << (i ? ", " : "") << fmt("%.2f", load->array[i].number);
    const double cpus = context->num("num_cpus", 1);
    if (!load->array.empty() && load->array[0].number > cpus) {
      out << " (**busy**: more runnable tasks than the " << context->str("num_cpus")
          << " CPUs, so absolute times are inflated and the 2-thread batch figures mean little; "
             "the "
             "interleaved ratios suffer less)";
    }
    out << " |\n";
  }
  out << "| compiler | " << context->str("compiler") << " |\n";
  out << "| build type | " << context->str("cmake_build_type") << " |\n";
  out << "| flags | `" << context->str("cxx_flags") << "` |\n";
  out << "| peers | MuJoCo " << context->str("mujoco_version") << " and Orocos KDL "
      << context->str("kdl_version") << " (Debian's prebuilt libraries), Eigen "
      << context->str("eigen_version");
  if (const std::string pin = context->str("pinocchio_version"); !pin.empty()) {
    out << "; Pinocchio " << pin << " (pip's `pin`, its wheels' prebuilt libraries)";
  }
  out << " |\n";
  const std::string gb_build = context->str("library_build_type");
  out << "| Google Benchmark | library built as " << gb_build
      << (gb_build == "debug"
              ? " (it says so when built without NDEBUG, as Debian's package is; the timing loop "
                "`for (auto _ : state)` is inline in lever's Release code, the same for every peer)"
              : "")
      << " |\n";
  for (const std::string& model : model_order) {
    out << "| model " << model << " | " << context->str("model." + model) << " |\n";
  }
  const std::string commit = context->str("lever_commit", "(not recorded)");
  // a source measured at another commit than the times is said so
  auto commit_note = [&](const std::string& other) {
    return other == commit ? std::string(" (the same commit)")
                           : " (**another commit than the times'**: " + other + ")";
  };
  if (in.counts.root != nullptr) {
    out << "| instruction counts | " << instructions_root.str("tool")
        << ", `bench/instructions.py`: each operation's loop of "
        << instructions_root.str("iterations")
        << " calls counted alone, the loop's own cost subtracted; commit "
        << instructions_root.str("lever_commit", "(not recorded)")
        << commit_note(instructions_root.str("lever_commit", "(not recorded)")) << "; took "
        << instructions_root.str("seconds") << " s |\n";
  }
  if (in.web.root != nullptr) {
    out << "| WebAssembly peer | " << web_root.str("date") << ", node " << web_root.str("node")
        << ", npm `mujoco-js` " << web_root.str("mujoco_js") << " (MuJoCo "
        << web_root.str("mujoco_version") << "), commit " << web_root.str("lever_commit")
        << commit_note(web_root.str("lever_commit")) << " |\n";
  }
  out << "\n";
}

// the sensor model (lever_bench's context says "sensors: nsensor=..." of it): timed on forward alone
bool sensor_model(const Inputs& in, const std::string& model) {
  return in.context->str("model." + model).find(" sensors: nsensor=") != std::string::npos;
}

// every target with its goal and this run's ratios
std::vector<Target> collect_targets(const Inputs& in) {
  const Results& r = in.results;
  const Instructions& counts = in.counts;
  const std::vector<std::string>& model_order = in.model_order;
  std::vector<Target> targets;
  const auto time_of = [&](const std::string& op, const std::string& model,
                           const std::string& peer) -> std::optional<double> {
    const auto t = r.time(op, model, peer);
    if (!t) return std::nullopt;
    return t->median;
  };
  // lever's op on a model against a peer's, in time and in instructions
  const auto against = [&](const std::string& text, double goal, const std::string& op,
                           const std::string& model, const std::string& peer) {
    targets.push_back({text,
                       goal,
                       false,
                       {time_of(op, model, "lever"), time_of(op, model, peer), "ns"},
                       {counts.count(op, model, "lever"), counts.count(op, model, peer), ""}});
  };
  const std::map<std::string, double> goals = forward_goals();
  against("arm2 `forward` / `mj_forward`", goals.at("arm2"), "forward", "arm2", "mujoco");
  against("arm2 `forward` / `mj_forward`, one limit active", 0.10, "forward_limit", "arm2",
          "mujoco");
  against("arm2 `step` / `mj_step`", 0.10, "step", "arm2", "mujoco");
  against("arm2 `step` / `mj_step`, one limit active", 0.10, "step_limit", "arm2", "mujoco");
  for (const std::string model : {"panda7", "chain20"}) {
    against(model + " `forward` / `mj_forward`", goals.at(model), "forward", model, "mujoco");
  }
  // the contact scene (lesson 5.3's gripper), each peer with its own contact solver
  against("gripper `forward` / `mj_forward`, box resting in contact", 0.5, "forward", "gripper",
          "mujoco");
  against("gripper `step` / `mj_step`, box resting in contact", 0.5, "step", "gripper", "mujoco");
  // the sensor stages: tests/models/sensors.xml, every sensor type lever evaluates, both peers
  // evaluating the same sensors inside their forward
  against("sensors `forward` / `mj_forward`, every sensor type lever evaluates", 0.5, "forward",
          "sensors", "mujoco");
  // a mesh gripper (bench/scenes: the Panda hand's finger meshes closed on a box, MPR)
  against("mesh_gripper `forward` / `mj_forward`, Panda finger meshes holding a box", 0.5,
          "forward", "mesh_gripper", "mujoco");
  for (const auto& [op, peer_call, g] :
       {std::tuple{"bias", "`mj_rne`", 0.7}, std::tuple{"crba", "`mj_crb`", 1.0},
        std::tuple{"jac_site", "`mj_jacSite`", 1.0}}) {
    for (const std::string& model : model_order) {
      if (sensor_model(in, model)) continue;  // timed on forward alone
      against(model + " `" + op + "` / " + peer_call, g, op, model, "mujoco");
    }
  }
  for (const std::string& model : model_order) {
    // one frame from q against one frame from q: `fk_tip` (the `fk` row places every frame)
    if (!r.time("fk_tip", model, "kdl") && !counts.count("fk_tip", model, "kdl")) continue;
    against(model + " `fk_tip` / KDL's `ChainFkSolverPos`", 1.0, "fk_tip", model, "kdl");
  }
  // the analytic step Jacobian against one forward: both lever's
  targets.push_back({"panda7 analytic step Jacobian (`step_derivatives`) / one panda7 `forward`",
                     5.0,
                     false,
                     {time_of("step_jacobian_forward", "panda7", "lever"),
                      time_of("forward", "panda7", "lever"), "ns"},
                     {counts.count("step_jacobian_forward", "panda7", "lever"),
                      counts.count("forward", "panda7", "lever"), ""}});
  // the same with contacts pushing (the gripper's scene: the box resting on the table)
  targets.push_back({"gripper analytic step Jacobian with contacts (`step_derivatives`) / one "
                     "gripper `forward`",
                     5.0,
                     false,
                     {time_of("step_jacobian_forward", "gripper", "lever"),
                      time_of("forward", "gripper", "lever"), "ns"},
                     {counts.count("step_jacobian_forward", "gripper", "lever"),
                      counts.count("forward", "gripper", "lever"), ""}});
  // the browser peer (make web-bench): time only
  for (const auto& [model, g] : {std::pair{"arm2", 0.12}, std::pair{"panda7", 0.25}}) {
    Ratio t{std::nullopt, std::nullopt, "ns"};
    if (const Json* w = in.web.model(model)) t = {w->num("lever_ns"), w->num("mujoco_ns"), "ns"};
    targets.push_back({std::string("wasm lab step / MuJoCo ") +
                           (in.web.root ? in.web_root.str("mujoco_version") : "3.3.8") + " wasm (" +
                           model + ")",
                       g,
                       false,
                       t,
                       {}});
  }
  // batches: states per second on 2 threads over 1 thread, for every batch benchmark
  bool any_batch_target = false;
  for (const auto& [name, stats2] : r.throughput_stats) {
    const std::string two = "/lever/threads:2";
    if (name.size() <= two.size() || name.compare(name.size() - two.size(), two.size(), two) != 0)
      continue;
    const std::string family = name.substr(0, name.size() - two.size());
    const auto one = r.throughput_stats.find(family + "/lever/threads:1");
    if (one == r.throughput_stats.end()) continue;
    targets.push_back({"`" + family + "`: states per second, 2 threads / 1 thread",
                       1.8,
                       true,
                       {stats2.median, one->second.median, "states/s"},
                       {}});
    any_batch_target = true;
  }
  if (!any_batch_target) {
    targets.push_back({"batch: states per second, 2 threads / 1 thread", 1.8, true, {}, {}});
  }
  return targets;
}

// the targets' table: goal, both ratios, met or missed by how much
void write_targets(std::ostream& out, const std::vector<Target>& targets) {
  out << "## Targets\n\n"
         "Each ratio is lever's over the peer's (for the step Jacobian: over lever's own "
         "`forward`; for the batch: 2 threads' throughput over 1 thread's). The time ratio is "
         "of medians in this run; the instruction ratio is of callgrind's exact counts, which do "
         "not depend on the load of the machine (MuJoCo's and KDL's prebuilt code runs the same "
         "instructions per call anywhere; a time ratio far from the instruction ratio says where "
         "the time is spent other than in instructions: memory, branches, `sincos`).\n\n"
         "| target | goal | time (ns): lever / peer | instructions: lever / peer | by time | by "
         "instructions |\n|---|---|---|---|---|---|\n";
  for (const Target& t : targets) {
    const char* unit = t.time.numerator_unit == "states/s" ? "%.3g" : "%.1f";
    out << "| " << t.text << " | " << t.goal_text() << " | " << measured_cell(t.time, unit) << " | "
        << measured_cell(t.instructions, "%.0f") << " | " << verdict(t.time, t.goal, t.at_least)
        << " | " << (t.instructions.known() ? verdict(t.instructions, t.goal, t.at_least) : "—")
        << " |\n";
  }
  out << "\n";
}

// why the whole forward dynamics misses its goal: the share of mj_forward's instructions spent on
// the work lever's forward does too, and what a step and an active limit add
void explain_missed_forward(std::ostream& out, const Instructions& counts) {
  // the stages of mj_forward that do what lever's forward does too (MuJoCo's stage profile, the
  // last section)
  const std::vector<std::string> shared_stages{"mj_kinematics",
                                               "mj_comPos",
                                               "mj_transmission",
                                               "mj_crb",
                                               "mj_factorM",
                                               "mj_comVel",
                                               "mj_passive",
                                               "mj_rne",
                                               "mj_fwdActuation",
                                               "mj_fwdAcceleration",
                                               "mj_makeConstraint",
                                               "mj_projectConstraint",
                                               "mj_referenceConstraint",
                                               "mj_fwdConstraint"};
  for (const auto& [model, goal] : forward_goals()) {
    const auto mujoco_stages = counts.stages(model, "mujoco");
    const auto lever_forward = counts.count("forward", model, "lever");
    const auto mujoco_forward = counts.count("forward", model, "mujoco");
    if (mujoco_stages.empty() || !lever_forward || !mujoco_forward) continue;
    double shared = 0;
    std::vector<std::string> other;
    for (const auto& [name, c] : mujoco_stages) {
      if (std::find(shared_stages.begin(), shared_stages.end(), name) != shared_stages.end())
        shared += c;
      else if (c >= 0.05 * *mujoco_forward)
        other.push_back("`" + name + "` " + count_text(c));
    }
    std::string others;
    for (const std::string& o : other) others += (others.empty() ? "" : ", ") + o;
    const double allowed = goal * *mujoco_forward;
    out << "- **" << model << " `forward` (goal " << fmt("%.2f", goal) << ")**: `mj_forward` "
        << "runs " << count_text(*mujoco_forward) << " instructions, " << count_text(shared)
        << " of them in the stages that compute what lever's `forward` "
        << "computes too (kinematics, com quantities, M and its factor, velocities, passive "
        << "and bias forces, actuation, the constraint stage), the rest in what lever does not "
        << "need on this model (" << others << "). The goal allows lever " << count_text(allowed)
        << " instructions: " << fmt("%.2f", allowed / shared)
        << " of MuJoCo's for the same work, i.e. " << fmt("%.1f", shared / allowed)
        << "x fewer instructions than MuJoCo's own kernels. lever's `forward` runs "
        << count_text(*lever_forward) << " (" << fmt("%.2f", *lever_forward / shared)
        << " of that work's), and its kernels one by one reach the ratios of the `bias`, "
        << "`crba` and `jac_site` rows (0.5-1.0 of MuJoCo's): each kernel would have to run at "
        << fmt("%.0f", 100 * allowed / shared) << "% of MuJoCo's instructions.";
    // what a step and an active limit add, each against what they add to MuJoCo's call
    const auto added = [&](const char* op) -> std::optional<std::pair<double, double>> {
      const auto l = counts.count(op, model, "lever"), m = counts.count(op, model, "mujoco");
      if (!l || !m) return std::nullopt;
      return std::make_pair(*l - *lever_forward, *m - *mujoco_forward);
    };
    if (const auto step = added("step")) {
      out << " `step` adds " << count_text(step->first) << " instructions to lever's `forward` "
          << "(the integrator's work: Euler's implicit damping factors M + h D and solves "
          << "with it again, as `mj_Euler` does; `implicit` its own pass) and "
          << count_text(step->second) << " to `mj_forward`'s.";
    }
    if (const auto limit = added("forward_limit")) {
      out << " An active limit adds " << count_text(limit->first) << " instructions to lever's "
          << "`forward` against " << count_text(limit->second) << " to `mj_forward`'s ("
          << ratio_text(limit->first / limit->second) << "): the row, its soft parameters and "
          << "a one-row solve.";
    }
    out << " Computing the dynamics in body coordinates instead (Featherstone's tables as "
        << "printed, MuJoCo's frames only where read) was tried for the step and was not "
        << "cheaper: docs/conventions.md says why.\n";
  }
}

// a time ratio missed where the instruction ratio is met: for a short call, the run's noise; for
// a long one (microseconds), the time per instruction beside its peer's, and what a count misses
void explain_missed_by_time_alone(std::ostream& out, const std::vector<Target>& targets) {
  constexpr double kShortCallNs = 1000.0;
  for (const Target& t : targets) {
    if (!missed(t.time, t.goal, t.at_least) || !t.instructions.known() ||
        missed(t.instructions, t.goal, t.at_least))
      continue;
    out << "- " << t.text << ": met by instructions (" << ratio_text(t.instructions.value())
        << "), missed by time (" << ratio_text(t.time.value()) << "): ";
    const bool long_call = t.time.numerator_unit == "ns" && *t.time.numerator >= kShortCallNs;
    if (!long_call) {
      out << "the median of a call this short (tens to hundreds of nanoseconds) moves by more "
          << "than that from run to run on this machine (see the ± columns below); the "
          << "instruction count is exact.\n";
    } else {
      // time per thousand instructions, the call's and its peer's
      const double call_rate = *t.time.numerator / *t.instructions.numerator * 1000.0;
      const double peer_rate = *t.time.denominator / *t.instructions.denominator * 1000.0;
      out << "the call takes " << fmt("%.1f", *t.time.numerator / 1000.0) << " µs, "
          << fmt("%.0f", call_rate) << " ns per thousand instructions against its peer's "
          << fmt("%.0f", peer_rate) << ": an instruction count weighs a division, a cache miss "
          << "or a mispredicted branch as one instruction, and the median moves from run to run "
          << "too (the ± columns below). callgrind's cache and branch simulation "
          << "(`valgrind --tool=callgrind --cache-sim=yes --branch-sim=yes`) shows where.\n";
    }
  }
}

// the number of dofs lever_bench recorded for a model ("nv=<n> ..." in the context), 0 if none
double dofs_of(const Json& context, const std::string& model) {
  const std::string about = context.str("model." + model);
  const std::size_t at = about.find("nv=");
  return at == std::string::npos ? 0.0 : std::atof(about.c_str() + at + 3);
}

// the kernels missed by instructions: what each computes beyond its peer
void explain_missed_kernels(std::ostream& out, const Inputs& in) {
  const Instructions& counts = in.counts;
  const std::vector<std::string>& model_order = in.model_order;
  for (const std::string& model : model_order) {
    const auto lever_fk = counts.count("fk_tip", model, "lever");
    const auto kdl_fk = counts.count("fk_tip", model, "kdl");
    const double nv = dofs_of(*in.context, model);
    if (!lever_fk || !kdl_fk || nv <= 0 || *lever_fk <= *kdl_fk) continue;
    out << "- " << model << " `fk_tip` / KDL: lever's `place_site` runs " << count_text(*lever_fk)
        << " instructions (" << count_text(*lever_fk / nv) << " per joint), KDL's tip frame "
        << count_text(*kdl_fk) << " (" << count_text(*kdl_fk / nv)
        << " per joint). Both evaluate one `sincos` per hinge and compose one frame per body "
        << "from the world to the tip; `place_site` also checks the state on entry, walks the "
        << "path through the model's index arrays and writes each body's frame into `Data`, "
        << "where the Jacobians and MuJoCo's callers read it.\n";
  }
  for (const std::string& model : model_order) {
    const auto lever_bias = counts.count("bias", model, "lever");
    const auto mujoco_bias = counts.count("bias", model, "mujoco");
    if (!lever_bias || !mujoco_bias || *lever_bias <= 0.7 * *mujoco_bias) continue;
    out << "- " << model << " `bias` / `mj_rne`: " << count_text(*lever_bias) << " against "
        << count_text(*mujoco_bias) << " instructions (" << ratio_text(*lever_bias / *mujoco_bias)
        << "): lever's RNEA runs over the com-frame quantities `kinematics` leaves and does "
        << "`mj_comVel`'s work too (the velocities and `cdof_dot`), each one-dof body in one "
        << "step and its net force by Newton and Euler's equations about the frame origin "
        << "(recursion.hpp); what remains is the six-vector products of that frame.\n";
  }
  for (const std::string& model : model_order) {
    const auto lever_crba = counts.count("crba", model, "lever");
    const auto mujoco_crba = counts.count("crba", model, "mujoco");
    if (!lever_crba || !mujoco_crba || *lever_crba <= *mujoco_crba) continue;
    const double nv = dofs_of(*in.context, model);
    out << "- " << model << " `crba` / `mj_crb`: " << count_text(*lever_crba) << " against "
        << count_text(*mujoco_crba) << " instructions (" << ratio_text(*lever_crba / *mujoco_crba)
        << "). Where a model has simple bodies (a free body about its centre of mass), both "
        << "copy their constant diagonal (`dof_M0`) instead of computing it; beyond that, "
        << "lever's M is dense, so crba writes all " << count_text(nv * nv)
        << " entries every call, the zero couplings of a simple body "
        << "and those between branches included, where MuJoCo's sparse "
        << "`qM` holds only each dof's ancestors and clears them in one call; and lever sums "
        << "every body's composite inertia, which the implicit step and the derivatives read "
        << "after it.\n";
  }
  if (const auto jac = counts.count("step_jacobian_forward", "panda7", "lever"),
      fwd = counts.count("forward", "panda7", "lever");
      jac && fwd && *jac > 5.0 * *fwd) {
    out << "- panda7 step Jacobian: " << count_text(*jac) << " instructions, "
        << fmt("%.2f", *jac / *fwd) << " forwards: one forward, an analytic RNEA-derivative "
        << "pass and one of the velocity product's polar form (dM at the step's acceleration "
        << "and D's change), the implicit step's "
        << "factorisation of M - h D along the tree and one solve of its 2 nv + nu "
        << "right-hand sides, and the chain rule through the integrator (dense nv x nv "
        << "products). The Jacobian's own work is counted against a forward that has itself "
        << "become cheaper: the ratio's denominator moves with every gain in forward.\n";
  }
  if (const auto jac = counts.count("step_jacobian_forward", "gripper", "lever"),
      fwd = counts.count("forward", "gripper", "lever");
      jac && fwd && *jac > 5.0 * *fwd) {
    out << "- gripper step Jacobian with contacts: " << count_text(*jac) << " instructions, "
        << fmt("%.2f", *jac / *fwd) << " forwards: the state's forward; a second forward at the "
        << "step's end, which says whether the constraints' active set changed within the step "
        << "(the Jacobian's warning and flag); the analytic RNEA-derivative passes; each "
        << "contact's distance, point and frame differentiated on dual numbers (its case held, "
        << "checked against the collision stage's contact, and probed where its closed form can "
        << "jump); the held rows' derivatives and their solve; and the chain rule through the "
        << "integrator. The two forwards alone spend two of the five the goal allows.\n";
  }
  if (const auto lever_forward = counts.count("forward", "mesh_gripper", "lever"),
      mujoco_forward = counts.count("forward", "mesh_gripper", "mujoco");
      lever_forward && mujoco_forward && *lever_forward > 0.5 * *mujoco_forward) {
    double mujoco_collision = 0;
    for (const auto& [name, c] : counts.stages("mesh_gripper", "mujoco")) {
      if (name == "mj_collision") mujoco_collision = c;
    }
    out << "- mesh_gripper `forward` in contact: " << count_text(*lever_forward) << " against "
        << count_text(*mujoco_forward) << " instructions ("
        << ratio_text(*lever_forward / *mujoco_forward) << ").";
    if (mujoco_collision > 0) {
      const double allowed = 0.5 * *mujoco_forward;
      out << " `mj_collision` is " << count_text(mujoco_collision) << " of MuJoCo's; there both "
          << "engines run libccd's MPR (lever its own writing of it) on the finger meshes' hulls "
          << "with the same support points "
          << "(MuJoCo's hill-climb over each hull, from its start, in its order, so that the "
          << "same vertex and so the same contact is found), and that share cannot fall far "
          << "below MuJoCo's. The goal allows lever " << count_text(allowed) << " instructions "
          << "in all; with collision at MuJoCo's instructions that would leave "
          << count_text(std::max(0.0, allowed - mujoco_collision)) << " for the rest, "
          << fmt("%.2f", std::max(0.0, allowed - mujoco_collision) /
                             (*mujoco_forward - mujoco_collision))
          << " of MuJoCo's rest (the rows, the solve, the smooth stages).";
    }
    out << "\n";
  }
  for (const std::string& model : {std::string("gripper"), std::string("box_drop")}) {
    const auto lever_forward = counts.count("forward", model, "lever");
    const auto mujoco_forward = counts.count("forward", model, "mujoco");
    if (!lever_forward || !mujoco_forward || *lever_forward <= 0.5 * *mujoco_forward) continue;
    out << "- " << model << " `forward` in contact: " << count_text(*lever_forward) << " against "
        << count_text(*mujoco_forward) << " instructions ("
        << ratio_text(*lever_forward / *mujoco_forward)
        << "). lever solves the pyramid's rows exactly (active sets in dof space, "
           "docs/contact.md) "
        << "where MuJoCo stops its iterative solver at its tolerance. The rows are built "
        << "through each contact's frame (a pyramid's edges are combinations of its rows, "
        << "J^T D J summed per contact over the dofs that move one body against the other, "
        << "each contact's soft parameters computed once, the collision filters fixed in "
        << "set_const); what is left is the work itself, spread thin: building the rows (a "
        << "point Jacobian per contact), the solve's row products, J^T D J and the Cholesky "
        << "factor of M + J^T D J (on box_drop a dense 6 x 6: each of the free body's dofs "
        << "moves every contact).\n";
  }
}

// the batches (the machine's two cores) and the WebAssembly rows
void explain_missed_batches_and_wasm(std::ostream& out, const Inputs& in) {
  const Json* context = in.context;
  const Results& r = in.results;
  const std::vector<std::string>& model_order = in.model_order;
  std::string load_text = "not recorded";
  if (const Json* load = context->find("load_avg");
      load != nullptr && load->kind == Json::Kind::kArray && !load->array.empty())
    load_text = fmt("%.2f", load->array[0].number);
  out << "- the batches (2 threads / 1 thread): this machine has " << context->str("num_cpus")
      << " CPUs (a virtual machine: other guests and the run's own other processes share "
      << "them); the load average at the start was " << load_text
      << ". A speed-up of 1.8 needs both cores free for the whole run; each thread's work is "
      << "independent (one Data each, states taken in chunks from a shared counter).";
  // MuJoCo's own batch, split the same way over the same two cores, in the same run: what the
  // machine gives a second thread
  double mujoco_low = 0.0, mujoco_high = 0.0, widest_iqr = 0.0;
  for (const std::string& model : model_order) {
    for (const char* threads : {"/threads:1", "/threads:2"}) {
      const auto l = r.throughput_stats.find("batch_forward/" + model + "/lever" + threads);
      if (l != r.throughput_stats.end()) widest_iqr = std::max(widest_iqr, l->second.iqr);
    }
    const auto m1 = r.throughput_stats.find("batch_forward/" + model + "/mujoco/threads:1");
    const auto m2 = r.throughput_stats.find("batch_forward/" + model + "/mujoco/threads:2");
    if (m1 == r.throughput_stats.end() || m2 == r.throughput_stats.end()) continue;
    const double speedup = m2->second.median / m1->second.median;
    mujoco_low = mujoco_low == 0.0 ? speedup : std::min(mujoco_low, speedup);
    mujoco_high = std::max(mujoco_high, speedup);
  }
  if (mujoco_high > 0.0) {
    out << " MuJoCo's own batch, one mjData per thread, gains " << fmt("%.2f", mujoco_low) << "-"
        << fmt("%.2f", mujoco_high)
        << "x from its second thread in the same run (the batch table below), and lever's "
           "throughputs spread by up to ±"
        << fmt("%.0f", 100 * widest_iqr)
        << "% over the repetitions: one run on this machine cannot tell a 1.8 from a 1.4.";
  }
  out << "\n";
  out << "- the WebAssembly rows: the same work as `forward` and `step` in lever's wasm, "
      << "against MuJoCo 3.3.8's (a later MuJoCo than 2.2.2, built by its authors); the ratio "
      << "misses for the reasons of the `forward` rows above.";
  // the same lab step natively in this run (forward + step against mj_forward + mj_step): the
  // floor the wasm ratio starts from
  std::string native;
  for (const std::string& model : {std::string("arm2"), std::string("panda7")}) {
    const auto lf = r.time("forward", model, "lever"), ls = r.time("step", model, "lever");
    const auto mf = r.time("forward", model, "mujoco"), ms = r.time("step", model, "mujoco");
    if (!lf || !ls || !mf || !ms) continue;
    native += (native.empty() ? "" : ", ") + model + " " +
              ratio_text((lf->median + ls->median) / (mf->median + ms->median));
  }
  if (!native.empty()) {
    out << " Natively, in this run, the same lab step (`forward` then `step`) is " << native
        << " of MuJoCo 2.2.2's (`mj_forward` then `mj_step`), before any cost of WebAssembly "
        << "itself; the wasm goals are 0.12 and 0.25.";
  }
  out << "\n\n";
}

// why the missed targets are missed, from this run's own numbers (nothing when all are met)
void write_why_missed(std::ostream& out, const Inputs& in, const std::vector<Target>& targets) {
  bool any_missed = false;
  for (const Target& t : targets)
    any_missed = any_missed || missed(t.time, t.goal, t.at_least) ||
                 missed(t.instructions, t.goal, t.at_least);
  if (!any_missed) return;
  out << "### Why the missed targets are missed\n\n";
  explain_missed_forward(out, in.counts);
  explain_missed_by_time_alone(out, targets);
  explain_missed_kernels(out, in);
  explain_missed_batches_and_wasm(out, in);
}

// the table operation x model: times, ratios and (when counted) instructions per call
void write_times_table(std::ostream& out, const Inputs& in) {
  const Results& r = in.results;
  const Instructions& counts = in.counts;
  const std::vector<std::string>& model_order = in.model_order;
  const bool with_counts = counts.root != nullptr;
  out << "## Times per call (ns) and ratios" << (with_counts ? "; instructions per call" : "")
      << "\n\n";
  out << "| operation | model | lever | MuJoCo | KDL | lever/MuJoCo | lever/KDL |";
  if (with_counts) {
    out << " instructions lever | MuJoCo | KDL | instructions lever/MuJoCo | lever/KDL |";
  }
  out << "\n|---|---|---:|---:|---:|---:|---:|" << (with_counts ? "---:|---:|---:|---:|---:|" : "")
      << "\n";
  for (const Operation& op : kOperations) {
    for (const std::string& model : model_order) {
      const auto l = r.time(op.name, model, "lever");
      const auto m = r.time(op.name, model, "mujoco");
      const auto k = r.time(op.name, model, "kdl");
      const auto li = counts.count(op.name, model, "lever");
      const auto mi = counts.count(op.name, model, "mujoco");
      const auto ki = counts.count(op.name, model, "kdl");
      if (!l && !m && !k && !li && !mi && !ki) continue;
      out << "| " << op.name << " | " << model << " | " << time_cell(l) << " | " << time_cell(m)
          << " | " << time_cell(k) << " | " << ratio_cell(l, m) << " | " << ratio_cell(l, k)
          << " |";
      if (with_counts) {
        out << " " << count_cell(li) << " | " << count_cell(mi) << " | " << count_cell(ki) << " | "
            << count_ratio_cell(li, mi) << " | " << count_ratio_cell(li, ki) << " |";
      }
      out << "\n";
    }
  }
  out << "\n";
}

// forward dynamics in batches: lever's and MuJoCo's states per second on 1 and 2 threads
void write_batch_forward(std::ostream& out, const Inputs& in) {
  const Json* context = in.context;
  const Results& r = in.results;
  const std::vector<std::string>& model_order = in.model_order;
  bool any_batch = false;
  for (const auto& [name, s] : r.throughput_stats)
    any_batch = any_batch || name.rfind("batch_forward/", 0) == 0;
  if (!any_batch) return;
  out << "## Batch forward dynamics: states per second (BatchRunner)\n\n";
  out << context->str("batch_states") << " different states per call, no limit active; one Data "
      << "(lever) or mjData (MuJoCo) per thread; lever's threads take the states in chunks from "
         "a "
      << "shared counter, MuJoCo's in one contiguous block each; "
      << "lever's runner keeps its worker threads between calls, MuJoCo's are started per "
      << "call (tens of microseconds per call). Wall-clock throughput, median ± IQR.\n\n";
  out << "| model | threads | lever (states/s) | MuJoCo (states/s) | lever/MuJoCo throughput | "
         "lever speed-up 2 vs 1 thread | MuJoCo speed-up 2 vs 1 thread |\n";
  out << "|---|---:|---:|---:|---:|---:|---:|\n";
  for (const std::string& model : model_order) {
    for (const int threads : {1, 2}) {
      const std::string suffix = "/threads:" + std::to_string(threads);
      const auto l = r.throughput_stats.find("batch_forward/" + model + "/lever" + suffix);
      const auto m = r.throughput_stats.find("batch_forward/" + model + "/mujoco" + suffix);
      const auto l1 = r.throughput_stats.find("batch_forward/" + model + "/lever/threads:1");
      const auto m1 = r.throughput_stats.find("batch_forward/" + model + "/mujoco/threads:1");
      if (l == r.throughput_stats.end()) continue;
      auto cell = [&](const auto& it) {
        return it == r.throughput_stats.end() ? std::string("—")
                                              : fmt("%.3g", it->second.median) + " ±" +
                                                    fmt("%.0f", 100 * it->second.iqr) + "%";
      };
      out << "| " << model << " | " << threads << " | " << cell(l) << " | " << cell(m) << " | "
          << (m == r.throughput_stats.end() ? "—"
                                            : fmt("%.1fx", l->second.median / m->second.median))
          << " | "
          << (l1 == r.throughput_stats.end() ? "—"
                                             : fmt("%.2fx", l->second.median / l1->second.median))
          << " | "
          << (m == r.throughput_stats.end() || m1 == r.throughput_stats.end()
                  ? "—"
                  : fmt("%.2fx", m->second.median / m1->second.median))
          << " |\n";
    }
  }
  out << "\n";
}

// the lessons' batch workloads: lever alone, the speed-up from a second thread
void write_lesson_batches(std::ostream& out, const Inputs& in) {
  const Results& r = in.results;
  const std::vector<std::string>& model_order = in.model_order;
  bool any_lesson_batch = false;
  for (const auto& [name, s] : r.throughput_stats) {
    any_lesson_batch = any_lesson_batch || name.rfind("batch_workspace_map/", 0) == 0 ||
                       name.rfind("batch_rollout/", 0) == 0;
  }
  if (!any_lesson_batch) return;
  out << "## The lessons' batches: states per second against threads (BatchRunner)\n\n"
         "`batch_workspace_map`: exercise 2's workspace map, forward() at rest on a 64 x 64 grid "
         "over the first two joints' ranges. `batch_rollout`: 256 rollouts of 50 steps each "
         "(states per second counts steps). Wall-clock throughput, median ± IQR.\n\n"
         "| workload | model | 1 thread (states/s) | 2 threads (states/s) | speed-up |\n"
         "|---|---|---:|---:|---:|\n";
  for (const char* family : {"batch_workspace_map", "batch_rollout"}) {
    for (const std::string& model : model_order) {
      const std::string base = std::string(family) + "/" + model + "/lever/threads:";
      const auto one = r.throughput_stats.find(base + "1");
      const auto two = r.throughput_stats.find(base + "2");
      if (one == r.throughput_stats.end() || two == r.throughput_stats.end()) continue;
      out << "| `" << family << "` | " << model << " | " << fmt("%.3g", one->second.median) << " ±"
          << fmt("%.0f", 100 * one->second.iqr) << "% | " << fmt("%.3g", two->second.median) << " ±"
          << fmt("%.0f", 100 * two->second.iqr) << "% | "
          << fmt("%.2fx", two->second.median / one->second.median) << " |\n";
    }
  }
  out << "\n";
}

// what each operation times, for each peer, and what differs between them
void write_operations(std::ostream& out) {
  out << "## What each operation times\n\n";
  out << "Every peer gets the same model file and the same state (qpos, qvel, qacc, ctrl drawn "
         "once per "
         "model with a fixed seed, every joint inside its range; the `_limit` variants put the "
         "first "
         "limited joint, the shoulder, 1 mrad past its lower stop). Stages a peer needs before the "
         "timed call run once before the timing loop. The contact scenes (lesson 5.3's models) "
         "are timed on `forward`, `step` and the three kernels whose targets name every model "
         "(`bias`, `crba`, `jac_site`), at rest in contact (their model row says how "
         "many contacts), each peer with the contact solver its file asks for: MuJoCo's "
         "iterative one at its tolerance, lever's exact solve.\n\n";
  out << "| operation | lever | MuJoCo | KDL |\n|---|---|---|---|\n";
  for (const Operation& op : kOperations) {
    out << "| " << op.name << " | " << op.lever << " | " << op.mujoco << " | "
        << (*op.kdl ? op.kdl : "—") << " |\n";
  }
  out << "\nNotes. lever's `kinematics` does the work of `mj_kinematics` and `mj_comPos` together "
         "(poses, "
         "then subtree centres of mass, body inertias and dof axes in MuJoCo's com-based frame), "
         "and "
         "its `bias` that of `mj_comVel` and `mj_rne` (the `bias` row counts `mj_rne` alone, "
         "`mj_comVel` having run before it: lever's row also computes the velocities); lever's "
         "`step` runs `forward` without the outputs nothing in a step reads (`xquat`, and the "
         "geom frames where nothing can collide); "
         "`mj_forward` and `mj_step` also run collision "
         "detection (nothing collides in these models), sensors and MuJoCo's iterative constraint "
         "solver, which lever replaces with an exact solve of the limit rows. KDL's forward "
         "dynamics "
         "has no passive forces, motors or limits, and KDL's solvers always start from q (they "
         "recompute every segment pose), so KDL is compared on the `*_from_q`, `fk`, `fk_tip`, "
         "`jac_site` and "
         "`forward` rows. KDL's tip Jacobian and FK give one frame: `fk_tip` compares it with "
         "lever's "
         "`place_site`, which places the tip site and the bodies on its path alone (MuJoCo has no "
         "such call: its `fk_tip` is the whole `mj_kinematics`); the `fk` row places every frame, "
         "every body, geom and site (lever's `poses`, which leaves out the quaternions "
         "`mj_kinematics` also composes; `kinematics` has them and MuJoCo's `mj_comPos`); the "
         "`*_from_q` rows run lever's `body_kinematics`, `kinematics` without the geom and site "
         "frames, which neither M, the bias nor inverse dynamics reads (MuJoCo has no such call "
         "and places them all). lever's "
         "flags include `-ffp-contract=off` (no fused multiply-add); "
         "nothing is "
         "built with `-march=native`. The instruction counts run the same calls on the same states "
         "(`lever_bench_profile`, bench/README.md); lever's step Jacobian is one call, counted "
         "once for both of MuJoCo's finite differences.\n\n";
}

// lever against Pinocchio: times, instructions and their ratios, each operation from the state
void write_pinocchio(std::ostream& out, const Inputs& in) {
  const Results& r = in.results;
  const Instructions& counts = in.counts;
  const std::string version = in.context != nullptr ? in.context->str("pinocchio_version") : "";
  out << "## lever against Pinocchio" << (version.empty() ? "" : " " + version) << "\n\n";
  if (version.empty()) {
    out << "Not in this run: the benchmark was built without the Pinocchio peer (make bench "
           "installs pip's `pin` into `build-bench/venv-pinocchio`; CMake's configure output "
           "says why it was skipped).\n\n";
    return;
  }
  out << "Pinocchio " << version << " from pip's `pin` (its wheels' prebuilt libraries), on every "
         "serial chain, the model built from the same chain as KDL's (every joint turned to its "
         "frame's z: `JointModelRZ`, Pinocchio's fastest revolute joint), the same state; every "
         "operation starts from q, as Pinocchio's algorithms do. The checks below prove every "
         "quantity equal to lever's to the 1e-12 bound first. A ratio above 1 is where Pinocchio "
         "is faster.\n\n";
  out << "| operation | lever | Pinocchio |\n|---|---|---|\n";
  for (const PinocchioOperation& op : kPinocchioOperations) {
    out << "| " << op.name << " | " << op.lever << " | " << op.pinocchio << " |\n";
  }
  const bool with_counts = counts.root != nullptr;
  out << "\n| operation | model | lever (ns) | Pinocchio (ns) | lever/Pinocchio |";
  if (with_counts) out << " instructions lever | Pinocchio | instructions lever/Pinocchio |";
  out << "\n|---|---|---:|---:|---:|" << (with_counts ? "---:|---:|---:|" : "") << "\n";
  std::vector<std::string> slower;
  for (const PinocchioOperation& op : kPinocchioOperations) {
    for (const std::string& model : in.model_order) {
      const auto l = r.time(op.name, model, "lever");
      const auto p = r.time(op.name, model, "pinocchio");
      const auto li = counts.count(op.name, model, "lever");
      const auto pi = counts.count(op.name, model, "pinocchio");
      if (!p && !pi) continue;
      out << "| " << op.name << " | " << model << " | " << time_cell(l) << " | " << time_cell(p)
          << " | " << ratio_cell(l, p) << " |";
      if (with_counts) {
        out << " " << count_cell(li) << " | " << count_cell(pi) << " | "
            << count_ratio_cell(li, pi) << " |";
      }
      out << "\n";
      if (l && p && p->median > 0 && l->median > p->median) {
        slower.push_back("`" + std::string(op.name) + "` on " + model + " (" +
                         ratio_text(l->median / p->median) + "x in time" +
                         (li && pi && *pi > 0 ? ", " + ratio_text(*li / *pi) + "x in instructions"
                                              : std::string()) +
                         ")");
      }
    }
  }
  out << "\n";
  if (slower.empty()) {
    out << "lever is at or below Pinocchio on every operation and model measured.\n\n";
  } else {
    out << "Where Pinocchio is faster (median times): ";
    for (std::size_t i = 0; i < slower.size(); ++i) out << (i ? "; " : "") << slower[i];
    out << ".\n\n";
  }
}

// the browser peer: the lab step in WebAssembly against MuJoCo's official build
void write_browser_peer(std::ostream& out, const Inputs& in) {
  if (in.web.root == nullptr) return;
  const Json& web_root = in.web_root;
  out << "## In WebAssembly: the lab step against MuJoCo " << web_root.str("mujoco_version")
      << "'s official build\n\n"
      << "`make web-bench` (web/bench/peer_step_time.mjs): lever's WebAssembly build through "
         "web/lever.js, as the lab runs it, against npm `mujoco-js` "
      << web_root.str("mujoco_js")
      << ", in one node process. One lab step is `mj_forward`, the controller (reads data, "
         "writes ctrl), `mj_step`, called from JavaScript on each engine's own API, from the "
         "same start; each round times the same number of steps on both, alternating which "
         "goes first. Medians of the node process's CPU time over "
      << web_root.str("rounds") << " rounds, `±` the interquartile range over the median.\n\n";
  out << "| | |\n|---|---|\n";
  out << "| date | " << web_root.str("date") << " |\n";
  out << "| lever commit | " << web_root.str("lever_commit") << " |\n";
  out << "| machine | " << web_root.str("cpu_model") << ", " << web_root.str("num_cpus")
      << " CPUs |\n";
  if (const Json* load = web_root.find("load_avg");
      load != nullptr && load->kind == Json::Kind::kArray) {
    out << "| load average at start | ";
    for (std::size_t i = 0; i < load->array.size(); ++i)
      out << (i ? ", " : "") << fmt("%.2f", load->array[i].number);
    out << " |\n";
  }
  out << "| node | " << web_root.str("node") << " |\n";
  out << "| sizes | lever_wasm.wasm " << fmt("%.0f", web_root.num("lever_wasm_bytes"))
      << " bytes; mujoco-js's mujoco_wasm.js (the wasm inside) "
      << fmt("%.0f", web_root.num("mujoco_js_bytes")) << " bytes |\n\n";
  out << "| model | start and controller | lever (ns per step) | MuJoCo (ns per step) | "
         "lever/MuJoCo | steps per round | max \\|qpos difference\\| after 1 s |\n"
         "|---|---|---:|---:|---:|---:|---:|\n";
  const Json* models = web_root.find("models");
  for (std::size_t i = 0; i < models->keys.size(); ++i) {
    const Json& m = models->members[i];
    out << "| " << models->keys[i] << " | " << m.str("controller") << " | "
        << fmt("%.0f", m.num("lever_ns")) << " ±" << fmt("%.0f", 100 * m.num("lever_iqr")) << "% | "
        << fmt("%.0f", m.num("mujoco_ns")) << " ±" << fmt("%.0f", 100 * m.num("mujoco_iqr"))
        << "% | " << ratio_text(m.num("lever_ns") / m.num("mujoco_ns")) << " | "
        << fmt("%.0f", m.num("steps_per_round")) << " | "
        << fmt("%.1e", m.num("qpos_max_diff_after_1s")) << " |\n";
  }
  out << "\nThe last column checks that both engines run the same simulation: one second "
         "from the same start set moving (every joint at 0.5 rad/s), the same controller.\n\n";
}

// one peer's call by function (or stage) x model, from per-model lists, in the first model's
// order; fold_small sums the functions under 1% of every model's call in one row
void write_stage_table(std::ostream& out, const Instructions& counts,
                       const std::vector<std::string>& staged, const std::string& peer,
                       const std::string& first_column, bool fold_small) {
  std::vector<std::string> names;
  std::map<std::string, std::map<std::string, double>> cost;  // name -> model -> count
  std::map<std::string, double> total;
  for (const std::string& model : staged) {
    for (const auto& [name, c] : counts.stages(model, peer)) {
      if (cost.find(name) == cost.end()) names.push_back(name);
      cost[name][model] = c;
      total[model] += c;
    }
  }
  out << "| " << first_column << " |";
  for (const std::string& model : staged) out << " " << model << " | share |";
  out << "\n|---|";
  for (std::size_t i = 0; i < staged.size(); ++i) out << "---:|---:|";
  out << "\n";
  std::map<std::string, double> small;
  int small_count = 0;
  for (const std::string& name : names) {
    bool large = !fold_small;
    for (const auto& [model, c] : cost[name]) large = large || c >= 0.01 * total[model];
    if (!large) {
      for (const auto& [model, c] : cost[name]) small[model] += c;
      ++small_count;
      continue;
    }
    out << "| `" << name << "` |";
    for (const std::string& model : staged) {
      const auto it = cost[name].find(model);
      if (it == cost[name].end()) {
        out << " — | |";
      } else {
        out << " " << count_text(it->second) << " | "
            << fmt("%.1f%%", 100 * it->second / total[model]) << " |";
      }
    }
    out << "\n";
  }
  if (small_count > 0) {
    out << "| " << small_count << " other functions |";
    for (const std::string& model : staged) {
      out << " " << count_text(small[model]) << " | "
          << fmt("%.1f%%", 100 * small[model] / total[model]) << " |";
    }
    out << "\n";
  }
  out << "| **the whole call** |";
  for (const std::string& model : staged) out << " **" << count_text(total[model]) << "** | |";
  out << "\n\n";
}

// where forward's (and step's) instructions go, lever's by function and MuJoCo's by stage
void write_forward_instructions(std::ostream& out, const Inputs& in) {
  const Instructions& counts = in.counts;
  const std::vector<std::string>& model_order = in.model_order;
  // the models counted with stages: in the times' order, then any the times do not have
  std::vector<std::string> staged;
  for (const std::string& model : model_order) {
    if (!counts.stages(model, "lever").empty()) staged.push_back(model);
  }
  if (const Json* all = counts.root != nullptr ? counts.root->find("stages") : nullptr) {
    for (const std::string& model : all->keys) {
      if (std::find(staged.begin(), staged.end(), model) == staged.end() &&
          !counts.stages(model, "lever").empty())
        staged.push_back(model);
    }
  }
  if (staged.empty()) return;
  out << "## Where `forward`'s instructions go (callgrind, instructions per call)\n\n"
         "lever's `forward` by function, each function's own instructions (what it calls "
         "counted apart; a function the compiler inlined is counted in its caller); the share "
         "of the whole call beside it. Functions under 1% of every model's call are summed "
         "in the last row.\n\n";
  write_stage_table(out, counts, staged, "lever", "lever function", true);
  out << "lever's `step` the same way (the state restored before each call, as in the "
         "benchmark): what it adds to `forward` is its integrator's work (arm2's is Euler, "
         "panda7's `implicit`).\n\n";
  write_stage_table(out, counts, staged, "lever_step", "lever function (`step`)", true);
  out << "MuJoCo's `mj_forward` by the stages of its pipeline, each with what it calls "
         "(libmujoco's own static functions have no names to list them by); `rest` is "
         "`mj_forward`'s own work and the checks. `mj_collision` runs its broad phase over the "
         "geoms even where nothing can collide.\n\n";
  write_stage_table(out, counts, staged, "mujoco", "MuJoCo stage", false);
}

// the checks lever_bench --check wrote, as they are
void write_checks(std::ostream& out, const std::string& check_path) {
  if (check_path.empty()) return;
  std::ifstream check(check_path);
  std::stringstream check_text;
  check_text << check.rdbuf();
  out << "## Checks run with these numbers (`lever_bench --check`)\n\n";
  out << "The KDL bridge (lever's model as a KDL chain), the claim that lever and MuJoCo do the "
         "same "
         "work on the timed states, the batch API, and lever against Pinocchio where it ran:\n\n";
  out << check_text.str() << "\n";
}

}  // namespace

int main(int argc, char** argv) {
  const std::optional<Arguments> arguments = parse_arguments(argc, argv);
  if (!arguments) return 2;
  Inputs in;
  if (!read_inputs(*arguments, in)) return 2;
  const std::vector<Target> targets = collect_targets(in);

  std::ostream& out = std::cout;
  write_header(out, in);
  write_targets(out, targets);
  write_why_missed(out, in, targets);
  write_times_table(out, in);
  write_batch_forward(out, in);
  write_lesson_batches(out, in);
  write_operations(out);
  write_pinocchio(out, in);
  write_browser_peer(out, in);
  write_forward_instructions(out, in);
  write_checks(out, in.check_path);
  return 0;
}
