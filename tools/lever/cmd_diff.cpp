// lever diff: compare lever with MuJoCo 2.2.2 on random states (and trajectories) of a model.
//
//   lever diff MODEL... [--states N] [--seed S] [--path loader|engine|both] [--trajectory]
//                       [--key NAME] [--json | --markdown]
//
// For each model and each path (lever's own loader, or MuJoCo's compiled parameters copied into
// lever), it prints the largest difference per quantity with its ratio to the bound
// |lever - mujoco| <= 1e-12 max(1, |mujoco|), and PASS or FAIL. Exit 0: all within the bound;
// 1: something is not; 2: a model could not be loaded (or bad arguments, or no MuJoCo).
// --markdown writes the agreement document (docs/agreement.md); it implies --trajectory.
#include <cstdio>

#include "cli.hpp"
#include "commands.hpp"

#ifndef LEVER_WITH_MUJOCO

namespace lever::cli {

void declare_diff(CLI::App& command) {
  command.allow_extras();  // whatever is asked, the answer is the one below
}

int cmd_diff(const Args&) {
  std::fprintf(stderr,
               "lever diff: this lever was built without MuJoCo 2.2.2, so there is nothing to "
               "compare with (install libmujoco-dev 2.2.2 and reconfigure)\n");
  return kBadInput;
}

}  // namespace lever::cli

#else

#include <sys/utsname.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <lever/diff/runs.hpp>
#include <lever/mjcf.hpp>
#include <string>
#include <vector>

namespace lever::cli {

namespace {

using diff::Extreme;
using diff::Path;
using diff::Report;

constexpr double kTrajectorySeconds = 10.0;
constexpr double kNudge = 1e-15;

struct Options {
  std::vector<std::string> files;
  int states = 1000;
  bool seed_given = false;
  std::uint64_t seed = 0;
  std::vector<Path> paths{Path::kLoader, Path::kEngine};
  bool trajectory = false, json = false, markdown = false;
  std::string key;  // the keyframe the trajectories start from ("": the first, else rest)
};

struct PathResult {
  Path path = Path::kEngine;
  std::string error;  // non-empty: the model could not be loaded on this path
  std::uint64_t seed = 0;
  int states = 0;
  Report random;
  Report self_noise;  // MuJoCo against a moved copy of itself, on the same states
  bool has_trajectories = false;
  Report lockstep_euler, lockstep_rk4, lockstep_implicit;
  diff::RunStats stats_euler, stats_rk4, stats_implicit;
  diff::FreeRun free;
  std::string start;  // the state the runs start from (a keyframe, or rest)

