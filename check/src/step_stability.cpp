// (8) Stability of the step. At each keyframe (qpos0 when the model has none), with ctrl held at
// the keyframe's (zero at qpos0):
//   - the step's linearisation A = d[qpos'; qvel'] / d[qpos; qvel] by central differences of
//     lever::step, for the model's integrator and for explicit Euler at the model's timestep, and
//     its spectral radius rho;
//   - the dynamics' own growth: the largest real part of the eigenvalues of the continuous
//     linearisation [[0, I], [dqacc/dqpos, dqacc/dqvel]] (central differences of forward()). A step
//     is stable when rho <= max(1, exp(h growth)) (1 + slack): it grows no mode faster than the
//     dynamics do (rho < 1 for a damped, held arm; an arm that falls grows anyway);
//   - the largest stable timestep for each integrator, and the smallest armature that keeps
//     explicit Euler stable at the model's timestep (the same on every joint, then per joint with
//     the others heavy, and per joint alone, the others as in the model). Each is a scan: the
//     criterion on a log-spaced grid, every change of stability between neighbours bisected.
//     Stability need not change only once (one boundary); every change is kept, and the value
//     reported holds on a whole stretch: the timestep below which every timestep is stable,
//     the armature above which every armature is;
//   - simulations that confirm it: the model as it is, explicit Euler with the model's armature,
//     and explicit Euler with `margin` times the smallest armature on every joint.
#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include <lever/spectra.hpp>

#include <lever/data.hpp>
#include <lever/forward.hpp>

#include <lever/check.hpp>
#include "format.hpp"
#include "util.hpp"

