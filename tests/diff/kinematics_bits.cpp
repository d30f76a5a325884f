// Poses bit for bit: lever's kinematics() against MuJoCo 2.2.2's mj_kinematics on random states
// of every model, each number equal (==), not merely within the agreement bound. Where two faces
// are exactly flush (the xArm7's finger pads), whether a box corner touches is decided by the last
// bit of the geoms' frames, so the frames must be MuJoCo's own, not a rounding away.
#include <mujoco/mujoco.h>

#include <catch2/catch.hpp>
#include <random>
#include <sstream>
#include <string>

#include <lever/diff/runs.hpp>
#include <lever/diff/twin.hpp>
#include <lever/harness/models.hpp>
#include <lever/kinematics.hpp>

namespace lever::test {

namespace {

constexpr int kStates = 200;

// Counts the numbers that differ in any bit of their value (+0 and -0 count as equal), and keeps
// the first.
struct BitTally {
  long compared = 0, differing = 0;
  std::string first;

  void compare(const char* name, int row, const double* ours, const mjtNum* theirs, int n) {
    for (int k = 0; k < n; ++k) {
      ++compared;
      if (ours[k] == theirs[k]) continue;
      if (differing++ == 0) {
        std::ostringstream out;
        out.precision(17);
        out << name << "[" << row << "][" << k << "]: lever " << ours[k] << ", MuJoCo "
            << theirs[k];
        first = out.str();
      }
    }
  }
};

void compare_poses(const diff::Twin& twin, BitTally& tally) {
  const Model& model = twin.model;
  const Data& data = twin.data;
  const mjData* d = twin.d.get();
  for (int b = 0; b < model.nbody; ++b) {
    tally.compare("xpos", b, data.xpos[b].data(), d->xpos + 3 * b, 3);
    tally.compare("xquat", b, data.xquat[b].data(), d->xquat + 4 * b, 4);
    tally.compare("xmat", b, data.xmat[b].data(), d->xmat + 9 * b, 9);
    tally.compare("xipos", b, data.xipos[b].data(), d->xipos + 3 * b, 3);
    tally.compare("ximat", b, data.ximat[b].data(), d->ximat + 9 * b, 9);
  }
  for (int j = 0; j < model.njnt; ++j) {
    tally.compare("xanchor", j, data.xanchor[j].data(), d->xanchor + 3 * j, 3);
    tally.compare("xaxis", j, data.xaxis[j].data(), d->xaxis + 3 * j, 3);
  }
  for (int g = 0; g < model.ngeom; ++g) {
    tally.compare("geom_xpos", g, data.geom_xpos[g].data(), d->geom_xpos + 3 * g, 3);
    tally.compare("geom_xmat", g, data.geom_xmat[g].data(), d->geom_xmat + 9 * g, 9);
  }
  for (int s = 0; s < model.nsite; ++s) {
    tally.compare("site_xpos", s, data.site_xpos[s].data(), d->site_xpos + 3 * s, 3);
    tally.compare("site_xmat", s, data.site_xmat[s].data(), d->site_xmat + 9 * s, 9);
  }
}

void check_bits_on_every_model(diff::Path path) {
  REQUIRE(mj_version() == 222);
  for (const std::string& file : all_model_files()) {
    INFO(file << " (" << diff::path_name(path) << ")");
    diff::Twin twin(file, path);
    std::mt19937_64 rng(diff::default_seed(file));
    BitTally tally;
    for (int i = 0; i < kStates; ++i) {
      twin.set_state(random_state(twin.model, rng));
      mj_kinematics(twin.m.get(), twin.d.get());
      kinematics(twin.model, twin.data);
      compare_poses(twin, tally);
    }
    INFO(tally.differing << " of " << tally.compared << " numbers differ; first " << tally.first);
    CHECK(tally.compared > 0);
    CHECK(tally.differing == 0);
  }
}

}  // namespace

TEST_CASE("diff: poses equal MuJoCo's to the bit on random states, MuJoCo's compiled model",
          "[diff][bits]") {
  check_bits_on_every_model(diff::Path::kEngine);
}

TEST_CASE("diff: poses equal MuJoCo's to the bit on random states, lever's loader",
          "[diff][bits]") {
  check_bits_on_every_model(diff::Path::kLoader);
}

}  // namespace lever::test
