// The base parameters (see lever/regressor.hpp): the regressor stacked over random states and
// factored by column-pivoted QR.
#include <lever/error.hpp>
#include <lever/kinematics.hpp>
#include <lever/regressor.hpp>

#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>

#include "identification/identification.hpp"

namespace lever {

Eigen::MatrixXd BaseParameters::base_regressor(const Eigen::Ref<const Eigen::MatrixXd>& Y) const {
  Eigen::MatrixXd out(Y.rows(), rank);
  for (int k = 0; k < rank; ++k) out.col(k) = Y.col(base[static_cast<std::size_t>(k)]);
  return out;
}

BaseParameters base_parameters(const Model& model, int samples, unsigned long long seed) {
  return base_parameters_with_gains(model, gain_actuators(model), samples, seed);
}

BaseParameters base_parameters_with_gains(const Model& model, const std::vector<int>& gains,
                                          int samples, unsigned long long seed) {
  for (const int a : gains) {
    if (a < 0 || a >= model.nu || !has_gain_column(model, a)) {
      throw StateError("base_parameters: actuator " + std::to_string(a) +
                       " has no gain column (only fixed-gain actuators have one).");
    }
  }
  const int n = regressor_columns(model);
  const int nv = model.nv;
  if (model.nq != model.nv) {
    throw ModelError(
        "base parameters: the model has ball or free joints; lever identifies "
        "robots of hinge and slide joints so far.");
  }
  std::mt19937_64 rng(seed);
  const auto uniform = [&](double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
  };

  // the regressor stacked over random states
  Data data(model);
  Eigen::MatrixXd W(static_cast<Eigen::Index>(samples) * nv, n);
  Eigen::VectorXd qacc(nv);
  for (int s = 0; s < samples; ++s) {
    for (int j = 0; j < model.njnt; ++j) {
      const int q = model.jnt_qposadr[j];
      data.qpos[q] = model.jnt_limited[j] ? uniform(model.jnt_range[j][0], model.jnt_range[j][1])
                                          : model.qpos0[q] + uniform(-3, 3);
    }
    for (int i = 0; i < nv; ++i) {
      data.qvel[i] = uniform(-2, 2);
      qacc[i] = uniform(-10, 10);
    }
    for (const int a : gains) {
      const auto& range = model.actuator_ctrlrange[a];
      data.ctrl[a] =
          model.actuator_ctrllimited[a] ? uniform(range[0], range[1]) : uniform(-1.0, 1.0);
    }
    kinematics(model, data);
    regressor(model, data, qacc, W.middleRows(static_cast<Eigen::Index>(s) * nv, nv));
  }

  // the gain columns of actuators whose gain is known are left out (zero: unidentifiable)
  const std::vector<int> fixed = gain_actuators(model);
  for (std::size_t g = 0; g < fixed.size(); ++g) {
    if (std::find(gains.begin(), gains.end(), fixed[g]) != gains.end()) continue;
    W.col(n - static_cast<int>(fixed.size()) + static_cast<int>(g)).setZero();
  }

  // W P = Q R: the first `rank` pivoted columns span the rest, W_D = W_B beta
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(W);
  const Eigen::MatrixXd R = qr.matrixR().triangularView<Eigen::Upper>();
  const double largest = n > 0 ? std::abs(R(0, 0)) : 0.0;
  int rank = 0;
  while (rank < std::min<Eigen::Index>(W.rows(), n) && std::abs(R(rank, rank)) > 1e-9 * largest) {
    ++rank;
  }
  const auto& perm = qr.colsPermutation().indices();
  const Eigen::MatrixXd beta = R.topLeftCorner(rank, rank)
                                   .triangularView<Eigen::Upper>()
                                   .solve(R.topRightCorner(rank, n - rank));

  BaseParameters out;
  out.rank = rank;
  out.K = Eigen::MatrixXd::Zero(rank, n);
  const std::vector<std::string> names = regressor_names(model);
  for (int k = 0; k < rank; ++k) {
    out.base.push_back(perm[k]);
    out.K(k, perm[k]) = 1.0;
  }
  for (int d = 0; d < n - rank; ++d) {
    const int column = perm[rank + d];
    bool used = false;
    for (int k = 0; k < rank; ++k) {
      const double coefficient = beta(k, d);
      if (std::abs(coefficient) < 1e-10) continue;  // a structural zero, up to rounding
      out.K(k, column) = coefficient;
      used = true;
    }
    if (!used) out.unidentifiable.push_back(column);
  }
  std::sort(out.unidentifiable.begin(), out.unidentifiable.end());
  for (int k = 0; k < rank; ++k) {
    std::ostringstream s;
    s.precision(6);
    s << names[static_cast<std::size_t>(out.base[static_cast<std::size_t>(k)])];
    for (int c = 0; c < n; ++c) {
      const double coefficient = out.K(k, c);
      if (c == out.base[static_cast<std::size_t>(k)] || coefficient == 0.0) continue;
      s << (coefficient < 0 ? " - " : " + ");
      if (std::abs(coefficient) != 1.0) s << std::abs(coefficient) << " ";
      s << names[static_cast<std::size_t>(c)];
    }
    out.names.push_back(s.str());
  }
  return out;
}

}  // namespace lever