  bool loaded() const { return error.empty(); }
  bool pass() const {
    return loaded() && random.pass() && lockstep_euler.pass() && lockstep_rk4.pass() &&
           lockstep_implicit.pass();
  }
};

struct ModelResult {
  std::string file;
  std::vector<PathResult> paths;
};

// ---- options --------------------------------------------------------------------------------

// "" when text is a seed (a whole number >= 0), else why not.
std::string seed_error(const std::string& text) {
  errno = 0;
  char* end = nullptr;
  std::strtoull(text.c_str(), &end, 10);
  if (text.empty() || text[0] == '-' || end != text.c_str() + text.size() || errno == ERANGE) {
    return "'" + text + "' is not a whole number >= 0";
  }
  return "";
}

std::uint64_t parse_seed(const std::string& text) {
  const std::string error = seed_error(text);
  if (!error.empty()) throw UsageError{"--seed: " + error};
  return std::strtoull(text.c_str(), nullptr, 10);
}

std::vector<Path> parse_paths(const std::string& text) {
  if (text == "loader") return {Path::kLoader};
  if (text == "engine") return {Path::kEngine};
  if (text == "both") return {Path::kLoader, Path::kEngine};
  throw UsageError{"--path: '" + text + "' is not one of loader, engine, both"};
}

Options parse_options(const Args& args) {
  Options o;
  o.files = args.positional();
  const long states = args.get_long("states", o.states);
  if (states < 1 || states > 100000000) throw UsageError{"--states must be between 1 and 1e8"};
  o.states = static_cast<int>(states);
  o.seed_given = args.has("seed");
  if (o.seed_given) o.seed = parse_seed(args.get("seed"));
  if (args.has("path")) o.paths = parse_paths(args.get("path"));
  o.json = args.has("json");
  o.markdown = args.has("markdown");
  o.trajectory = args.has("trajectory") || o.markdown;
  if (args.has("key")) {
    o.key = args.get("key");
    if (!o.trajectory) {
      throw UsageError{"--key NAME sets where the trajectories start: add --trajectory"};
    }
  }
  return o;
}

// ---- running --------------------------------------------------------------------------------

void print_mujoco_warning(const char* message) {
  std::fprintf(stderr, "lever diff: MuJoCo warns: %s\n", message);
}

// MuJoCo's own errors (its data stack overflowing at a state with very many contacts, say) end
// the process: its default handler waits for Enter first. Say which and stop, as for bad input.
[[noreturn]] void stop_on_mujoco_error(const char* message) {
  std::fprintf(stderr, "lever diff: MuJoCo 2.2.2 stopped with an error: %s\n", message);
  std::fflush(stdout);
  std::_Exit(2);
}

PathResult run_path(const std::string& file, Path path, const Options& o) {
  PathResult result;
  result.path = path;
  result.seed = o.seed_given ? o.seed : diff::default_seed(file);
  result.states = o.states;
  try {
    diff::Twin twin(file, path);
    if (!o.key.empty()) {
      try {
        twin.start_from_key(o.key);
      } catch (const StateError& e) {
        result.error = "--key: " + std::string(e.what());
        return result;
      }
    }
    result.random = diff::random_states(twin, o.states, result.seed);
    result.self_noise = diff::mujoco_self_noise(twin, o.states, result.seed);
    if (o.trajectory) {
      result.has_trajectories = true;
      result.lockstep_euler = diff::lockstep(twin, Integrator::kEuler, kTrajectorySeconds,
                                             diff::Control::kSmooth, &result.stats_euler);
      result.lockstep_rk4 = diff::lockstep(twin, Integrator::kRK4, kTrajectorySeconds,
                                           diff::Control::kSmooth, &result.stats_rk4);
      result.lockstep_implicit = diff::lockstep(twin, Integrator::kImplicit, kTrajectorySeconds,
                                                diff::Control::kSmooth, &result.stats_implicit);
      result.start = twin.start_name();
      result.free = diff::free_run(twin, kTrajectorySeconds, diff::Control::kSmooth, kNudge);
    }
  } catch (const std::exception& e) {
    result.error = e.what();
  }
  return result;
}

// Every model that lever's loader reads must have keyframe `key`; checked before anything runs,
// so that a misspelt name costs no comparisons and prints no half report. (A model lever cannot
// load is reported by its run, as without --key.)
bool keys_exist(const Options& o) {
  if (o.key.empty()) return true;
  for (const std::string& file : o.files) {
    try {
      const Model model = mjcf::load_file(file);
      if (model.key(o.key) >= 0) continue;
      Data data(model);
      reset_keyframe(model, data, o.key);  // throws the engine's message, listing the keyframes
    } catch (const StateError& e) {
      std::fprintf(stderr, "lever diff: --key: %s: %s\n", file.c_str(), e.what());
      return false;
    } catch (const Error&) {
      continue;  // lever cannot load it: its run says why
    }
  }
  return true;
}

int exit_status(const std::vector<ModelResult>& results) {
  int status = kOk;
  for (const ModelResult& m : results) {
    for (const PathResult& p : m.paths) {
      if (!p.loaded()) return kBadInput;
      if (!p.pass()) status = kFindings;
    }
  }
  return status;
}

// ---- text -----------------------------------------------------------------------------------

// "state 17: lever ... vs mujoco ..., body 'link2' #2, z" (`unit` names what the number counts)
std::string where(const Extreme& e, const char* unit = "state") {
  if (e.state < 0 || e.max_abs_diff == 0.0) return "";
  char buf[160];
  std::snprintf(buf, sizeof buf, "%s %d: lever %.17g vs mujoco %.17g", unit, e.state, e.lever,
                e.mujoco);
  return std::string(buf) + (e.element.empty() ? "" : ", " + e.element);
}

// "0.12" or "-" where a quantity is not measured.
std::string ratio_or_dash(const Extreme* e, double Extreme::*ratio) {
  if (!e || e->compared == 0) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", e->*ratio);
  return buf;
}

void print_table(const Report& report, const char* state_word, const Report* floor = nullptr) {
  std::printf("    %-34s %9s %14s %8s %12s %12s  %s\n", "quantity", "compared", "largest |diff|",
              "ratio", "element-wise", floor ? "MuJoCo floor" : "", "largest ratio at");
  for (const Extreme& e : report.quantities()) {
    const std::string at = where(e, state_word);
    const std::string noise =
        floor ? ratio_or_dash(floor->find(e.quantity), &Extreme::max_elementwise_ratio) : "";
    std::printf("    %-34s %9ld %14.2e %8.3g %12.3g %12s  %s%s\n", e.quantity.c_str(), e.compared,
                e.max_abs_diff, e.max_ratio, e.max_elementwise_ratio, noise.c_str(),
                e.pass() ? "" : "FAIL  ", at.c_str());
  }
  for (const std::string& f : report.failures())
    std::printf("    beyond the bound: %s\n", f.c_str());
}

void print_free_run(const diff::FreeRun& run) {
  std::printf("    %-16s %18s %22s\n", "quantity", "lever vs MuJoCo", "MuJoCo vs nudged MuJoCo");
  for (const std::string& q : diff::free_run_quantities()) {
    const Extreme* ours = run.lever_vs_mujoco.find(q);
    const Extreme* noise = run.nudged_vs_mujoco.find(q);
    if (!ours || !noise) continue;
    std::printf("    %-16s %18.2e %22.2e\n", q.c_str(), ours->max_abs_diff, noise->max_abs_diff);
  }
}

void print_text(const ModelResult& m) {
  std::printf("lever diff %s (MuJoCo %d.%d.%d)\n", m.file.c_str(), mj_version() / 100,
              mj_version() / 10 % 10, mj_version() % 10);
  std::printf(
      "bound: |lever - mujoco| <= 1e-12 * max(1, |mujoco|), |mujoco| the quantity's largest "
      "element\n"
      "ratio = |diff| / bound; element-wise = the same with each element's own |mujoco| "
      "(reported);\n"
      "MuJoCo floor = MuJoCo against a moved copy of itself, element-wise (no engine can do "
      "better);\n"
      "for the inverse at the forward qacc, against itself with that qacc moved one ulp\n");
  for (const PathResult& p : m.paths) {
    std::printf("\npath %s: %s\n", diff::path_name(p.path), diff::path_description(p.path));
    if (!p.loaded()) {
      std::printf("  could not load: %s\n", p.error.c_str());
      continue;
    }
    std::printf("  %d random states, seed %llu\n", p.states,
                static_cast<unsigned long long>(p.seed));
    if (p.random.skipped() > 0) {
      std::printf("  %d of %d random states skipped, lever refusing them (%s)\n",
                  p.random.skipped(), p.states, p.random.first_skipped().c_str());
    }
    print_table(p.random, "state", &p.self_noise);
    if (p.has_trajectories) {
      std::printf(
          "  lockstep, Euler, %.0f s from %s, smooth control (%d of %d steps with limit rows)\n",
          kTrajectorySeconds, p.start.c_str(), p.stats_euler.constrained_steps,
          p.stats_euler.steps);
      print_table(p.lockstep_euler, "step");
      std::printf("  lockstep, RK4, %.0f s (%d of %d steps with limit rows)\n", kTrajectorySeconds,
                  p.stats_rk4.constrained_steps, p.stats_rk4.steps);
      print_table(p.lockstep_rk4, "step");
      std::printf("  lockstep, implicit, %.0f s (%d of %d steps with limit rows)\n",
                  kTrajectorySeconds, p.stats_implicit.constrained_steps, p.stats_implicit.steps);
      print_table(p.lockstep_implicit, "step");
      std::printf("  free run, %.0f s, each engine on its own (a report, not held to the bound):\n",
                  kTrajectorySeconds);
      print_free_run(p.free);
    }
    // with contacts, what MuJoCo's iterative solver decides is held to 1e-10
    const bool contacts = p.random.find("qacc") != nullptr && p.random.find("qacc")->bound > 1.0;
    const char* bound = contacts ? "1e-12 (1e-10 for what the constraint solver decides)" : "1e-12";
    std::printf("  %s: %s %s of MuJoCo 2.2.2%s\n", p.pass() ? "PASS" : "FAIL",
                p.pass() ? "every quantity within" : "some quantities beyond", bound,
                p.pass() ? "" : " (see FAIL above)");
  }
}

// ---- JSON -----------------------------------------------------------------------------------

void json_report(Json& j, const Report& report) {
  j.begin_array();
  for (const Extreme& e : report.quantities()) {
    j.begin_object();
    j.key("quantity").value(e.quantity);
    j.key("compared").value(e.compared);
    j.key("beyond").value(e.beyond);
    j.key("max_abs_diff").value(e.max_abs_diff);
    j.key("max_ratio").value(e.max_ratio);
    j.key("max_elementwise_ratio").value(e.max_elementwise_ratio);
    j.key("pass").value(e.pass());
    j.key("state").value(e.state);
    j.key("index").value(e.index);
    j.key("element").value(e.element);
    j.key("lever").value(e.lever);
    j.key("mujoco").value(e.mujoco);
    j.end_object();
  }
  j.end_array();
}

void json_free_run(Json& j, const diff::FreeRun& run) {
  j.begin_array();
  for (const std::string& q : diff::free_run_quantities()) {
    const Extreme* ours = run.lever_vs_mujoco.find(q);
    const Extreme* noise = run.nudged_vs_mujoco.find(q);
    if (!ours || !noise) continue;
    j.begin_object();
    j.key("quantity").value(q);
    j.key("lever_vs_mujoco").value(ours->max_abs_diff);
    j.key("nudged_vs_mujoco").value(noise->max_abs_diff);
    j.end_object();
  }
  j.end_array();
}

void print_json(const std::vector<ModelResult>& results) {
  Json j(stdout);
  j.begin_object();
  j.key("bound").value(1e-12);
  j.key("mujoco_version").value(mj_version());
  j.key("models").begin_array();
  for (const ModelResult& m : results) {
    j.begin_object();
    j.key("model").value(m.file);
    j.key("paths").begin_array();
    for (const PathResult& p : m.paths) {
      j.begin_object();
      j.key("path").value(diff::path_name(p.path));
      j.key("loaded").value(p.loaded());
      if (!p.loaded()) j.key("error").value(p.error);
      j.key("pass").value(p.pass());
      j.key("states").value(p.states);
      j.key("skipped_states").value(p.random.skipped());
      if (p.random.skipped() > 0) j.key("first_skipped").value(p.random.first_skipped());
      j.key("seed").value(std::to_string(p.seed));  // a string: JSON numbers lose 64-bit seeds
      j.key("random_states");
      json_report(j, p.random);
      j.key("mujoco_self_noise");
      json_report(j, p.self_noise);
      if (p.has_trajectories) {
        j.key("lockstep_euler");
        json_report(j, p.lockstep_euler);
        j.key("lockstep_rk4");
        json_report(j, p.lockstep_rk4);
        j.key("lockstep_implicit");
        json_report(j, p.lockstep_implicit);
        j.key("start").value(p.start);
        j.key("free_run");
        json_free_run(j, p.free);
      }
      j.end_object();
    }
    j.end_array();
    j.end_object();
  }
  j.end_array();
  j.end_object();
  j.newline();
}

// ---- Markdown (docs/agreement.md) -----------------------------------------------------------

std::string cpu_name() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  }
  return "unknown CPU";
}

