// lever/lab/lab.hpp: lesson 5.1's lab as library code: its controller and the loop that runs it.
//
// The lab applies a constant command at each actuator plus, when switched on, a
// gravity-compensation term equal to the current state's qfrc_bias, turned into ctrl through the
// actuator's fixed gain (for a motor of gain 1, ctrl is the torque; for a servo, it is a
// feed-forward offset of its target that adds exactly that torque whatever its bias):
//     ctrl[a] = torque[a] + (gravity_compensation ? qfrc_bias[dof of a] / (gear[a] gain[a]) : 0).
// `run` steps a model under it and hands every state visited to a callback: the start state and
// the state after each step (N + 1 rows for N steps). Each row holds the state at its time and what
// forward() computes there under the ctrl the controller chose, so the forces and accelerations
// of a row are those that act during the step that starts at it. The loop is therefore
//     forward (the current state's qfrc_bias) -> set ctrl -> forward (the row) -> step.
// `lever simulate`, the Python package and the browser build all run this one loop.
#pragma once

#include <Eigen/Core>

#include <array>
#include <functional>
#include <string>
#include <vector>

#include <lever/data.hpp>
#include <lever/model.hpp>

namespace lever::lab {

/// The lab's controller.
struct Controller {
  Eigen::VectorXd torque;             ///< (nu) the constant part, in ctrl units
  bool gravity_compensation = false;  ///< add qfrc_bias / (gear gain)
  /// Excitation for identification (`lever simulate --excite`), 0 for none: each motor's joint
  /// tracks a sum of three sines (0.3, 0.71, 1.3 Hz, plus 0.1 Hz per motor index, a third of the
  /// amplitude each) about the middle of its range, sweeping this fraction of the half range (of
  /// +-1 rad or m for an unlimited joint); a motor tracks it by a PD law tuned to dof_M0 (natural
  /// frequency 4 Hz, damping ratio 0.7), a servo (affine bias) is given it as its target. The
  /// command is added to the others.
  double excite = 0.0;
};

/// Throws StateError when the controller does not fit the model: torque of the wrong size or not
/// finite, excite outside [0, 1], or gravity compensation or excitation through an actuator with
/// gear 0 or without a fixed, nonzero gain (a torque cannot be expressed as its ctrl).
void validate(const Model& model, const Controller& controller);

/// Write the controller's command into data.ctrl. data.qfrc_bias must be the current state's.
void apply(const Model& model, const Controller& controller, Data& data);

/// The engine's warnings over many evaluations. Data keeps only those since its last reset (and
/// step() resets a bad state, as mj_step does), so a run moves them here after every call.
class WarningLog {
 public:
  /// Add data's warnings to the log and clear them in data.
  void collect(Data& data);
  int count() const;
  const std::array<WarningStat, static_cast<size_t>(Warning::kCount)>& total() const {
    return total_;
  }
  /// One line per kind of warning: "<what> (<n> times, last at index <i>)".
  std::vector<std::string> lines() const;

 private:
  std::array<WarningStat, static_cast<size_t>(Warning::kCount)> total_{};
};

/// Whether every number forward() leaves in data (and the energy) is finite.
bool outputs_finite(const Data& data);

/// What a run reports besides its rows.
struct RunLog {
  std::vector<long> clamped;  ///< per motor, the steps whose command was clamped
  WarningLog warnings;        ///< the engine's warnings over the whole run
  long non_finite_rows = 0;   ///< rows holding a number that is not finite
};

/// Called for each row: the row's index (0: the start state) and the data at that state.
using RowCallback = std::function<void(long row, const Data& data)>;

/// Run `steps` steps of the model's integrator under the controller from data's current state.
/// Throws StateError if the controller does not fit the model or steps < 0.
RunLog run(const Model& model, Data& data, const Controller& controller, long steps,
           const RowCallback& on_row = {});

}  // namespace lever::lab
