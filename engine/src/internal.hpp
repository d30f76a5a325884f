// Engine functions shared between source files but not part of lever's public API.
#pragma once

#include <Eigen/Core>

#include <array>

#include <lever/data.hpp>
#include <lever/fields.hpp>
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

/// Whether the arrays a caller assigns (the state and the inputs) still have the model's sizes.
inline bool inputs_fit(const Model& model, const Data& data) {
  return data.qpos.size() == model.nq && data.qvel.size() == model.nv &&
         data.qacc.size() == model.nv && data.ctrl.size() == model.nu &&
         data.qfrc_applied.size() == model.nv;
}

/// The check at the door of every public function. Model and Data are matched where they meet:
/// set_const gives a model a fresh tag, and a Data that passed check_fit against a model keeps its
/// tag. A call then costs a comparison of tags and of the input arrays' sizes; only a Data meeting
/// a model (or a model edition) it has not been checked against walks the whole field table.
/// No guard object: nothing to unwind on the hot path. checked_before: this Data has met this
/// model edition and its inputs kept their sizes.
inline bool checked_before(const Model& model, const Data& data) {
  return model.fit_tag != 0 && data.model_tag == model.fit_tag && inputs_fit(model, data);
}

/// The entry check of a function that writes data: a Data that fits adopts the model's tag.
inline void check_entry(const Model& model, Data& data, const char* where) {
  if (checked_before(model, data)) return;
  check_fit(model, data, where);  // throws, naming the array that does not fit
  data.model_tag = model.fit_tag;
}

/// The same for functions that only read data (Jacobians, solves).
inline void check_entry(const Model& model, const Data& data, const char* where) {
  if (checked_before(model, data)) return;
  check_fit(model, data, where);
}

/// The three stages of forward() (MuJoCo's mj_fwdPosition, mj_fwdVelocity, and mj_fwdActuation +
/// mj_fwdAcceleration + mj_fwdConstraint); step1()/step2() split a step between them.
void position_stage(const Model& model, Data& data);
void velocity_stage(const Model& model, Data& data);
void acceleration_stage(const Model& model, Data& data);

/// Throws StateError unless a vector argument has n elements.
void check_argument_size(long size, long n, const char* where, const char* what);

namespace detail {
/// Size every array of the field table in data for the model, zero-filled (the Data constructor).
void size_data_arrays(const Model& model, Data& data);

/// MuJoCo 2.2.2's implicit step (implicit.cpp), after forward().
void implicit_step(const Model& model, Data& data);

/// qpos advanced by velocity qvel for time h, joint by joint (MuJoCo's mj_integratePos): hinge and
/// slide coordinates add h qvel; a ball's or free joint's quaternion turns by the rotation h w
/// about its body axes and is normalized. Used by every integrator.
void integrate_positions(const Model& model, double* qpos, const double* qvel, double h);
}  // namespace detail

/// MuJoCo's mju_isBad: NaN, or beyond +-1e10.
inline bool is_bad(double x) { return x != x || x > 1e10 || x < -1e10; }

}  // namespace lever