std::string machine() {
  utsname u{};
  if (uname(&u) != 0) return cpu_name();
  return std::string(u.sysname) + " " + u.release + " " + u.machine + ", " + cpu_name();
}

std::string today() {
  const std::time_t now = std::time(nullptr);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%d", std::gmtime(&now));
  return buf;
}

std::string base_name(const std::string& file) { return file.substr(file.find_last_of('/') + 1); }

std::string ratio_text(double ratio, bool fail) {
  char buf[48];
  std::snprintf(buf, sizeof buf, ratio == 0.0 ? "0" : "%.2g", ratio);
  return fail ? std::string("**") + buf + "**" : std::string(buf);
}

std::string cell(const Extreme* e) {
  if (!e || e->compared == 0) return "–";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1e (", e->max_abs_diff);
  return buf + ratio_text(e->max_ratio, !e->pass()) + ")";
}

// Every quantity of some reports, in first-seen order.
std::vector<std::string> quantity_names(const std::vector<const Report*>& reports) {
  std::vector<std::string> names;
  for (const Report* r : reports) {
    for (const Extreme& e : r->quantities()) {
      if (std::find(names.begin(), names.end(), e.quantity) == names.end()) {
        names.push_back(e.quantity);
      }
    }
  }
  return names;
}

// The reports `which` of every loaded path of a model.
std::vector<const Report*> reports_of(const ModelResult& m, Report PathResult::*which) {
  std::vector<const Report*> reports;
  for (const PathResult& p : m.paths) {
    if (p.loaded()) reports.push_back(&(p.*which));
  }
  return reports;
}

// Worst ratio of a quantity over some reports (-1: never compared).
double worst_ratio(const std::vector<const Report*>& reports, const std::string& quantity,
                   double Extreme::*ratio) {
  double worst = -1.0;
  for (const Report* r : reports) {
    const Extreme* e = r->find(quantity);
    if (e && e->compared > 0) worst = std::max(worst, e->*ratio);
  }
  return worst;
}

// Quantity x model: the worst ratio over both paths (`ratio`: the verdict, or the element-wise
// figure, which is reported, not held to the bound). `only` limits the rows.
void markdown_matrix(const std::vector<ModelResult>& results, Report PathResult::*which,
                     double Extreme::*ratio = &Extreme::max_ratio,
                     const std::vector<std::string>& only = {}) {
  std::vector<const Report*> all;
  std::printf("| quantity |");
  for (const ModelResult& m : results) {
    std::printf(" %s |", base_name(m.file).c_str());
    for (const Report* r : reports_of(m, which)) all.push_back(r);
  }
  std::printf("\n|---|");
  for (std::size_t i = 0; i < results.size(); ++i) std::printf("---|");
  std::printf("\n");
  const bool verdict = ratio == &Extreme::max_ratio;
  for (const std::string& q : quantity_names(all)) {
    if (!only.empty() && std::find(only.begin(), only.end(), q) == only.end()) continue;
    std::printf("| %s |", q.c_str());
    for (const ModelResult& m : results) {
      const double worst = worst_ratio(reports_of(m, which), q, ratio);
      std::printf(" %s |", worst < 0 ? "–" : ratio_text(worst, verdict && worst > 1.0).c_str());
    }
    std::printf("\n");
  }
}

// One model's reports `which`: a column per path, then where each miss was.
void markdown_model_table(const ModelResult& m, Report PathResult::*which) {
  std::printf("| quantity |");
  for (const PathResult& p : m.paths)
    std::printf(" %s: largest \\|diff\\| (ratio) |", diff::path_name(p.path));
  std::printf("\n|---|");
  for (std::size_t i = 0; i < m.paths.size(); ++i) std::printf("---|");
  std::printf("\n");
  for (const std::string& q : quantity_names(reports_of(m, which))) {
    std::printf("| %s |", q.c_str());
    for (const PathResult& p : m.paths) {
      std::printf(" %s |", p.loaded() ? cell((p.*which).find(q)).c_str() : "not loaded");
    }
    std::printf("\n");
  }
  for (const PathResult& p : m.paths) {
    if (!p.loaded()) continue;
    for (const Extreme& e : (p.*which).quantities()) {
      if (e.pass()) continue;
      std::printf("\n- beyond the bound (%s path): %s, %ld of %ld values; worst at %s\n",
                  diff::path_name(p.path), e.quantity.c_str(), e.beyond, e.compared,
                  where(e, which == &PathResult::random ? "state" : "step").c_str());
    }
  }
}

void markdown_summary(const std::vector<ModelResult>& results) {
  std::printf(
      "| model | path | seed | worst ratio, random states | worst ratio, lockstep | verdict |\n");
  std::printf("|---|---|---|---|---|---|\n");
  for (const ModelResult& m : results) {
    for (const PathResult& p : m.paths) {
      if (!p.loaded()) {
        std::printf("| %s | %s | – | – | – | not loaded: %s |\n", base_name(m.file).c_str(),
                    diff::path_name(p.path), p.error.c_str());
        continue;
      }
      double worst_random = 0, worst_lockstep = 0;
      std::string random_at, lockstep_at;
      for (const Extreme& e : p.random.quantities()) {
        if (e.max_ratio >= worst_random) worst_random = e.max_ratio, random_at = e.quantity;
      }
      for (const Report* r : {&p.lockstep_euler, &p.lockstep_rk4, &p.lockstep_implicit}) {
        for (const Extreme& e : r->quantities()) {
          if (e.max_ratio >= worst_lockstep) worst_lockstep = e.max_ratio, lockstep_at = e.quantity;
        }
      }
      std::printf("| %s | %s | %llu | %s (%s) | %s (%s) | %s |\n", base_name(m.file).c_str(),
                  diff::path_name(p.path), static_cast<unsigned long long>(p.seed),
                  ratio_text(worst_random, worst_random > 1).c_str(), random_at.c_str(),
                  ratio_text(worst_lockstep, worst_lockstep > 1).c_str(), lockstep_at.c_str(),
                  p.pass() ? "PASS" : "**FAIL**");
    }
  }
}

void markdown_free_runs(const std::vector<ModelResult>& results) {
  const std::vector<std::string>& quantities = diff::free_run_quantities();
  std::printf("| model | path |");
  for (const std::string& q : quantities) std::printf(" %s |", q.c_str());
  std::printf("\n|---|---|");
  for (std::size_t i = 0; i < quantities.size(); ++i) std::printf("---|");
  std::printf("\n");
  for (const ModelResult& m : results) {
    for (const PathResult& p : m.paths) {
      if (!p.loaded()) continue;
      std::printf("| %s | %s |", base_name(m.file).c_str(), diff::path_name(p.path));
      for (const std::string& q : quantities) {
        const Extreme* ours = p.free.lever_vs_mujoco.find(q);
        const Extreme* noise = p.free.nudged_vs_mujoco.find(q);
        if (!ours || !noise) {
          std::printf(" – |");
          continue;
        }
        std::printf(" %.1e / %.1e (of %.2g) |", ours->max_abs_diff, noise->max_abs_diff,
                    ours->max_abs_mujoco);
      }
      std::printf("\n");
    }
  }
}

void print_markdown(const std::vector<ModelResult>& results, const Options& o) {
  const std::string start =
      o.key.empty() ? "the model's first keyframe (else from rest)" : "keyframe '" + o.key + "'";
  std::printf("# Agreement with MuJoCo 2.2.2\n\n");
  std::printf("Generated by `make agreement` (`lever diff --markdown`) on %s.  \n",
              today().c_str());
  std::printf("Machine: %s.  \n", machine().c_str());
  std::printf(
      "Compiler: %s (lever built with `-ffp-contract=off`); MuJoCo %d (`mj_version()`).\n\n",
#ifdef __VERSION__
      "GCC-compatible " __VERSION__,
#else
      "unknown compiler",
#endif
      mj_version());
  std::printf(
      "Every value is compared against the bound |lever − MuJoCo| ≤ 1e-12 · max(1, |MuJoCo|), "
      "where |MuJoCo| is the magnitude of the quantity in that state (its largest element: the "
      "largest joint acceleration, the largest entry of M, ...); a *ratio* is a difference divided "
      "by its bound (≤ 1 passes, 0 means bit-identical, **bold** is beyond the bound). Both "
      "engines run in the same process on the same inputs; nothing here is a stored number.\n\n"
      "Models with contacts (box_drop, gripper): MuJoCo runs its Newton solver to convergence "
      "(tolerance 0, 1000 iterations), and what the solver decides (qacc, qfrc_constraint, "
      "efc_force, inverse dynamics at the forward qacc, the state after a step) passes up to a "
      "ratio of 100, i.e. within 1e-10: converged iterations stop ~1e-13 to 1e-12 from the unique "
      "answer lever's exact solve finds. Contacts, constraint rows and everything else are held "
      "to 1e-12.\n\n"
      "Why the magnitude of the quantity, not of each element: accelerations come out of a solve "
      "with M, whose rounding error is set by the largest acceleration and M's conditioning. A "
      "small element beside large ones then carries an absolute error that no implementation "
      "rounding differently from MuJoCo can avoid: MuJoCo itself, given the same model moved in "
      "space (identical physics, other rounding), differs from itself element-wise by more than "
      "1e-12 on some models (the *MuJoCo floor* table below, measured on the same states). The "
      "element-wise ratios of lever are reported beside it, so nothing is hidden.\n\n"
      "Two paths per model: **loader** compiles the file with lever's own `lever::mjcf::load_file` "
      "(what users get: compiler and engine together); **engine** copies MuJoCo's compiled "
      "parameters into a lever Model (`from_mujoco`: the engine alone).\n\n"
      "Random states: %d per model, seeded from the file name; qpos inside the ranges, past a "
      "stop by up to 10 mrad (5 mm on slides), inside margins and exactly on stops; qvel, ctrl "
      "(up to 3x its range) and qfrc_applied random. Per state: forward, energy, site Jacobians, "
      "inverse dynamics at the forward qacc and at a random qacc, and one Euler, one RK4 and one "
      "implicit step. An RK4 step is compared stage by stage: MuJoCo's three later stages are "
      "evaluated at the states lever's step went through (mj_RungeKutta's arithmetic, which "
      "along MuJoCo's own stages ends where mj_step does, bit for bit), each stage's qvel "
      "compared, then the step's sum. "
      "Lockstep, under Euler, RK4 and implicit (MuJoCo's `opt.integrator` set to each): %.0f s "
      "from %s under a sinusoidal control sweeping each motor's whole range; at every step lever "
      "starts from MuJoCo's own state, the forward pass at that state is compared (qacc, "
      "qfrc_constraint), then both take one step and the state after it is compared (qpos, "
      "qvel).\n\n",
      o.states, kTrajectorySeconds, start.c_str());
  std::printf("## Summary\n\n");
  markdown_summary(results);
  std::printf("\n## Random states: worst ratio to the bound, quantity × model (both paths)\n\n");
  markdown_matrix(results, &PathResult::random);
  std::printf(
      "\n## Element-wise, beside MuJoCo's own floor\n\n"
      "The same random states, with each element measured against its own |MuJoCo| "
      "(reported, not the verdict). First lever against MuJoCo:\n\n");
  markdown_matrix(results, &PathResult::random, &Extreme::max_elementwise_ratio,
                  diff::self_noise_quantities());
  std::printf(
      "\nThen MuJoCo against itself, the same file with every world child moved by (0.37, 0.21, "
      "0.3) m: the same physics, other rounding. Where this floor is near or above 1, the "
      "element-wise figure measures rounding, not a term that differs:\n\n");
  markdown_matrix(results, &PathResult::self_noise, &Extreme::max_elementwise_ratio);
  std::printf("\n## Lockstep trajectories: worst ratio to the bound (both paths)\n\nEuler:\n\n");
  markdown_matrix(results, &PathResult::lockstep_euler);
  std::printf("\nRK4:\n\n");
  markdown_matrix(results, &PathResult::lockstep_rk4);
  std::printf("\nImplicit (MuJoCo 2.2.2's `implicit`):\n\n");
  markdown_matrix(results, &PathResult::lockstep_implicit);
  std::printf("\n## Free runs: lever's divergence beside the dynamics' own noise floor\n\n");
  std::printf(
      "%.0f s from the same start under the same control, lever and MuJoCo each on its own. Each "
      "cell: the largest |lever − MuJoCo| / the largest |MuJoCo − MuJoCo started from qpos0 + "
      "1e-15| (of the largest |value|). The stiff limit impacts amplify any last-bit difference, "
      "so this is a report, not a 1e-12 assertion; the tests hold lever within 100x of MuJoCo's "
      "own sensitivity plus the bound.\n\n",
      kTrajectorySeconds);
  markdown_free_runs(results);
  std::printf("\n## Per model: largest differences\n");
  for (const ModelResult& m : results) {
    std::printf("\n### %s\n", base_name(m.file).c_str());
    for (const PathResult& p : m.paths) {
      if (!p.loaded()) continue;
      std::printf(
          "\n%s path: runs start from %s; lockstep steps with limit rows: Euler %d of %d, RK4 %d "
          "of %d, implicit %d of %d.\n",
          diff::path_name(p.path), p.start.c_str(), p.stats_euler.constrained_steps,
          p.stats_euler.steps, p.stats_rk4.constrained_steps, p.stats_rk4.steps,
          p.stats_implicit.constrained_steps, p.stats_implicit.steps);
    }
    std::printf("\nRandom states:\n\n");
    markdown_model_table(m, &PathResult::random);
    std::printf("\nLockstep, Euler:\n\n");
    markdown_model_table(m, &PathResult::lockstep_euler);
    std::printf("\nLockstep, RK4:\n\n");
    markdown_model_table(m, &PathResult::lockstep_rk4);
    std::printf("\nLockstep, implicit:\n\n");
    markdown_model_table(m, &PathResult::lockstep_implicit);
  }
}

}  // namespace

