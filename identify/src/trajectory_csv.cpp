// Reading a trajectory from `lever simulate --csv`'s columns (see lever/identify.hpp); the file
// itself is read by lever::io's CSV reader (lever/io/csv.hpp).
#include <lever/dynamics.hpp>
#include <lever/error.hpp>
#include <lever/identify.hpp>
#include <lever/io/csv.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "names.hpp"

namespace lever::identify {

namespace {

using detail::label_of;

double clamp(double x, const std::array<double, 2>& range) {
  return std::min(std::max(x, range[0]), range[1]);
}

// The force actuator a of the prior applies for a command ctrl at its joint's position q and
// velocity qd, as actuation() computes it: ctrl clamped to ctrlrange, gain * ctrl + bias with the
// gain and bias affine in length = gear q and velocity = gear qd (a motor: gain 1, no bias),
// clamped to forcerange. The gear that carries it to the joint is applied by the caller.
double force_from_ctrl(const Model& prior, int a, double ctrl, double q, double qd) {
  if (prior.actuator_ctrllimited[a]) ctrl = clamp(ctrl, prior.actuator_ctrlrange[a]);
  const double gear = prior.actuator_gear[a][0];
  const double length = gear * q, velocity = gear * qd;
  double force = actuator_gain(prior, a, length, velocity) * ctrl;
  force += actuator_bias(prior, a, length, velocity);
  if (prior.actuator_forcelimited[a]) force = clamp(force, prior.actuator_forcerange[a]);
  return force;
}

}  // namespace

Trajectory read_csv(const Model& prior, const std::string& path) {
  require_simple_actuators(prior, "identify");  // a row's forces go to the motors' dofs
  const io::CsvTable table = io::CsvTable::read(path);
  const auto find = [&](const std::string& name, bool required) {
    const int c = table.column(name);
    if (c >= 0) return c;
    if (required) {
      throw Error(path + ":1: no column '" + name + "' (is the file from another model? " +
                  "the prior '" + prior.name + "' names its joints and motors as `lever " +
                  "simulate --csv` does)");
    }
    return -1;
  };
  const int nv = prior.nv, nu = prior.nu;
  const int time_col = find("time", true);
  std::vector<int> qpos_col(nv), qvel_col(nv), qacc_col(nv), constraint_col(nv);
  bool have_qacc = true, have_constraint = true;
  for (int j = 0; j < prior.njnt; ++j) {
    const std::string name = label_of(prior.jnt_name[j], j);
    const int d = prior.jnt_dofadr[j];
    qpos_col[d] = find("qpos[" + name + "]", true);
    qvel_col[d] = find("qvel[" + name + "]", true);
    qacc_col[d] = find("qacc[" + name + "]", false);
    constraint_col[d] = find("qfrc_constraint[" + name + "]", false);
    have_qacc = have_qacc && qacc_col[d] >= 0;
    have_constraint = have_constraint && constraint_col[d] >= 0;
  }
  std::vector<int> force_col(nu), ctrl_col(nu);
  bool have_force = true;
  for (int a = 0; a < nu; ++a) {
    const std::string name = label_of(prior.actuator_name[a], a);
    force_col[a] = find("actuator_force[" + name + "]", false);
    have_force = have_force && force_col[a] >= 0;
  }
  bool have_ctrl = true;  // kept when every actuator has one; required without forces
  for (int a = 0; a < nu; ++a) {
    ctrl_col[a] = find("ctrl[" + label_of(prior.actuator_name[a], a) + "]", !have_force);
    have_ctrl = have_ctrl && ctrl_col[a] >= 0;
  }

  // the rows, every field used a finite number
  std::vector<std::vector<double>> rows;
  for (int r = 0; r < table.rows(); ++r) {
    std::vector<double> row(table.header().size(), 0.0);
    const auto parse = [&](int c) {
      if (c >= 0) row[static_cast<std::size_t>(c)] = table.number(r, c);
    };
    parse(time_col);
    for (int d = 0; d < nv; ++d) {
      parse(qpos_col[d]);
      parse(qvel_col[d]);
      if (have_qacc) parse(qacc_col[d]);
      if (have_constraint) parse(constraint_col[d]);
    }
    for (int a = 0; a < nu; ++a) {
      if (have_force) parse(force_col[a]);
      if (have_ctrl) parse(ctrl_col[a]);
    }
    rows.push_back(std::move(row));
  }

  // samples: every row, or all but the last when qacc is differenced
  const int count = static_cast<int>(rows.size()) - (have_qacc ? 0 : 1);
  if (count < 1) throw Error(path + ": too few rows (" + std::to_string(rows.size()) + ").");
  Trajectory t;
  t.time.resize(count);
  t.qpos.resize(nv, count);
  t.qvel.resize(nv, count);
  t.qacc.resize(nv, count);
  t.force.setZero(nv, count);
  t.actuator_force.setZero(nu, count);
  t.ctrl.setZero(have_ctrl ? nu : 0, count);
  const auto at = [&](int r, int c) {
    return rows[static_cast<std::size_t>(r)][static_cast<std::size_t>(c)];
  };
  for (int r = 0; r < count; ++r) {
    const int k = r;
    t.time[k] = at(r, time_col);
    for (int d = 0; d < nv; ++d) {
      t.qpos(d, k) = at(r, qpos_col[d]);
      t.qvel(d, k) = at(r, qvel_col[d]);
      if (have_qacc) {
        t.qacc(d, k) = at(r, qacc_col[d]);
      } else {
        // the velocity change over the step that starts at this row: what a semi-implicit
        // Euler step applied (its implicit-damping acceleration), a row's forces act over it
        const double dt = at(r + 1, time_col) - at(r, time_col);
        if (!(dt > 0)) {
          throw Error(path + ":" + std::to_string(table.line(r + 1)) + ": time does not increase.");
        }
        t.qacc(d, k) = (at(r + 1, qvel_col[d]) - at(r, qvel_col[d])) / dt;
      }
      if (have_constraint) t.force(d, k) += at(r, constraint_col[d]);
    }
    for (int a = 0; a < nu; ++a) {
      const int d = actuator_scalar_dof(prior, a);  // >= 0: checked when the file was opened
      // the row's actuator force, or its ctrl through the prior's actuator at the row's state
      const double force =
          have_force ? at(r, force_col[a])
                     : force_from_ctrl(prior, a, at(r, ctrl_col[a]), t.qpos(d, k), t.qvel(d, k));
      t.force(d, k) += prior.actuator_gear[a][0] * force;
      t.actuator_force(a, k) = force;
      if (have_ctrl) t.ctrl(a, k) = at(r, ctrl_col[a]);
    }
  }
  t.qacc_differenced = !have_qacc;
  t.qacc_source = have_qacc ? "the qacc columns"
                            : "forward differences of qvel, (qvel[k+1] - qvel[k]) / (t[k+1] - "
                              "t[k]) (the last row dropped)";
  t.force_source = have_force ? "actuator_force times gear"
                              : "ctrl through the prior's actuators (ctrl clamped, gain * ctrl + "
                                "bias at the row's qpos and qvel, force clamped) times gear";
  if (!have_constraint) t.force_source += "; no qfrc_constraint columns: joint stops taken as zero";
  return t;
}

}  // namespace lever::identify
