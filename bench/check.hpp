// The correctness checks that make the timings comparable (`lever_bench --check`).
#pragma once

#include <memory>
#include <ostream>
#include <vector>

#include "fixture.hpp"

namespace lever::bench {

/// 1. The KDL bridge: on seeded random states of every serial-chain model, KDL's M (JntToMass),
///    gravity torques (JntToGravity), bias (RNE, qddot = 0), inverse dynamics (RNE), forward
///    dynamics (ChainFdSolver_RNE), tip frame (FK) and Jacobian equal lever's to 1e-9 relative.
/// 2. The same work: on the timed states (with and without the limit), lever's M, qfrc_bias and
///    qacc equal MuJoCo's.
/// 3. The batch API: BatchRunner on 1 and 2 threads gives exactly what forward() and step() give
///    one state at a time.
/// Prints a Markdown table of the largest errors; returns false if any check fails.
bool run_checks(const std::vector<std::unique_ptr<Fixture>>& fixtures, std::ostream& out);

}  // namespace lever::bench
