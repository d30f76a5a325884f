// lever_step_time MODEL [STEPS]: the time of one lever::step on MODEL, from the lab's Bent pose
// with gravity compensation, timed with std::chrono over STEPS steps (best of 5 runs). Built both
// natively and with Emscripten (run by node), so that `make web-bench` compares the same loop on
// both. A measurement script, not a test.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <lever/lever.hpp>
#include <lever/mjcf.hpp>
#include <sstream>
#include <string>

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: lever_step_time MODEL [STEPS]\n");
    return 2;
  }
  std::ifstream in(argv[1], std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  const int steps = argc > 2 ? std::atoi(argv[2]) : 200000;
  const lever::Model model = lever::mjcf::load_string(text.str(), argv[1]);
  lever::Data data(model);
  double best = 1e30;
  for (int run = 0; run < 5; ++run) {
    lever::reset(model, data);
    for (int i = 0; i < model.nq && i < 2; ++i) data.qpos[i] = i == 0 ? 0.6 : -1.2;
    const auto start = std::chrono::steady_clock::now();
    for (int i = 0; i < steps; ++i) {
      lever::forward(model, data);  // the lab's controller reads the current qfrc_bias
      data.ctrl = data.qfrc_bias.head(model.nu);
      lever::step(model, data);
    }
    const std::chrono::duration<double, std::nano> took = std::chrono::steady_clock::now() - start;
    best = std::min(best, took.count() / steps);
  }
  std::printf("%s: %.0f ns per lab step (forward + step), best of 5 x %d; qpos[0] = %.17g\n",
              argv[1], best, steps, data.qpos[0]);
  return 0;
}
