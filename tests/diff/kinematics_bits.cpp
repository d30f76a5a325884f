// Poses bit for bit: lever's kinematics() against MuJoCo 2.2.2's mj_kinematics on random states
// of every model, each number equal (==), not merely within the agreement bound. Where two faces
// are exactly flush (the xArm7's finger pads), whether a box corner touches is decided by the last
// bit of the geoms' frames, so the frames must be MuJoCo's own, not a rounding away.
#include <mujoco/mujoco.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <sstream>
#include <string>

#include <lever/diff/runs.hpp>
#include <lever/diff/twin.hpp>
#include <lever/harness/models.hpp>
#include <lever/forward.hpp>
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

// ---- mocap bodies ------------------------------------------------------------------------------

const char* const kMocapModels[] = {"tests/models/mocap.xml",
                                    "tests/diff/contact_scenes/mocap_contacts.xml"};

// The same random mocap poses written into both: positions about the arm, quaternions of any
// length (kinematics normalizes them in place, as mj_kinematics does).
void write_random_mocap(diff::Twin& twin, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> x(0.0, 0.6), y(-0.1, 0.1), z(0.3, 0.7), scale(0.2, 3.0);
  std::normal_distribution<double> normal;
  for (int i = 0; i < twin.model.nmocap; ++i) {
    const Eigen::Vector3d pos(x(rng), y(rng), z(rng));
    const double s = scale(rng);
    const Eigen::Vector4d quat(s * normal(rng), s * normal(rng), s * normal(rng), s * normal(rng));
    twin.data.mocap_pos[i] = pos;
    twin.data.mocap_quat[i] = quat;
    for (int k = 0; k < 3; ++k) twin.d->mocap_pos[3 * i + k] = pos[k];
    for (int k = 0; k < 4; ++k) twin.d->mocap_quat[4 * i + k] = quat[k];
  }
}

void compare_mocap_state(const diff::Twin& twin, BitTally& tally) {
  for (int i = 0; i < twin.model.nmocap; ++i) {
    tally.compare("mocap_pos", i, twin.data.mocap_pos[i].data(), twin.d->mocap_pos + 3 * i, 3);
    tally.compare("mocap_quat", i, twin.data.mocap_quat[i].data(), twin.d->mocap_quat + 4 * i, 4);
  }
}

bool within_bound(double ours, double theirs) {
  return std::abs(ours - theirs) <= 1e-12 * std::max(1.0, std::abs(theirs));
}

}  // namespace

TEST_CASE("diff: mocap bodies are numbered, and keyframes place them, as MuJoCo's",
          "[diff][bits][mocap]") {
  for (const char* relative : kMocapModels) {
    for (const diff::Path path : {diff::Path::kLoader, diff::Path::kEngine}) {
      INFO(relative << " (" << diff::path_name(path) << ")");
      diff::Twin twin(model_path(relative), path);
      const mjModel* m = twin.m.get();
      REQUIRE(m->nmocap == 2);
      CHECK(twin.model.nmocap == m->nmocap);
      for (int b = 0; b < m->nbody; ++b) CHECK(twin.model.body_mocapid[b] == m->body_mocapid[b]);
      for (int k = 0; k < m->nkey; ++k) {
        for (int i = 0; i < 3 * m->nmocap; ++i) {
          CHECK(twin.model.key_mpos(k, i) == m->key_mpos[3 * m->nmocap * k + i]);
        }
        for (int i = 0; i < 4 * m->nmocap; ++i) {
          CHECK(twin.model.key_mquat(k, i) == m->key_mquat[4 * m->nmocap * k + i]);
        }
      }
      // Data's mocap arrays: at the bodies after construction and reset, at the key after a
      // keyframe reset
      BitTally tally;
      Data fresh(twin.model);
      mjData* d = twin.d.get();
      mj_resetData(m, d);
      for (int i = 0; i < m->nmocap; ++i) {
        tally.compare("mocap_pos", i, fresh.mocap_pos[i].data(), d->mocap_pos + 3 * i, 3);
        tally.compare("mocap_quat", i, fresh.mocap_quat[i].data(), d->mocap_quat + 4 * i, 4);
      }
      for (int k = 0; k < m->nkey; ++k) {
        reset_keyframe(twin.model, twin.data, k);
        mj_resetDataKeyframe(m, d, k);
        compare_mocap_state(twin, tally);
        reset(twin.model, twin.data);
        mj_resetData(m, d);
        compare_mocap_state(twin, tally);
      }
      INFO(tally.differing << " of " << tally.compared << " differ; first " << tally.first);
      CHECK(tally.compared > 0);
      CHECK(tally.differing == 0);
    }
  }
}