void declare_diff(CLI::App& command) {
  command.add_option("MODEL", "the model files (MJCF)")
      ->type_name("FILE")
      ->required()
      ->expected(1, -1)  // one or more
      ->allow_extra_args();
  add_value(command, "states", "N", "random states per model (default 1000)")
      ->check(whole_number_check());
  add_value(command, "seed", "S", "seed of the random states (default: derived from the file name)")
      ->check(CLI::Validator([](std::string& text) { return seed_error(text); }, ""));
  add_value(command, "path", "P",
            "loader: lever's own MJCF loader; engine: MuJoCo's compiled model copied\n"
            "into lever; both (default)")
      ->check(CLI::IsMember({"loader", "engine", "both"}));
  add_switch(command, "trajectory",
             "also 10 s lockstep trajectories (Euler, RK4, implicit) and a 10 s free\n"
             "run, from the model's first keyframe (else from rest)");
  add_value(command, "key", "NAME",
            "the trajectories start from keyframe NAME instead (every MODEL must\n"
            "have it; needs --trajectory or --markdown)")
      ->check(not_empty_check());
  add_switch(command, "json", "machine-readable output");
  add_switch(command, "markdown", "the agreement document for all MODELs (implies --trajectory)")
      ->excludes("--json");
  command.footer(
      "Each quantity is held to |lever - mujoco| <= 1e-12 max(1, |mujoco|), |mujoco| its largest\n"
      "element in that state; its element-wise ratio is printed beside it, with MuJoCo's own "
      "floor\n"
      "(MuJoCo against a copy of the model moved in space: same physics, other rounding).\n"
      "Exit status: 0 every quantity within the bound; 1 some are not; 2 a model could not be\n"
      "loaded, or has no keyframe NAME (nothing is compared then), or MuJoCo stopped with an\n"
      "error (its data stack overflowing at a state with very many contacts: the run ends there).");
}

int cmd_diff(const Args& args) {
  // MuJoCo prints its warnings on standard output (and appends them to MUJOCO_LOG.TXT in the
  // working directory), where they would break --json and --markdown: they go to standard error
  mju_user_warning = print_mujoco_warning;
  mju_user_error = stop_on_mujoco_error;
  const Options o = parse_options(args);
  if (!keys_exist(o)) return kBadInput;
  std::vector<ModelResult> results;
  for (const std::string& file : o.files) {
    ModelResult m{file, {}};
    for (Path path : o.paths) m.paths.push_back(run_path(file, path, o));
    results.push_back(std::move(m));
  }
  if (o.json) {
    print_json(results);
  } else if (o.markdown) {
    print_markdown(results, o);
  } else {
    for (std::size_t i = 0; i < results.size(); ++i) {
      if (i > 0) std::printf("\n");
      print_text(results[i]);
    }
  }
  return exit_status(results);
}

}  // namespace lever::cli

#endif  // LEVER_WITH_MUJOCO
