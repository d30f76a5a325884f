// The sensors against MuJoCo 2.2.2, sensor by sensor: tests/models/sensors.xml (an arm, a ball
// pendulum and a free body, every sensor type lever evaluates, no contact) at random states and
// after one step of each integrator from them, within 1e-12; and the gripper of models/gripper.xml
// with touch pads on its fingers, a force/torque sensor at its wrist, an accelerometer in the box
// and a rangefinder looking down (the sensors added to the file's text here, so the model the
// lessons use stays as it is), at random states and along a grasp, with both friction cones,
// within the contact solver's bound (MuJoCo at tolerance 0). Each test prints the worst error
// per sensor type, in units of the bound 1e-12 max(1, |mujoco|).
#include <mujoco/mujoco.h>
#include <catch2/catch.hpp>

#include <lever/diff/compare.hpp>
#include <lever/diff/report.hpp>
#include <lever/diff/twin.hpp>
#include <lever/lever.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <string>

#include <lever/harness/models.hpp>
#include <lever/harness/random_state.hpp>
#include <lever/harness/tolerance.hpp>

#include "sensors/sensors.hpp"  // the engine's ray casting (this executable sees engine/src)

namespace lever::test {

namespace {

// The worst difference per sensor type, in units of 1e-12 max(1, |mujoco|), and whether each
// sensor ever read something other than 0.
struct SensorAgreement {
  std::map<std::string, double> worst;  // by type
  std::vector<bool> nonzero;
  long compared = 0;

  void add(const Model& model, const Data& data, const mjData* d) {
    nonzero.resize(static_cast<size_t>(model.nsensor), false);
    for (int s = 0; s < model.nsensor; ++s) {
      double& w = worst[sensor_type_name(model.sensor_type[s])];
      for (int k = 0; k < model.sensor_dim[s]; ++k) {
        const int i = model.sensor_adr[s] + k;
        const double ours = data.sensordata[i], theirs = d->sensordata[i];
        w = std::max(w, std::abs(ours - theirs) / (1e-12 * std::max(1.0, std::abs(theirs))));
        if (theirs != 0) nonzero[static_cast<size_t>(s)] = true;
        ++compared;
      }
    }
  }