TEST_CASE("diff: mocap bodies at random poses: poses to the bit, contacts as MuJoCo's",
          "[diff][bits][mocap]") {
  REQUIRE(mj_version() == 222);
  for (const char* relative : kMocapModels) {
    for (const diff::Path path : {diff::Path::kLoader, diff::Path::kEngine}) {
      INFO(relative << " (" << diff::path_name(path) << ")");
      diff::Twin twin(model_path(relative), path);
      std::mt19937_64 rng(diff::default_seed(relative));
      BitTally tally;
      long contacts = 0, mocap_contacts = 0, contact_mismatches = 0;
      std::string first_mismatch;
      for (int i = 0; i < kStates; ++i) {
        twin.set_state(random_state(twin.model, rng));
        write_random_mocap(twin, rng);
        twin.mujoco_forward();
        forward(twin.model, twin.data);
        compare_poses(twin, tally);
        compare_mocap_state(twin, tally);  // normalized in place, both
        const mjData* d = twin.d.get();
        if (twin.data.ncon != d->ncon) {
          if (contact_mismatches++ == 0) {
            first_mismatch = "state " + std::to_string(i) + ": ncon " +
                             std::to_string(twin.data.ncon) + " vs " + std::to_string(d->ncon);
          }
          continue;
        }
        for (int c = 0; c < d->ncon; ++c) {
          const Contact& ours = twin.data.contact[c];
          const mjContact& theirs = d->contact[c];
          ++contacts;
          const int b1 = twin.model.geom_bodyid[theirs.geom1];
          const int b2 = twin.model.geom_bodyid[theirs.geom2];
          if (twin.model.body_mocapid[b1] >= 0 || twin.model.body_mocapid[b2] >= 0) {
            ++mocap_contacts;
          }
          bool same = ours.geom1 == theirs.geom1 && ours.geom2 == theirs.geom2 &&
                      within_bound(ours.dist, theirs.dist);
          for (int k = 0; k < 3; ++k) same = same && within_bound(ours.pos[k], theirs.pos[k]);
          for (int k = 0; k < 9; ++k) {
            same = same && within_bound(ours.frame.data()[k], theirs.frame[k]);
          }
          if (!same && contact_mismatches++ == 0) {
            first_mismatch = "state " + std::to_string(i) + ", contact " + std::to_string(c);
          }
        }
      }
      INFO(tally.differing << " of " << tally.compared << " pose numbers differ; first "
                           << tally.first);
      CHECK(tally.differing == 0);
      INFO(contact_mismatches << " contacts differ; first " << first_mismatch << "; "
                              << mocap_contacts << " of " << contacts << " touch a mocap body");
      CHECK(contact_mismatches == 0);
      if (twin.model.ngeom > 0 && relative == kMocapModels[1]) CHECK(mocap_contacts >= 50);
    }
  }
}

TEST_CASE("diff: poses equal MuJoCo's to the bit on random states, MuJoCo's compiled model",
          "[diff][bits]") {
  check_bits_on_every_model(diff::Path::kEngine);
}

TEST_CASE("diff: poses equal MuJoCo's to the bit on random states, lever's loader",
          "[diff][bits]") {
  check_bits_on_every_model(diff::Path::kLoader);
}

}  // namespace lever::test
