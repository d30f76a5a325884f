// `lever check --svg`: the torque budget as grouped bars, one group per joint: the worst-case
// gravity torque, the motor limit on the side that holds the arm, and the spare torque left.
#include <algorithm>
#include <cmath>

#include <lever/plot.hpp>

#include <lever/check.hpp>
#include "format.hpp"

namespace lever::check {

namespace {

const char* kGravityColor = "#d62728";
const char* kLimitColor = "#1f77b4";
const char* kSpareColor = "#2ca02c";

plot::BarChart::Group joint_group(const JointBudget& j) {
  const bool sized = j.actuated() && std::isfinite(j.limit);
  std::string label = j.joint;
  if (!j.actuated())
    label += " (no motor)";
  else if (!sized)
    label += " (unbounded)";
  else if (j.loaded)
    label.append(" ").append(fmt::fixed(j.ratio, 2)).append("x");
  return {label,
          {{"worst gravity torque", std::abs(j.worst_torque), kGravityColor},
           {"motor limit", sized ? j.limit : 0.0, kLimitColor},
           {"spare torque", sized ? j.spare : 0.0, kSpareColor}}};
}

}  // namespace

std::string torque_budget_svg(const Report& r) {
  plot::BarChart chart;
  chart.title = r.model + ": torque budget at each joint's worst pose";
  const bool any_slide = std::any_of(r.budget.joints.begin(), r.budget.joints.end(),
                                     [](const JointBudget& j) { return !j.hinge; });
  chart.ylabel = any_slide ? "torque (N m) or force (N)" : "torque (N m)";
  for (const JointBudget& j : r.budget.joints) chart.groups.push_back(joint_group(j));
  const int groups = static_cast<int>(chart.groups.size());
  chart.width = std::max(640, 140 + (groups <= 8 ? 100 : 75) * groups);
  chart.height = 420;
  const std::string key = " (Nx: limit / gravity)";  // explains the labels, where it fits
  if (9.0 * double(chart.title.size() + key.size()) < chart.width) chart.title += key;
  return plot::to_svg(chart);
}

std::string singular_poses_svg(const Report& r) {
  plot::BarChart chart;
  chart.title = r.model + ": smallest singular value of the site Jacobian";
  chart.ylabel = "sigma_min";
  for (const SiteSingularity& s : r.singular.sites) {
    const std::string site = r.singular.sites.size() > 1 ? s.site + ": " : "";
    for (const auto* list : {&s.states, &s.worst}) {
      for (const JacobianAt& at : *list) {
        const double low = at.sigma.size() ? at.sigma[at.sigma.size() - 1] : 0.0;
        chart.groups.push_back({site + at.where, {{"sigma_min", low, kLimitColor}}});
      }
    }
  }
  chart.width = std::max(640, 140 + 100 * static_cast<int>(chart.groups.size()));
  chart.height = 420;
  return plot::to_svg(chart);
}

std::string step_stability_svg(const Report& r) {
  plot::Figure figure;
  figure.title = r.model + ": spectral radius of the step against the timestep";
  for (const StabilityAt& s : r.stability.states) {
    plot::Chart chart;
    chart.title = s.where;
    chart.xlabel = "log10 timestep (s)";
    chart.ylabel = "log10 rho";
    plot::Series model{r.stability.integrator, {}, {}, kLimitColor};
    plot::Series euler{"Euler", {}, {}, kGravityColor};
    for (size_t k = 0; k < s.sweep_dt.size(); ++k) {
      const double x = std::log10(s.sweep_dt[k]);
      model.x.push_back(x);
      model.y.push_back(std::log10(s.sweep_rho_model[k]));
      euler.x.push_back(x);
      euler.y.push_back(std::log10(s.sweep_rho_euler[k]));
    }
    if (r.stability.integrator != "Euler") chart.series.push_back(model);
    chart.series.push_back(euler);
    chart.lines.push_back({plot::RefLine::Axis::kHorizontal, 0.0, "rho = 1"});
    chart.lines.push_back(
        {plot::RefLine::Axis::kVertical, std::log10(r.stability.timestep), "the model's timestep"});
    figure.charts.push_back(chart);
  }
  return plot::to_svg(figure);
}

std::string grip_svg(const Report& r) {
  plot::BarChart chart;
  const Grip& g = r.contacts.grip;
  chart.title = r.model + ": the box's drop at each grip force";
  chart.ylabel = "drop (mm)";
  if (!r.contacts.skipped.empty() || !g.skipped.empty()) {
    chart.title = r.model + ": grip not checked (see the text)";
  }
  for (const GripTrial& t : g.trials) {
    chart.groups.push_back({fmt::fixed(t.force, 3) + " N" + (t.slipped ? " slip" : ""),
                            {{"drop", t.drop * 1e3, t.slipped ? kGravityColor : kSpareColor}}});
  }
  chart.width = std::max(640, 140 + 75 * static_cast<int>(chart.groups.size()));
  chart.height = 420;
  return plot::to_svg(chart);
}

}  // namespace lever::check
