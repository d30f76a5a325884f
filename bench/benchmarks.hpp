// Registration of every benchmark with Google Benchmark.
#pragma once

#include <memory>
#include <vector>

#include "fixture.hpp"

namespace lever::bench {

/// Register <operation>/<model>/<peer> for every fixture and peer, and the batch benchmarks
/// (batch_forward/<model>/<peer>/threads:<n>, `batch_states` states per call). The fixtures must
/// outlive the benchmark run.
void register_benchmarks(const std::vector<std::unique_ptr<Fixture>>& fixtures, int batch_states);

}  // namespace lever::bench
