// Engine functions shared between source files but not part of lever's public API.
#pragma once

#include <Eigen/Core>

#include <array>

#include <lever/data.hpp>
#include <lever/model.hpp>

namespace lever {

/// Factor M + h diag(dof_damping) into data.work.LD2 (the Euler step's implicit damping).
void factor_mass_damped(const Model& model, Data& data, double h);

/// x = (M + h diag(dof_damping))^-1 x with the factor above.
void solve_mass_damped(const Model& model, const Data& data, Eigen::Ref<Eigen::VectorXd> x);

/// A joint limit's solref and solimp, sanitized as MuJoCo's getsolparam (constraint.cpp).
void limit_parameters(const Model& model, int jnt, std::array<double, 2>& solref,
                      std::array<double, 5>& solimp);

/// A limit row's impedance at distance pos from the stop (constraint.cpp); with slope !=
/// nullptr, also d imp / d pos.
double impedance(const std::array<double, 5>& solimp, double pos, double margin, double* slope);

/// Record a warning of kind w about index info (MuJoCo's mj_warning).
inline void record_warning(Data& data, Warning w, int info) {
  WarningStat& stat = data.warning[static_cast<int>(w)];
  ++stat.number;
  stat.lastinfo = info;
}

/// MuJoCo's mju_isBad: NaN, or beyond +-1e10.
inline bool is_bad(double x) { return x != x || x > 1e10 || x < -1e10; }

}  // namespace lever