  void print(const std::string& title) const {
    std::printf("%s: worst |lever - mujoco| / (1e-12 max(1, |mujoco|)) per sensor type\n",
                title.c_str());
    for (const auto& [type, w] : worst) std::printf("  %-14s %.3g\n", type.c_str(), w);
  }
};

// lever's and MuJoCo's forward at state s, then their sensors
void forward_both(diff::Twin& twin, const State& s) {
  twin.set_state(s);
  forward(twin.model, twin.data);
  twin.mujoco_forward();
}

// models/gripper.xml (whose fingers carry a touch pad each: a box site around the two tip spheres)
// with more sensors: a force/torque sensor and a rangefinder at the carriage, an accelerometer and
// a gyro in the box, the lift's limit force, the servos' forces.
std::string gripper_with_sensors() {
  std::string xml = read_text(model_path("models/gripper.xml"));
  const auto insert_after = [&xml](const std::string& anchor, const std::string& text) {
    const size_t at = xml.find(anchor);
    REQUIRE(at != std::string::npos);
    xml.insert(xml.find("/>", at) + 2, text);
  };
  insert_after("<geom name=\"carriage\"",
               "<site name=\"wrist\" pos=\"0 0 -0.02\" euler=\"3.14159 0 0.3\"/>");
  xml.insert(xml.find("<keyframe>"), R"(<sensor>
    <force name="wrist_force" site="wrist"/>
    <torque name="wrist_torque" site="wrist"/>
    <rangefinder name="range" site="wrist"/>
    <accelerometer name="box_acc" site="box"/>
    <gyro name="box_gyro" site="box"/>
    <framelinacc name="box_linacc" objtype="body" objname="box"/>
    <frameangacc name="box_angacc" objtype="geom" objname="box"/>
    <jointlimitfrc name="lift_limit" joint="lift"/>
    <actuatorfrc name="left_servo" actuator="left"/>
    <subtreelinvel name="box_vel" body="box"/>
  </sensor>
  )");
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / "lever_gripper_with_sensors.xml";
  std::ofstream(file) << xml;
  return file.string();
}

}  // namespace

TEST_CASE("diff: every sensor agrees with MuJoCo at random states and after a step",
          "[diff][sensors]") {
  REQUIRE(mj_version() == 222);
  const std::string file = model_path("tests/models/sensors.xml");
  for (const diff::Path path : {diff::Path::kLoader, diff::Path::kEngine}) {
    diff::Twin twin(file, path);
    INFO(diff::path_name(path) << " path");
    REQUIRE(twin.model.nsensor >= 40);
    SensorAgreement forward_agreement, step_agreement;
    std::mt19937_64 rng(seed_for(file));
    constexpr int kStates = 300;
    for (int k = 0; k < kStates; ++k) {
      State s = random_state(twin.model, rng);
      s.time = 0.1 * k;  // the clock
      forward_both(twin, s);
      forward_agreement.add(twin.model, twin.data, twin.d.get());
      // a step leaves the sensors of the state it starts from (RK4: not of its later stages)
      const Integrator integrator = static_cast<Integrator>(k % 3);
      twin.set_integrator(integrator);
      twin.set_state(s);
      step(twin.model, twin.data);
      mj_step(twin.m.get(), twin.d.get());
      step_agreement.add(twin.model, twin.data, twin.d.get());
    }
    forward_agreement.print(std::string("sensors.xml, ") + diff::path_name(path) + " path");
    step_agreement.print(std::string("sensors.xml after a step, ") + diff::path_name(path) +
                         " path");
    for (const SensorAgreement* a : {&forward_agreement, &step_agreement}) {
      for (const auto& [type, w] : a->worst) {
        INFO(type);
        CHECK(w <= 1.0);
      }
    }
    // every sensor read something (touch: nothing to touch in this model)
    for (int s = 0; s < twin.model.nsensor; ++s) {
      if (twin.model.sensor_type[s] == SensorType::kTouch) continue;
      INFO("sensor " << s << " '" << twin.model.sensor_name[s] << "'");
      CHECK(forward_agreement.nonzero[static_cast<size_t>(s)]);
    }
  }
}

TEST_CASE("diff: the gripper's sensors agree with MuJoCo, touch and force included",
          "[diff][sensors][contact]") {
  REQUIRE(mj_version() == 222);
  const std::string file = gripper_with_sensors();
  for (const Cone cone : {Cone::kPyramidal, Cone::kElliptic}) {
    diff::Twin twin(file, diff::Path::kLoader);
    twin.set_cone(cone, 1.0);
    const std::string title =
        std::string("gripper, ") + (cone == Cone::kElliptic ? "elliptic" : "pyramidal") + " cone";
    INFO(title);
    REQUIRE(twin.model.contacts_possible);
    SensorAgreement agreement;
    // random states: the box dropped anywhere, a quarter at rest
    std::mt19937_64 rng(seed_for(file));
    for (int k = 0; k < 100; ++k) {
      State s = random_state(twin.model, rng);
      if (k % 4 == 0) s.qvel.setZero();
      forward_both(twin, s);
      agreement.add(twin.model, twin.data, twin.d.get());
    }
    // a grasp: down to the box, close, lift; lever evaluates MuJoCo's state at every step
    twin.reset();
    const int left = twin.model.sensor("left_touch"), right = twin.model.sensor("right_touch");
    double grip = 0;
    for (int k = 0; k < 400; ++k) {
      const double t = twin.d->time;
      twin.d->ctrl[0] = t < 0.6 ? -0.23 : -0.15;  // lift
      twin.d->ctrl[1] = twin.d->ctrl[2] = t < 0.3 ? 0.0 : 0.04;  // fingers
      twin.follow_mujoco();
      forward(twin.model, twin.data);
      twin.mujoco_forward();
      agreement.add(twin.model, twin.data, twin.d.get());
      grip = std::max(grip, std::min(twin.data.sensordata[twin.model.sensor_adr[left]],
                                     twin.data.sensordata[twin.model.sensor_adr[right]]));
      mj_step(twin.m.get(), twin.d.get());
    }
    agreement.print(title);
    for (const auto& [type, w] : agreement.worst) {
      INFO(type);
      CHECK(w <= diff::kContactSolverBound);
    }
    // both pads felt the box at once, pushed by servos of at most 10 N
    INFO("largest grip both pads felt: " << grip << " N");
    CHECK(grip > 1.0);
    CHECK(grip <= 10.5);
    for (int s = 0; s < twin.model.nsensor; ++s) {
      INFO("sensor '" << twin.model.sensor_name[s] << "'");
      CHECK(agreement.nonzero[static_cast<size_t>(s)]);
    }
  }
}

}  // namespace lever::test

