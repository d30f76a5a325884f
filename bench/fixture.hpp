// One model for every peer: lever's Model, MuJoCo's mjModel and (for a serial chain) the KDL
// chain, with the state every peer is timed on.
#pragma once

#include <mujoco/mujoco.h>

#include <Eigen/Core>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <lever/model.hpp>

#include "kdl_peer.hpp"

namespace lever::bench {

using MjModelPtr = std::unique_ptr<mjModel, void (*)(mjModel*)>;
using MjDataPtr = std::unique_ptr<mjData, void (*)(mjData*)>;

/// A state: what forward() reads, plus the acceleration inverse dynamics is given.
struct State {
  Eigen::VectorXd qpos, qvel, qacc, ctrl;
};

struct Fixture {
  std::string name;  ///< the file's stem: "arm2"
  std::string path;
  std::string loader;  ///< how lever's model was made: "mjcf_lite" or "from_mujoco"
  Model model;
  MjModelPtr mj{nullptr, mj_deleteModel};
  int site =
      -1;  ///< the site of the Jacobian, the FK tip and the KDL chain's tip ("ee", else the last)

  State state;                 ///< no joint near a stop: no limit row
  std::optional<State> limit;  ///< the same, with one joint 1 mrad past its lower stop
  int limit_joint = -1;        ///< that joint (the first limited one: the shoulder)

  std::optional<ChainSpec> chain;  ///< KDL's chain, when the model is a serial chain
  std::string kdl_note;            ///< why there is no chain, if there is none

  bool scene = false;  ///< a contact scene (free bodies, contacts): timed on forward and step only
  int ncon = 0;        ///< a scene's contacts in its timed state
  bool differentiable = true;  ///< lever's step derivatives cover it (a scene's contacts)
  bool sensors = false;  ///< the sensor model: timed on forward only, every sensor evaluated
};

/// The *.xml files in a directory, as paths: the arms fixed to the world (every operation is
/// timed on them).
std::vector<std::string> model_files(const std::string& dir);

/// A contact scene: free bodies or contacts possible (lesson 5.3's models).
bool is_scene(const Model& model);

/// The contact scenes of a directory (lesson 5.3's models: free bodies, contacts possible).
std::vector<std::string> scene_files(const std::string& dir);

/// The contact scenes of a directory that read real model files from ../shared/robots beside the
/// checkout (bench/scenes: the mesh gripper, MuJoCo Menagerie's Panda hand), each copied to a
/// temporary folder with that folder replaced by lever::test::robots_dir(): the copies' paths.
std::vector<std::string> robot_scene_files(const std::string& dir);

/// One such scene's copy (as robot_scene_files makes it), or the path itself when the file does
/// not name ../shared/robots beside the checkout.
std::string robot_scene_file(const std::string& path);

/// A contact scene timed where the lesson uses it, at rest in contact: its first keyframe (else
/// qpos0), ctrl 0, then one second of lever's steps, so that its bodies lie on each other.
/// Throws std::runtime_error if MuJoCo cannot load it or the scene has no contact then.
std::unique_ptr<Fixture> make_scene_fixture(const std::string& path);

/// A model with sensors and no contact (tests/models/sensors.xml): its first keyframe's state,
/// where its sensors read something (a moving arm, a swinging ball, a spinning free body).
/// Throws std::runtime_error if MuJoCo cannot load it, or it has no sensors or no keyframe.
std::unique_ptr<Fixture> make_sensor_fixture(const std::string& path);

/// Whether lever_bench_profile times a model as the sensor model: sensors, and no contacts.
bool is_sensor_model(const Model& model);

/// Load a model for every peer and draw its state (seeded by the model's name).
/// Throws std::runtime_error if MuJoCo cannot load it.
std::unique_ptr<Fixture> make_fixture(const std::string& path);

/// A random state with every limited joint well inside its range (the middle 60%), qvel and
/// qacc in [-1, 1], ctrl in the middle half of each ctrlrange.
State random_state(const Model& model, unsigned long long seed);

/// The KDL description of a serial chain (link i's parent is link i-1), its tip on `site`
/// (which must hang from the last link). Throws std::invalid_argument otherwise.
ChainSpec chain_spec(const Model& model, int site);

/// A fresh mjData for the fixture's model, holding `s`.
MjDataPtr mujoco_data(const Fixture& f, const State& s);

/// Copy a state into MuJoCo's mjData (qpos, qvel, qacc, ctrl).
void set_mujoco_state(const mjModel* m, mjData* d, const State& s);

}  // namespace lever::bench
