// lever_bench: lever against MuJoCo 2.2.2 and Orocos KDL, every model of a directory, one process.
//
//   lever_bench [--models=DIR] [--batch_states=N] [Google Benchmark flags]
//   lever_bench --check [--models=DIR]     the correctness checks only (bench/check.hpp)
//
// `make bench` runs it with repetitions and random interleaving and turns its JSON output into
// docs/performance.md (bench/report.cpp).
#include <benchmark/benchmark.h>

#include <Eigen/Core>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <iostream>
#include <string>

#include "benchmarks.hpp"
#include "check.hpp"
#include "fixture.hpp"
#include "pinocchio_ops.hpp"

#ifndef LEVER_BENCH_MODELS_DIR
#define LEVER_BENCH_MODELS_DIR "models"
#endif
#ifndef LEVER_BENCH_SCENES_DIR
#define LEVER_BENCH_SCENES_DIR "bench/scenes"
#endif

namespace {

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) == 0) {
      const auto colon = line.find(':');
      if (colon != std::string::npos) return line.substr(line.find_first_not_of(" \t", colon + 1));
    }
  }
  return "unknown";
}

}  // namespace

int main(int argc, char** argv) {
  std::string models_dir = LEVER_BENCH_MODELS_DIR;
  bool check = false;
  int batch_states = 1024;
  // our own flags, removed before Google Benchmark sees the rest
  int kept = 1;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--check") {
      check = true;
    } else if (arg.rfind("--models=", 0) == 0) {
      models_dir = arg.substr(9);
    } else if (arg.rfind("--batch_states=", 0) == 0) {
      batch_states = std::max(1, std::stoi(arg.substr(15)));
    } else {
      argv[kept++] = argv[i];
    }
  }
  argc = kept;

  std::vector<std::unique_ptr<lever::bench::Fixture>> fixtures;
  try {
    for (const std::string& path : lever::bench::model_files(models_dir)) {
      fixtures.push_back(lever::bench::make_fixture(path));
    }
    for (const std::string& path : lever::bench::scene_files(models_dir)) {
      fixtures.push_back(lever::bench::make_scene_fixture(path));
    }
    // the sensor-heavy model (every sensor type lever evaluates), timed on forward alone
    if (models_dir == LEVER_BENCH_MODELS_DIR) {
      fixtures.push_back(lever::bench::make_sensor_fixture(LEVER_BENCH_SENSOR_MODEL));
      // the scenes on real model files: the default run's
      for (const std::string& path : lever::bench::robot_scene_files(LEVER_BENCH_SCENES_DIR)) {
        fixtures.push_back(lever::bench::make_scene_fixture(path));
      }
    }
  } catch (const std::exception& e) {
    std::cerr << "lever_bench: " << e.what() << "\n";
    return 2;
  }
  if (fixtures.empty()) {
    std::cerr << "lever_bench: no *.xml model in " << models_dir << "\n";
    return 2;
  }
  // fewest joints first: the table shows how the cost grows
  std::stable_sort(fixtures.begin(), fixtures.end(),
                   [](const auto& a, const auto& b) { return a->model.nv < b->model.nv; });

  if (check) {
    const bool ok = lever::bench::run_checks(fixtures, std::cout);
    std::cout << (ok ? "\nall checks passed\n" : "\nSOME CHECKS FAILED\n");
    return ok ? 0 : 1;
  }

  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;

  benchmark::AddCustomContext("cpu_model", cpu_model());
  benchmark::AddCustomContext("compiler", LEVER_BENCH_COMPILER);
  benchmark::AddCustomContext("cxx_flags", LEVER_BENCH_CXX_FLAGS);
  benchmark::AddCustomContext("cmake_build_type", LEVER_BENCH_BUILD_TYPE);
  benchmark::AddCustomContext("mujoco_version", mj_versionString());
  benchmark::AddCustomContext("kdl_version", LEVER_BENCH_KDL_VERSION);
  if (lever::bench::have_pinocchio()) {
    benchmark::AddCustomContext("pinocchio_version", lever::bench::pinocchio_peer_version());
  }
  benchmark::AddCustomContext("eigen_version", std::to_string(EIGEN_WORLD_VERSION) + "." +
                                                   std::to_string(EIGEN_MAJOR_VERSION) + "." +
                                                   std::to_string(EIGEN_MINOR_VERSION));
  benchmark::AddCustomContext("batch_states", std::to_string(batch_states));
  for (const auto& f : fixtures) {
    const lever::Model& m = f->model;
    std::string about = "nv=" + std::to_string(m.nv) + " nbody=" + std::to_string(m.nbody) +
                        " nsite=" + std::to_string(m.nsite) + " nu=" + std::to_string(m.nu) +
                        " loader=" + f->loader;
    if (f->site >= 0) about += " site=" + m.site_name[static_cast<std::size_t>(f->site)];
    if (f->limit) about += " limit_joint=" + m.jnt_name[static_cast<std::size_t>(f->limit_joint)];
    if (f->sensors) {
      about += " sensors: nsensor=" + std::to_string(m.nsensor) +
               " nsensordata=" + std::to_string(m.nsensordata) + ", at its first keyframe";
    } else if (f->scene) {
      about += " scene: at rest after 1 s, ncon=" + std::to_string(f->ncon);
    } else {
      about += f->chain ? " kdl=yes" : " kdl=no (" + f->kdl_note + ")";
    }
    benchmark::AddCustomContext("model." + f->name, about);
  }

  lever::bench::register_benchmarks(fixtures, batch_states);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