namespace lever::test {

TEST_CASE("diff: a ray meets every geom type where MuJoCo's does", "[diff][sensors]") {
  // random shapes, poses and rays, many of them starting inside the shape or grazing it
  std::mt19937_64 rng(2202);
  std::uniform_real_distribution<double> u(-1, 1), size(0.05, 0.5);
  const GeomType types[] = {GeomType::kPlane,     GeomType::kSphere,   GeomType::kCapsule,
                            GeomType::kEllipsoid, GeomType::kCylinder, GeomType::kBox};
  for (const GeomType type : types) {
    int hits = 0;
    double worst = 0;
    for (int k = 0; k < 20000; ++k) {
      const Eigen::Vector3d pos(u(rng), u(rng), u(rng)), pnt(u(rng), u(rng), u(rng));
      Eigen::Vector3d vec(u(rng), u(rng), u(rng));
      if (k % 3 == 0) vec = pos - pnt + 0.2 * vec;  // aimed at the shape
      Eigen::Vector3d sz(size(rng), size(rng), size(rng));
      if (type == GeomType::kPlane && k % 2 == 0) sz[0] = sz[1] = 0;  // infinite
      const Eigen::Matrix3d R = quat_to_mat(quat_normalized(Quat(u(rng), u(rng), u(rng), u(rng))));
      const Mat3 Rrow = R;
      const double ours = ray_shape(pos, Rrow, sz, pnt, vec, type);
      const double theirs = mju_rayGeom(pos.data(), Rrow.data(), sz.data(), pnt.data(), vec.data(),
                                        static_cast<int>(type));
      INFO("geom type " << static_cast<int>(type) << ", ray " << k);
      REQUIRE((ours < 0) == (theirs < 0));
      if (theirs >= 0) {
        ++hits;
        worst = std::max(worst, std::abs(ours - theirs) / (1e-12 * std::max(1.0, theirs)));
      }
    }
    INFO("geom type " << static_cast<int>(type) << ": " << hits << " hits, worst " << worst);
    CHECK(hits > 2000);
    CHECK(worst <= 1.0);
  }
}

TEST_CASE("diff: the rangefinder's ray skips its own body and invisible geoms as mj_ray does",
          "[diff][sensors]") {
  diff::Twin twin(model_path("tests/models/sensors.xml"), diff::Path::kLoader);
  std::mt19937_64 rng(77);
  std::uniform_real_distribution<double> u(-1, 1);
  int hits = 0;
  for (int k = 0; k < 300; ++k) {
    forward_both(twin, random_state(twin.model, rng));
    // rays from every site in random directions, the site's body excluded
    for (int s = 0; s < twin.model.nsite; ++s) {
      const Eigen::Vector3d vec(u(rng), u(rng), u(rng));
      const int body = twin.model.site_bodyid[s];
      int our_geom = -1, their_geom = -1;
      const double ours = ray(twin.model, twin.data, twin.data.site_xpos[s], vec, body, &our_geom);
      const double theirs = mj_ray(twin.m.get(), twin.d.get(), twin.d->site_xpos + 3 * s,
                                   vec.data(), nullptr, 1, body, &their_geom);
      INFO("state " << k << ", site " << s);
      REQUIRE(our_geom == their_geom);
      CHECK(std::abs(ours - theirs) <= 1e-12 * std::max(1.0, std::abs(theirs)));
      hits += our_geom >= 0;
    }
  }
  CHECK(hits > 300);
}

}  // namespace lever::test

