// MuJoCo 2.2.2's primal problem (primal.cpp) solved by Newton's method with an exact line search
// (read in engine_solver.c's mj_solNewton; written here in lever's own words). Used for models
// with elliptic friction cones, equality constraints or friction loss, whatever opt.solver says
// when it is Newton; the iterations run until the cost stops decreasing (no tolerance).
#include <lever/constraint.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include "constraint/constraint_room.hpp"

namespace lever {

namespace {

// Most Newton steps: far above what convergence takes (a few steps), a guard against a loop that
// would never end.
constexpr int kMaxNewtonSteps = 200;

}  // namespace

int solve_constraint_newton([[maybe_unused]] const Model& model, Data& data) {
  auto& w = data.work;
  const int n = data.nefc;
  rows_jar(data, data.qacc_smooth.data(), data.efc_b.data());
  // start from the unconstrained acceleration (lever's forward is a function of the state alone;
  // a warm start would change only where the iterations stop, at rounding)
  data.qacc = data.qacc_smooth;
  primal_cost(data, data.qacc);
  w.newton_jar.head(n) = w.newton_x.head(n);

  // The iterations stop at the minimum, to rounding: a cost of 1e5 cannot show a decrease of
  // 1e-20, so the test is on the steps. Newton's steps shrink quadratically near the minimum;
  // they stop when a step moves qacc by a few units in the last place, when a step no longer
  // shrinks once it is tiny (rounding noise, not convergence), or when a step changed no row's
  // state and no cone is in its middle zone (the cost was one quadratic there: the Newton step
  // reached its minimum, to the rounding of the solve with H). One more step is then taken, as
  // iterative refinement: stiff rows (an equality constraint's D is large) make H ill-conditioned,
  // and the second solve removes most of the first one's rounding error, as MuJoCo's further
  // iterations do.
  constexpr double kEps = std::numeric_limits<double>::epsilon();
  double previous_step = std::numeric_limits<double>::infinity();
  int step = 0;
  bool refined = false;
  for (; step < kMaxNewtonSteps; ++step) {
    // gradient M (a - a_smooth) + J^T ds/djar and Hessian M + J^T (d^2 s / d jar^2) J: per
    // row, ds/djar (w.lcp_w) and a one-sided row's d^2 s / d jar^2 (w.lcp_f); per elliptic
    // cone, its block's d^2 s / d jar^2 (w.contact_weight), in its frame's coordinates (its
    // rows are its frame's rows)
    bool changed = step == 0, cone = false;
    for (int r = 0; r < n;) {
      const int size = block_size(data, r);
      double g[6], c;
      BlockHessian h;
      const ConstraintState state = block_cost(data, r, size, w.newton_jar.data() + r, c, g, &h);
      changed = changed || state != data.efc_state[r];
      cone = cone || state == ConstraintState::kCone;
      std::fill(data.efc_state.begin() + r, data.efc_state.begin() + r + size, state);
      const bool pushing = state != ConstraintState::kSatisfied;
      for (int i = 0; i < size; ++i) w.lcp_w[r + i] = pushing ? g[i] : 0.0;
      std::fill(w.lcp_f.data() + r, w.lcp_f.data() + r + size, 0.0);
      if (data.efc_type[r] != ConstraintType::kContactElliptic) {  // a row of its own
        w.lcp_f[r] = pushing ? h(0, 0) : 0.0;
      } else {
        double* W = w.contact_weight.data() + 36 * static_cast<std::ptrdiff_t>(data.efc_id[r]);
        for (int i = 0; i < size; ++i) {
          for (int j = 0; j < size; ++j) W[i * size + j] = pushing ? h(i, j) : 0.0;
        }
      }
      r += size;
    }
    if (!changed && !cone) {
      if (refined) break;
      refined = true;
    }
    w.newton_grad = w.newton_Merr;
    add_rows_transpose(data, w.lcp_w.data(), w.newton_grad.data());
    if (w.newton_grad.lpNorm<Eigen::Infinity>() == 0.0) break;
    w.newton_dir = -w.newton_grad;
    w.newton_H = data.M;
    add_rows_hessian(data, w.lcp_f.data(), w.newton_H);  // the one-sided rows
    for (int i = 0; i < data.ncon; ++i) {
      const int first = data.contact[i].efc_address;
      if (first < 0 || data.efc_type[first] != ConstraintType::kContactElliptic) continue;
      add_frame_hessian(data, i, w.contact_weight.data() + 36 * static_cast<std::ptrdiff_t>(i),
                        w.newton_H);
    }
    solve_with_hessian(data, w.newton_H, w.newton_dir);
    if (!(w.newton_dir.dot(w.newton_grad) < 0)) break;  // no descent left, at rounding

    // the exact minimum along the Newton direction
    w.newton_Mdir.noalias() = data.M * w.newton_dir;
    const double gauss1 = w.newton_dir.dot(w.newton_Merr);
    const double gauss2 = 0.5 * w.newton_dir.dot(w.newton_Mdir);
    rows_times(data, w.newton_dir.data(), w.newton_jv.data());
    const double alpha = exact_line_search(data, {0.0, gauss1, gauss2});
    if (!(alpha > 0.0)) break;
    data.qacc += alpha * w.newton_dir;
    primal_cost(data, data.qacc);
    w.newton_jar.head(n) = w.newton_x.head(n);

    const double moved = alpha * w.newton_dir.lpNorm<Eigen::Infinity>();
    const double scale = 1.0 + data.qacc.lpNorm<Eigen::Infinity>();
    if (moved <= 4 * kEps * scale) break;
    if (!changed && moved >= 0.5 * previous_step && moved <= 1e-8 * scale) break;
    previous_step = moved;
  }
  record_primal_forces(data, w.newton_jar);
  return step;
}

}  // namespace lever
