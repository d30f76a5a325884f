// What the fuzz targets check, as plain functions: the libFuzzer entry points (fuzz_mjcf.cpp,
// fuzz_engine.cpp) call them and abort on a finding; tests/hostile replays every saved input
// through the same functions without libFuzzer. Each returns "" when the input was handled
// correctly, else a sentence describing the finding.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace lever::fuzz {

/// mjcf_lite's load_string on arbitrary bytes: it must return a model that set_const() accepts and
/// that evaluates (forward, inverse, one step of each integrator) at qpos0 with finite outputs and
/// no warning, or throw a lever::Error whose message is not empty. Anything else is a finding.
std::string check_mjcf(const std::uint8_t* data, std::size_t size);

/// The engine on every model of models/ and tests/models/: the first byte picks the model, the
/// rest fills qpos, qvel, ctrl, qfrc_applied and qacc (NaN, infinities, huge, denormal and
/// ordinary values) and chooses the integrator and how many steps to take. forward, inverse and
/// step must leave every output finite unless they recorded a warning, and step must leave a
/// finite state. `models_dir` is the repository's root (models/ and tests/models/ below it).
std::string check_engine(const std::uint8_t* data, std::size_t size, const std::string& models_dir);

/// How many models check_engine() chooses from (0 if none loads: itself a finding).
int engine_model_count(const std::string& models_dir);

}  // namespace lever::fuzz