namespace lever::test {

namespace {

// The user sensors' callback on both sides: each user sensor's numbers from the state of its
// stage (qpos at the position stage, qvel at the velocity stage, qacc at the acceleration stage),
// so that both engines must call it at the same stages with the same data.
void fill_user_sensors(int nsensor, const int* type, const int* stage_of, const int* adr,
                       const int* dim, int stage, const double* qpos, const double* qvel,
                       const double* qacc, double* sensordata) {
  for (int s = 0; s < nsensor; ++s) {
    if (type[s] != mjSENS_USER || stage_of[s] != stage) continue;
    const double* from = stage == mjSTAGE_POS ? qpos : stage == mjSTAGE_VEL ? qvel : qacc;
    for (int k = 0; k < dim[s]; ++k) sensordata[adr[s] + k] = 10 * from[k] + s;
  }
}

void mujoco_user_sensors(const mjModel* m, mjData* d, int stage) {
  fill_user_sensors(m->nsensor, m->sensor_type, m->sensor_needstage, m->sensor_adr, m->sensor_dim,
                    stage, d->qpos, d->qvel, d->qacc, d->sensordata);
}

}  // namespace

TEST_CASE("diff: user sensors are filled by the callback at MuJoCo's stages, cut off as MuJoCo's",
          "[diff][sensors]") {
  REQUIRE(mj_version() == 222);
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / "lever_user_sensors.xml";
  std::ofstream(file) << R"(<mujoco>
  <worldbody>
    <body name="arm" pos="0 0 1">
      <joint name="a" axis="0 1 0"/>
      <joint name="b" type="slide" axis="1 0 0"/>
      <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03"/>
      <site name="tip" pos="0.3 0 0"/>
    </body>
  </worldbody>
  <actuator><motor name="m" joint="a"/></actuator>
  <sensor>
    <jointpos joint="a"/>
    <user name="u_pos" objtype="site" objname="tip" dim="2" needstage="pos" datatype="real"
          cutoff="4"/>
    <user name="u_vel" objtype="joint" objname="b" dim="1" needstage="vel" datatype="positive"
          cutoff="3"/>
    <user name="u_acc" objtype="actuator" objname="m" dim="2" needstage="acc" datatype="real"
          user="1 2"/>
    <user name="u_none" objtype="body" objname="arm" dim="3" needstage="none" datatype="axis"/>
    <framepos objtype="site" objname="tip"/>
  </sensor>
</mujoco>)";
  diff::Twin twin(file.string(), diff::Path::kLoader);
  REQUIRE(twin.model.nsensordata == 1 + 2 + 1 + 2 + 3 + 3);
  std::mt19937_64 rng(5150);
  // no callback: the user sensors' numbers stay zero, on both sides
  mjcb_sensor = nullptr;
  for (int k = 0; k < 5; ++k) forward_both(twin, random_state(twin.model, rng));
  for (int i = 0; i < twin.model.nsensordata; ++i) {
    CHECK(twin.data.sensordata[i] == twin.d->sensordata[i]);
  }
  CHECK(twin.data.sensordata[1] == 0);
  // with one: the same numbers (cutoff applied after the callback)
  mjcb_sensor = mujoco_user_sensors;
  twin.model.sensor_callback = [](const Model& model, Data& data, SensorStage stage) {
    std::vector<int> type, stage_of;
    for (int s = 0; s < model.nsensor; ++s) {
      type.push_back(static_cast<int>(model.sensor_type[s]));
      stage_of.push_back(static_cast<int>(model.sensor_needstage[s]));
    }
    fill_user_sensors(model.nsensor, type.data(), stage_of.data(), model.sensor_adr.data(),
                      model.sensor_dim.data(), static_cast<int>(stage), data.qpos.data(),
                      data.qvel.data(), data.qacc.data(), data.sensordata.data());
  };
  int clipped = 0;
  for (int k = 0; k < 50; ++k) {
    forward_both(twin, random_state(twin.model, rng));
    for (int i = 0; i < twin.model.nsensordata; ++i) {
      INFO("state " << k << ", sensordata " << i);
      CHECK(std::abs(twin.data.sensordata[i] - twin.d->sensordata[i]) <=
            1e-12 * std::max(1.0, std::abs(twin.d->sensordata[i])));
    }
    clipped += std::abs(twin.data.sensordata[1]) == 4.0;
  }
  mjcb_sensor = nullptr;
  CHECK(clipped > 0);
  // the needstage="none" sensor is never evaluated
  for (int k = 0; k < 3; ++k) CHECK(twin.data.sensordata[6 + k] == 0);
  std::filesystem::remove(file);
}

