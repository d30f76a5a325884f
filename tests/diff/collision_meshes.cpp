// Meshes colliding end to end: models compiled by lever's loader (its mesh vertices and qhull
// hulls, not MuJoCo's copied) against MuJoCo 2.2.2 compiling the same file, on random states. The
// files are real ones read in place from the shared robot files: the Menagerie's Panda arm
// (panda_nohand.xml, its links' collision meshes against each other), and a gripper of the
// Panda hand's and the 2F-85's meshes closing on a box over a plane (mesh-mesh, mesh-box,
// plane-mesh), with and without multiccd. As in collision_driver.cpp, MuJoCo's collision stage is
// run on lever's geom poses (which agree with MuJoCo's to the bound), and the two contact lists
// must be the same list.
#include <mujoco/mujoco.h>
#include <catch2/catch.hpp>

#include <array>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include <lever/collision.hpp>
#include <lever/diff/twin.hpp>
#include <lever/harness/models.hpp>
#include <lever/harness/tolerance.hpp>
#include <lever/kinematics.hpp>

namespace lever::test::mesh_diff {

namespace {

std::string gripper_scene() {
  return R"(<mujoco>
  <compiler autolimits="true" meshdir=")" + robots_dir() + R"(/menagerie-2022/"/>
  <asset>
    <mesh name="hand" file="franka_emika_panda/assets/hand.stl"/>
    <mesh name="finger" file="franka_emika_panda/assets/finger_0.obj"/>
    <mesh name="pad" file="robotiq_2f85/assets/pad.stl"/>
  </asset>
  <worldbody>
    <geom name="floor" type="plane" size="1 1 0.1"/>
    <body name="hand" pos="0 0 0.16" quat="0 1 0 0">
      <joint name="lift" type="slide" axis="0 0 1" range="-0.1 0.1"/>
      <geom type="mesh" mesh="hand"/>
      <body name="left" pos="0 0 0.0584">
        <joint name="left" type="slide" axis="0 1 0" range="-0.01 0.04"/>
        <geom type="mesh" mesh="finger"/>
      </body>
      <body name="right" pos="0 0 0.0584" quat="0 0 0 1">
        <joint name="right" type="slide" axis="0 1 0" range="-0.01 0.04"/>
        <geom type="mesh" mesh="finger"/>
      </body>
    </body>
    <body name="box" pos="0 0 0.03">
      <freejoint/>
      <geom type="box" size="0.02 0.025 0.03"/>
    </body>
    <body name="pads" pos="0.05 0 0.03">
      <freejoint/>
      <geom type="mesh" mesh="pad"/>
      <geom type="cylinder" size="0.01 0.02" pos="0 0.02 0"/>
    </body>
  </worldbody>
</mujoco>)";
}

struct MeshTally {
  int states = 0, contacts = 0, mesh_contacts = 0;
  double worst = 0;
};

void random_pose(const Model& model, std::mt19937_64& rng, Eigen::Ref<Eigen::VectorXd> qpos) {
  std::uniform_real_distribution<double> unit(0.0, 1.0), spread(-0.06, 0.06);
  std::normal_distribution<double> normal(0.0, 1.0);
  qpos = model.qpos0;
  for (int j = 0; j < model.njnt; ++j) {
    const int adr = model.jnt_qposadr[j];
    const auto& range = model.jnt_range[j];
    switch (model.jnt_type[j]) {
      case JointType::kHinge:
      case JointType::kSlide:
        qpos[adr] = range[0] + (range[1] - range[0]) * unit(rng);
        break;
      case JointType::kFree:
        qpos[adr] += spread(rng);
        qpos[adr + 1] += spread(rng);
        qpos[adr + 2] += 0.5 * spread(rng);
        qpos.segment<4>(adr + 3) =
            Eigen::Vector4d(normal(rng), normal(rng), normal(rng), normal(rng)).normalized();
        break;
      case JointType::kBall: break;
    }
  }
}

MeshTally compare_file(const std::string& file, int states, bool multiccd, std::uint64_t seed) {
  diff::Twin twin(file, diff::Path::kLoader);
  Model& model = twin.model;
  Data& data = twin.data;
  mjModel* m = twin.m.get();
  mjData* d = twin.d.get();
  if (multiccd) model.opt.enableflags |= kEnableMulticcd;
  if (multiccd) m->opt.enableflags |= mjENBL_MULTICCD;
  std::mt19937_64 rng(seed);
  MeshTally tally;
  for (int s = 0; s < states; ++s) {
    INFO(file << (multiccd ? " (multiccd)" : "") << ", state " << s);
    random_pose(model, rng, data.qpos);
    kinematics(model, data);
    collision(model, data);
    for (int i = 0; i < model.nq; ++i) d->qpos[i] = data.qpos[i];
    mj_kinematics(m, d);
    for (int g = 0; g < model.ngeom; ++g) {
      // a visual mesh lever did not read keeps its frame as written (MuJoCo's is the mesh's);
      // it cannot collide
      const int mesh = model.geom_dataid[g];
      if (mesh >= 0 && model.mesh_vertnum[mesh] == 0) continue;
      for (int i = 0; i < 3; ++i) {
        REQUIRE(excess(data.geom_xpos[g][i], d->geom_xpos[3 * g + i],
                       magnitude(d->geom_xpos + 3 * g, 3)) <= 1);
        d->geom_xpos[3 * g + i] = data.geom_xpos[g][i];
      }
      for (int i = 0; i < 9; ++i) d->geom_xmat[9 * g + i] = data.geom_xmat[g](i / 3, i % 3);
    }
    mj_collision(m, d);
    CHECK(data.warning[static_cast<int>(Warning::kContactUnsupported)].number == 0);
    REQUIRE(data.ncon == d->ncon);
    for (int k = 0; k < d->ncon; ++k) {
      const Contact& ours = data.contact[k];
      const mjContact& c = d->contact[k];
      INFO("contact " << k << ": geoms " << c.geom1 << ", " << c.geom2);
      REQUIRE(ours.geom1 == c.geom1);
      REQUIRE(ours.geom2 == c.geom2);
      CHECK(ours.dim == c.dim);
      const auto check = [&](const char* field, int i, double a, double b, double size) {
        const double e = excess(a, b, size);
        tally.worst = std::max(tally.worst, e);
        INFO(describe(field, i, a, b, size));
        CHECK(e <= 1);
      };
      check("dist", 0, ours.dist, c.dist, c.dist);
      for (int i = 0; i < 3; ++i) check("pos", i, ours.pos[i], c.pos[i], magnitude(c.pos, 3));
      for (int i = 0; i < 9; ++i) check("frame", i, ours.frame(i / 3, i % 3), c.frame[i], 1.0);
      ++tally.contacts;
      if (m->geom_type[c.geom1] == mjGEOM_MESH || m->geom_type[c.geom2] == mjGEOM_MESH) {
        ++tally.mesh_contacts;
      }
    }
    ++tally.states;
  }
  return tally;
}

}  // namespace

TEST_CASE("mesh collisions of models lever compiled agree with MuJoCo's", "[diff][collision]") {
  REQUIRE(mj_version() == 222);
  const std::filesystem::path scene =
      std::filesystem::temp_directory_path() / "lever_gripper_meshes.xml";
  {
    std::ofstream out(scene);
    out << gripper_scene();
  }
  const std::string panda = robots_dir() + "/menagerie-2022/franka_emika_panda/panda_nohand.xml";
  // the arm's links touch each other in a few states in a hundred: more states, fewer contacts
  for (const std::string& file : {panda, scene.string()}) {
    const bool arm = file == panda;
    for (const bool multiccd : {false, true}) {
      const MeshTally t = compare_file(file, arm ? 2000 : 300, multiccd, 32 + multiccd);
      WARN(std::filesystem::path(file).filename().string()
           << (multiccd ? ", multiccd" : "") << ": " << t.states << " states, " << t.contacts
           << " contacts (" << t.mesh_contacts << " with a mesh), worst " << t.worst
           << " of the bound");
      CHECK(t.mesh_contacts > (arm ? 40 : t.states));  // the states reach mesh contacts
    }
  }
  std::filesystem::remove(scene);
}

}  // namespace lever::test::mesh_diff