namespace lever::check {

namespace {

constexpr int kRunSteps = 1000;
constexpr int kSweep = 40;  // chart points of rho against the timestep

struct State {
  Eigen::VectorXd qpos, qvel, ctrl;
};

Eigen::VectorXd state_of(const Data& d) {
  Eigen::VectorXd x(d.qpos.size() + d.qvel.size());
  x << d.qpos, d.qvel;
  return x;
}

// The largest real part of the eigenvalues of the continuous linearisation at the state.
double growth_rate(const Model& model, const State& s, double eps) {
  const int nv = model.nv;
  Data data(model);
  Eigen::MatrixXd Ac = Eigen::MatrixXd::Zero(2 * nv, 2 * nv);
  Ac.topRightCorner(nv, nv).setIdentity();
  for (int i = 0; i < 2 * nv; ++i) {
    Eigen::VectorXd qacc[2];
    for (int side = 0; side < 2; ++side) {
      reset(model, data);
      data.qpos = s.qpos;
      data.qvel = s.qvel;
      data.ctrl = s.ctrl;
      (i < nv ? data.qpos[i] : data.qvel[i - nv]) += side == 0 ? eps : -eps;
      forward(model, data);
      qacc[side] = data.qacc;
    }
    Ac.block(nv, i, nv, 1) = (qacc[0] - qacc[1]) / (2 * eps);
  }
  if (nv == 0) return 0.0;
  return eigenvalues(Ac).real().maxCoeff();
}

// A copy of the model with another integrator, timestep or armature (constants recomputed).
Model variant(const Model& model, Integrator integrator, double timestep,
              const std::vector<double>& armature) {
  Model m = model;
  m.opt.integrator = integrator;
  m.opt.timestep = timestep;
  if (!armature.empty()) {
    m.dof_armature = armature;
    set_const(m);
  }
  return m;
}

struct Judge {
  double slack, eps;
  bool stable(double rho, double growth, double h) const {
    return rho <= std::max(1.0, std::exp(h * growth)) * (1.0 + slack);
  }
  double rho(const Model& m, const State& s) const {
    return spectral_radius(step_linearisation(m, s.qpos, s.qvel, s.ctrl, eps));
  }
  // with the model's growth computed here (armature changes it)
  bool stable(const Model& m, const State& s) const {
    return stable(rho(m, s), growth_rate(m, s, eps), m.opt.timestep);
  }
};

// Stability along one parameter x on a log-spaced grid from `from` to `to` (`points_per_decade`
// points a decade, 0 first when `with_zero`), each change between neighbours bisected (in log x,
// linearly next to 0) until its sides are within the scan's relative resolution. Stability is not
// assumed to change once: every change the grid shows is kept.
StabilityScan scan(const std::function<bool(double)>& ok, double from, double to,
                   int points_per_decade, bool with_zero) {
  StabilityScan result;
  result.from = from;
  result.to = to;
  // (1e-9 below ceil: a whole number of decades gives that many intervals, however log10 rounds)
  const int intervals =
      std::max(1, static_cast<int>(std::ceil(points_per_decade * std::log10(to / from) - 1e-9)));
  std::vector<double> grid;
  if (with_zero) grid.push_back(0.0);
  for (int k = 0; k <= intervals; ++k) {
    grid.push_back(from * std::pow(to / from, static_cast<double>(k) / intervals));
  }
  result.points = static_cast<int>(grid.size());
  bool previous = ok(grid.front());
  result.stable_first = previous;
  for (size_t k = 1; k < grid.size(); ++k) {
    const bool now = ok(grid[k]);
    if (now == previous) continue;
    // bisect [lo, hi]: ok(lo) == previous, ok(hi) == now
    double lo = grid[k - 1], hi = grid[k];
    const double smallest = 1e-6 * from;  // next to 0: a change this close to 0 is at 0
    while (lo > 0 ? hi > lo * (1 + result.resolution) : hi > smallest) {
      const double mid = lo > 0 ? std::sqrt(lo * hi) : 0.5 * hi;
      (ok(mid) == previous ? lo : hi) = mid;
    }
    result.changes.push_back(previous ? lo : hi);  // the stable side
    previous = now;
  }
  return result;
}

// The largest timestep below which every timestep scanned is stable: the end of the first
// stable stretch, if it starts at the scan's smallest timestep (0 if that one is unstable,
// kInf if no change is found up to the cap).
double largest_stable(const StabilityScan& s) {
  if (!s.stable_first) return 0.0;
  return s.changes.empty() ? kInf : s.changes.front();
}

// The smallest armature above which every armature scanned is stable: the start of the last
// stable stretch, if it reaches the cap (kInf if the cap is unstable; 0 if nothing changes and 0
// is stable).
double smallest_stable(const StabilityScan& s) {
  const bool stable_last = s.stable_first == (s.changes.size() % 2 == 0);
  if (!stable_last) return kInf;
  return s.changes.empty() ? 0.0 : s.changes.back();  // the last change, to stable
}

StabilityScan timestep_scan(const Model& model, Integrator integrator, const State& s,
                            double growth, const Judge& judge, const StepStability& cfg) {
  const auto ok = [&](double h) {
    const Model m = variant(model, integrator, h, {});
    return judge.stable(judge.rho(m, s), growth, h);
  };
  return scan(ok, cfg.dt_floor * model.opt.timestep, cfg.dt_cap, cfg.points_per_decade, false);
}

StabilityScan armature_scan(const std::function<bool(double)>& ok, const StepStability& cfg) {
  return scan(ok, cfg.armature_start, cfg.armature_cap, cfg.points_per_decade, true);
}

StabilityRun simulate(const Model& m, const State& s, const std::string& armature,
                      const StepStability& cfg) {
  StabilityRun run;
  run.integrator = integrator_name(m.opt.integrator);
  run.armature = armature;
  Data data(m);
  reset(m, data);
  data.qpos = s.qpos;
  data.qvel = s.qvel;
  data.ctrl = s.ctrl;
  const int tail = kRunSteps - kRunSteps / 10;
  for (run.steps = 0; run.steps < kRunSteps;) {
    step(m, data);
    ++run.steps;
    int warnings = 0;
    for (const WarningStat& w : data.warning) warnings += w.number;
    run.warnings = warnings;
    const double v = data.qvel.size() ? data.qvel.cwiseAbs().maxCoeff() : 0.0;
    run.max_qvel = std::isfinite(v) ? std::max(run.max_qvel, v) : kInf;
    if (run.steps > tail) run.final_qvel = std::max(run.final_qvel, v);
    for (int a = 0; a < m.nu; ++a) {
      const auto& r = m.actuator_forcerange[a];
      if (m.actuator_forcelimited[a] &&
          (data.actuator_force[a] <= r[0] || data.actuator_force[a] >= r[1])) {
        ++run.saturated;
        break;
      }
    }
    if (warnings > 0 || !(v <= cfg.qvel_bound)) {
      run.blowup_step = run.steps;
      run.final_qvel = run.max_qvel;
      break;
    }
  }
  run.settled = run.bounded() && run.final_qvel <= cfg.settle_qvel;
  return run;
}

StabilityAt check_state(const Model& model, const StepStability& cfg, const std::string& where,
                        const State& s) {
  const Judge judge{cfg.slack, cfg.fd_eps};
  StabilityAt at;
  at.where = where;
  at.qpos = s.qpos;
  at.qvel = s.qvel;
  at.ctrl = s.ctrl;
  const double h = model.opt.timestep;
  at.growth = growth_rate(model, s, cfg.fd_eps);
  const Model euler = variant(model, Integrator::kEuler, h, {});
  at.rho_model = judge.rho(model, s);
  at.rho_euler = judge.rho(euler, s);
  at.stable_model = judge.stable(at.rho_model, at.growth, h);
  at.stable_euler = judge.stable(at.rho_euler, at.growth, h);
  at.dt_scan_model = timestep_scan(model, model.opt.integrator, s, at.growth, judge, cfg);
  at.dt_scan_euler = model.opt.integrator == Integrator::kEuler
                         ? at.dt_scan_model
                         : timestep_scan(model, Integrator::kEuler, s, at.growth, judge, cfg);
  at.max_dt_model = largest_stable(at.dt_scan_model);
  at.max_dt_euler = largest_stable(at.dt_scan_euler);

  // armature for explicit Euler at h
  const std::vector<double> own = model.dof_armature.to_vector();
  const auto euler_with = [&](const std::vector<double>& armature) {
    return judge.stable(variant(model, Integrator::kEuler, h, armature), s);
  };
  at.armature_scan_all =
      armature_scan([&](double a) { return euler_with(std::vector<double>(model.nv, a)); }, cfg);
  at.armature_all = smallest_stable(at.armature_scan_all);
  // per joint: each joint's own need, the others given `ample` times armature_all (heavy, so the
  // joint's effective inertia 1 / (M^-1)_ii is its own). The joints couple (that effective inertia
  // falls when the neighbours are light), so these needs do not hold together; the set that does:
  // max(need_i, floor) with the smallest common floor. Nothing to share out when no armature is
  // needed, or none is enough.
  const bool needed = std::isfinite(at.armature_all) && at.armature_all > 0;
  for (int j = 0; j < model.njnt; ++j) {
    const int dof = model.jnt_dofadr[j];
    if (!needed) {
      at.armature_each.push_back(at.armature_all);
      at.armature_alone.push_back(at.armature_all);
      continue;
    }
    at.armature_scan_each.push_back(armature_scan(
        [&](double a) {
          std::vector<double> arm(model.nv, cfg.ample * at.armature_all);
          arm[dof] = a;
          return euler_with(arm);
        },
        cfg));
    at.armature_each.push_back(smallest_stable(at.armature_scan_each.back()));
    at.armature_scan_alone.push_back(armature_scan(
        [&](double a) {
          std::vector<double> arm = own;
          arm[dof] = a;
          return euler_with(arm);
        },
        cfg));
    at.armature_alone.push_back(smallest_stable(at.armature_scan_alone.back()));
  }
  const auto floored = [&](double floor) {
    std::vector<double> arm(model.nv, floor);
    for (int j = 0; j < model.njnt; ++j) {
      const int dof = model.jnt_dofadr[j];
      arm[dof] = std::max(at.armature_each[j], floor);
    }
    return arm;
  };
  at.armature_floor = at.armature_all;
  if (needed) {
    at.armature_scan_floor = armature_scan([&](double t) { return euler_with(floored(t)); }, cfg);
    at.armature_floor = smallest_stable(at.armature_scan_floor);
  }
  for (int k = 0; k <= kSweep; ++k) {
    const double dt = h * std::pow(10.0, -1.0 + 2.0 * k / kSweep);
    at.sweep_dt.push_back(dt);
    at.sweep_rho_model.push_back(judge.rho(variant(model, model.opt.integrator, dt, {}), s));
    at.sweep_rho_euler.push_back(judge.rho(variant(model, Integrator::kEuler, dt, {}), s));
  }

  at.runs.push_back(simulate(model, s, "the model's", cfg));
  if (model.opt.integrator != Integrator::kEuler) {
    at.runs.push_back(simulate(euler, s, "the model's", cfg));
  }
  if (std::isfinite(at.armature_all) && at.armature_all > 0) {
    const double a = cfg.margin * at.armature_all;
    const Model all = variant(model, Integrator::kEuler, h, std::vector<double>(model.nv, a));
    at.rho_euler_with = judge.rho(all, s);
    at.runs.push_back(simulate(all, s, fmt::rounded(a, 4) + " on every joint", cfg));
    if (std::isfinite(at.armature_floor)) {  // (when the floor is armature_all, the same run)
      std::vector<double> each = floored(at.armature_floor);
      for (double& x : each) x *= cfg.margin;
      const Model per = variant(model, Integrator::kEuler, h, each);
      at.rho_euler_each = judge.rho(per, s);
      at.stable_euler_each = judge.stable(per, s);
      if (at.armature_floor < at.armature_all)
        at.runs.push_back(simulate(
            per, s,
            "per joint " + fmt::list(Eigen::Map<const Eigen::VectorXd>(each.data(), model.nv), 4),
            cfg));
    }
  }
  return at;
}

}  // namespace

Eigen::MatrixXd step_linearisation(const Model& model, const Eigen::VectorXd& qpos,
                                   const Eigen::VectorXd& qvel, const Eigen::VectorXd& ctrl,
                                   double eps) {
  const int nq = model.nq, nv = model.nv;
  Data data(model);
  Eigen::MatrixXd A(nq + nv, nq + nv);
  for (int i = 0; i < nq + nv; ++i) {
    Eigen::VectorXd x[2];
    for (int side = 0; side < 2; ++side) {
      reset(model, data);
      data.qpos = qpos;
      data.qvel = qvel;
      data.ctrl = ctrl;
      (i < nq ? data.qpos[i] : data.qvel[i - nq]) += side == 0 ? eps : -eps;
      step(model, data);
      x[side] = state_of(data);
    }
    A.col(i) = (x[0] - x[1]) / (2 * eps);
  }
  return A;
}

double spectral_radius(const Eigen::MatrixXd& A) {
  if (A.size() == 0) return 0.0;
  return eigenvalues(A).cwiseAbs().maxCoeff();
}

StepStability check_step_stability(const Model& model, const std::string& key) {
  StepStability result;
  result.timestep = model.opt.timestep;
  result.integrator = integrator_name(model.opt.integrator);
  for (int j = 0; j < model.njnt; ++j) result.joints.push_back(joint_label(model, j));
  if (model.nv == 0) return result;
  Data data(model);
  if (!key.empty()) {
    reset_keyframe(model, data,
                   key);  // throws, listing the keyframes, if there is none of that name
    result.states.push_back(
        check_state(model, result, "keyframe " + key, {data.qpos, data.qvel, data.ctrl}));
    return result;
  }
  if (model.nkey == 0) {
    reset(model, data);
    result.states.push_back(check_state(model, result, "qpos0",
                                        {data.qpos, data.qvel, Eigen::VectorXd::Zero(model.nu)}));
  }
  for (int k = 0; k < model.nkey; ++k) {
    reset_keyframe(model, data, k);
    result.states.push_back(check_state(model, result,
                                        "keyframe " + label(model.key_name[k], "key", k),
                                        {data.qpos, data.qvel, data.ctrl}));
  }
  return result;
}

}  // namespace lever::check
