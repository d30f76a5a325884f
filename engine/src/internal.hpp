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

/// The check at the door of every public function: Model and Data belong together and every
/// array of Data still has its size (check_fit). A pipeline (forward, step, inverse) checks once;
/// the stages it calls inside are not checked again. Allocates nothing unless it throws.
class EntryCheck {
 public:
  EntryCheck(const Model& model, Data& data, const char* where) : data_(&data) {
    if (data.work.inside_entry) {
      data_ = nullptr;  // an outer call has checked, and will clear the mark
      return;
    }
    check_fit(model, data, where);
    data.work.inside_entry = true;
  }
  /// For functions that only read data (Jacobians, solves): checks unless inside a pipeline.
  EntryCheck(const Model& model, const Data& data, const char* where) {
    if (!data.work.inside_entry) check_fit(model, data, where);
  }
  ~EntryCheck() {
    if (data_ != nullptr) data_->work.inside_entry = false;
  }
  EntryCheck(const EntryCheck&) = delete;
  EntryCheck& operator=(const EntryCheck&) = delete;

 private:
  Data* data_ = nullptr;
};

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
}  // namespace detail

/// MuJoCo's mju_isBad: NaN, or beyond +-1e10.
inline bool is_bad(double x) { return x != x || x > 1e10 || x < -1e10; }

}  // namespace lever