TEST_CASE("diff: the rangefinder's ray meets meshes where MuJoCo's does", "[diff][sensors]") {
  REQUIRE(mj_version() == 222);
  // the Panda arm's links (lever reads every mesh of a model with a rangefinder, visual ones too,
  // as MuJoCo does) with rangefinders at the world and on the hand looking at them
  std::string xml =
      read_text(robots_dir() + "/menagerie-2022/franka_emika_panda/panda_nohand.xml");
  const auto insert_before = [&xml](const std::string& anchor, const std::string& text) {
    const size_t at = xml.find(anchor);
    REQUIRE(at != std::string::npos);
    xml.insert(at, text);
  };
  insert_before("</worldbody>",
                "<site name=\"eye\" pos=\"0.8 0.3 0.5\" zaxis=\"-1 -0.3 -0.1\"/>"
                "<site name=\"below\" pos=\"0.3 0 0.02\" zaxis=\"0 0 1\"/>");
  insert_before("</mujoco>",
                "<sensor><rangefinder name=\"eye\" site=\"eye\"/>"
                "<rangefinder name=\"below\" site=\"below\"/></sensor>");
  // the file names its meshes relative to itself: the copy sits beside a link to them
  const std::filesystem::path panda =
      std::filesystem::path(robots_dir()) / "menagerie-2022" / "franka_emika_panda";
  const std::filesystem::path copy = std::filesystem::temp_directory_path() / "lever_panda_rays";
  std::filesystem::create_directories(copy);
  std::filesystem::remove_all(copy / "assets");
  std::filesystem::create_directory_symlink(panda / "assets", copy / "assets");
  const std::string path = (copy / "panda_rangefinder.xml").string();
  std::ofstream(path) << xml;

  for (const diff::Path which : {diff::Path::kLoader, diff::Path::kEngine}) {
    diff::Twin twin(path, which);
    INFO(diff::path_name(which) << " path");
    REQUIRE(twin.model.nmeshface > 1000);
    std::mt19937_64 rng(seed_for(path));
    std::uniform_real_distribution<double> u(-1, 1);
    int mesh_hits = 0;
    double worst = 0;
    for (int k = 0; k < 40; ++k) {
      forward_both(twin, random_state(twin.model, rng));
      for (int i = 0; i < twin.model.nsensordata; ++i) {
        worst = std::max(worst, std::abs(twin.data.sensordata[i] - twin.d->sensordata[i]) /
                                    (1e-12 * std::max(1.0, std::abs(twin.d->sensordata[i]))));
      }
      // rays aimed at each mesh geom from around it, against mj_rayMesh
      for (int g = 0; g < twin.model.ngeom; ++g) {
        if (twin.model.geom_type[g] != GeomType::kMesh) continue;
        const Eigen::Vector3d target = twin.data.geom_xpos[g];
        const Eigen::Vector3d pnt = target + 0.4 * Eigen::Vector3d(u(rng), u(rng), u(rng));
        const Eigen::Vector3d vec =
            target - pnt + 0.05 * Eigen::Vector3d(u(rng), u(rng), u(rng));
        const double ours = ray_mesh(twin.model, twin.data, g, pnt, vec);
        const double theirs = mj_rayMesh(twin.m.get(), twin.d.get(), g, pnt.data(), vec.data());
        INFO("state " << k << ", geom " << g);
        REQUIRE((ours < 0) == (theirs < 0));
        worst = std::max(worst, std::abs(ours - theirs) / (1e-12 * std::max(1.0, theirs)));
        mesh_hits += theirs >= 0;
      }
    }
    std::printf("rangefinder on meshes, %s path: %d mesh hits, worst %.3g of the bound\n",
                diff::path_name(which), mesh_hits, worst);
    CHECK(mesh_hits > 200);
    CHECK(worst <= 1.0);
  }
  std::filesystem::remove_all(copy);
}

}  // namespace lever::test
