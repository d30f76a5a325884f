#include "fixture.hpp"

#include <lever/derivatives.hpp>
#include <lever/error.hpp>
#include <lever/forward.hpp>
#include <lever/harness/from_mujoco.hpp>
#include <lever/harness/models.hpp>
#include <lever/mjcf.hpp>
#include <lever/spatial.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>

namespace lever::bench {

namespace {

unsigned long long seed_for(const std::string& name) {  // FNV-1a: a fixed state per model
  unsigned long long h = 1469598103934665603ull;
  for (const unsigned char ch : name) h = (h ^ ch) * 1099511628211ull;
  return h;
}

std::array<double, 9> row_major(const Eigen::Matrix3d& R) {
  std::array<double, 9> out{};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c)
      out[3 * static_cast<std::size_t>(r) + static_cast<std::size_t>(c)] = R(r, c);
  }
  return out;
}

std::array<double, 3> array3(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

}  // namespace

bool is_scene(const Model& model) { return model.nq != model.nv || model.contacts_possible; }

namespace {

// the *.xml files of a directory whose model is (scenes) or is not a contact scene
std::vector<std::string> files_where(const std::string& dir, bool scenes) {
  std::vector<std::string> files;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".xml") continue;
    if (is_scene(mjcf::load_file(entry.path().string())) == scenes)
      files.push_back(entry.path().string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace

// the arms fixed to the world: what the peers (KDL's chains, the step Jacobians) and the speed goals'
// kernel targets are about
std::vector<std::string> model_files(const std::string& dir) { return files_where(dir, false); }

std::vector<std::string> scene_files(const std::string& dir) { return files_where(dir, true); }

std::string robot_scene_file(const std::string& path) {
  // the scenes name the robots folder as it lies beside a checkout; the copy names the one the
  // tests read (lever::test::robots_dir(), which $LEVER_ROBOTS_DIR can move)
  const std::string beside_checkout = "../../../shared/robots";
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  std::string xml = text.str();
  if (xml.find(beside_checkout) == std::string::npos) return path;
  for (std::size_t at = xml.find(beside_checkout); at != std::string::npos;
       at = xml.find(beside_checkout, at)) {
    xml.replace(at, beside_checkout.size(), test::robots_dir());
    at += test::robots_dir().size();
  }
  const std::filesystem::path out_dir =
      std::filesystem::temp_directory_path() / "lever_bench_scenes";
  std::filesystem::create_directories(out_dir);
  const std::filesystem::path copy = out_dir / std::filesystem::path(path).filename();
  std::ofstream(copy) << xml;
  return copy.string();
}

std::vector<std::string> robot_scene_files(const std::string& dir) {
  std::vector<std::string> files;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() == ".xml") files.push_back(robot_scene_file(entry.path().string()));
  }
  std::sort(files.begin(), files.end());
  return files;
}

State random_state(const Model& model, unsigned long long seed) {
  std::mt19937_64 rng(seed);
  auto uniform = [&](double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
  };
  State s;
  s.qpos = model.qpos0;
  for (int j = 0; j < model.njnt; ++j) {
    const int adr = model.jnt_qposadr[j];
    if (model.jnt_limited[j]) {
      const double lo = model.jnt_range[j][0], hi = model.jnt_range[j][1];
      const double mid = 0.5 * (lo + hi), half = 0.3 * (hi - lo);
      s.qpos[adr] = uniform(mid - half, mid + half);
    } else {
      s.qpos[adr] = model.qpos0[adr] + uniform(-1.0, 1.0);
    }
  }
  s.qvel.resize(model.nv);
  s.qacc.resize(model.nv);
  for (int i = 0; i < model.nv; ++i) {
    s.qvel[i] = uniform(-1.0, 1.0);
    s.qacc[i] = uniform(-1.0, 1.0);
  }
  s.ctrl.resize(model.nu);
  for (int a = 0; a < model.nu; ++a) {
    const auto r =
        model.actuator_ctrllimited[a] ? model.actuator_ctrlrange[a] : std::array<double, 2>{-1, 1};
    const double mid = 0.5 * (r[0] + r[1]), half = 0.25 * (r[1] - r[0]);
    s.ctrl[a] = uniform(mid - half, mid + half);
  }
  return s;
}

namespace {

// A rigid transform: x_parent = R x_child + p.
struct Pose {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Pose operator*(const Pose& b) const { return {R * b.R, R * b.p + p}; }
};

Pose pose(const Eigen::Vector4d& quat, const Eigen::Vector3d& pos) {
  return {quat_to_mat(quat), pos};
}
Pose shift(const Eigen::Vector3d& pos) { return {Eigen::Matrix3d::Identity(), pos}; }

}  // namespace

// Built from the model's MuJoCo-named parameters only (body_pos, body_quat, jnt_pos, jnt_axis,
// body_ipos, ...), the way mj_kinematics reads them: a hinge turns its body about the axis
// through its anchor by qpos - qpos0; a slide moves it along the axis. Link j's frame has its
// body's orientation (before joint j moves) and its origin on joint j's anchor.
ChainSpec chain_spec(const Model& model, int site) {
  if (model.njnt == 0) throw std::invalid_argument("no joints");
  if (model.nq != model.nv || model.njnt != model.nv)
    throw std::invalid_argument("not one dof per joint");
  for (int i = 0; i < model.nv; ++i) {
    if (model.dof_parentid[i] != i - 1) {
      throw std::invalid_argument("not a serial chain (dof " + std::to_string(i) + "'s parent is " +
                                  std::to_string(model.dof_parentid[i]) + ")");
    }
  }
  // owner[b]: the last joint that moves body b (-1: welded to the world); at[b]: b's frame in
  // the moved frame of that joint's link (in the world's for owner -1)
  const auto nbody = static_cast<std::size_t>(model.nbody);
  std::vector<int> owner(nbody, -1);
  std::vector<Pose> at(nbody);
  // link_tree[j]: link j's frame at zero displacement, in the previous link's moved frame
  std::vector<Pose> link_tree(static_cast<std::size_t>(model.njnt));
  for (int b = 1; b < model.nbody; ++b) {
    const auto ub = static_cast<std::size_t>(b);
    const auto parent = static_cast<std::size_t>(model.body_parentid[ub]);
    Pose body = at[parent] * pose(model.body_quat[ub], model.body_pos[ub]);  // before b's joints
    owner[ub] = owner[parent];
    for (int k = 0; k < model.body_jntnum[ub]; ++k) {
      const int j = model.body_jntadr[ub] + k;
      const auto uj = static_cast<std::size_t>(j);
      if (owner[ub] != j - 1) throw std::invalid_argument("joints out of chain order");
      link_tree[uj] = body * shift(model.jnt_pos[uj]);
      body = shift(-model.jnt_pos[uj]);  // the body in link j's moved frame
      owner[ub] = j;
    }
    at[ub] = body;
  }

  ChainSpec spec;
  spec.gravity = array3(model.opt.gravity);
  for (int j = 0; j < model.njnt; ++j) {
    const auto uj = static_cast<std::size_t>(j);
    ChainSpec::Link link;
    link.prismatic = model.jnt_type[uj] == JointType::kSlide;
    link.axis = array3(model.jnt_axis[uj].normalized());
    link.offset = model.qpos0[model.jnt_qposadr[uj]];
    link.armature = model.dof_armature[static_cast<std::size_t>(model.jnt_dofadr[uj])];
    link.tree_pos = array3(link_tree[uj].p);
    link.tree_rot = row_major(link_tree[uj].R);
    // every body the link carries, in the link's frame, summed about its origin
    RigidInertia sum;
    for (int b = 1; b < model.nbody; ++b) {
      const auto ub = static_cast<std::size_t>(b);
      if (owner[ub] != j) continue;
      const Pose& P = at[ub];
      const Eigen::Matrix3d Ri = P.R * quat_to_mat(model.body_iquat[ub]);
      const Eigen::Matrix3d Ic = Ri * model.body_inertia[ub].asDiagonal() * Ri.transpose();
      sum += RigidInertia::from_com(model.body_mass[ub], P.R * model.body_ipos[ub] + P.p, Ic);
    }
    link.mass = sum.m;
    const Eigen::Vector3d c = sum.m > 0 ? Eigen::Vector3d(sum.h / sum.m) : Eigen::Vector3d::Zero();
    const Eigen::Matrix3d shift_back =
        sum.m * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
    link.com = array3(c);
    link.inertia_com =
        row_major(sum.I - shift_back);  // I about the origin = Ic + m (|c|^2 1 - c c^T)
    spec.links.push_back(link);
  }
  if (site >= 0) {
    const auto us = static_cast<std::size_t>(site);
    const auto b = static_cast<std::size_t>(model.site_bodyid[us]);
    if (owner[b] != model.njnt - 1) {
      throw std::invalid_argument("site '" + model.site_name[us] + "' is not on the last link");
    }
    const Pose tip = at[b] * pose(model.site_quat[us], model.site_pos[us]);
    spec.tip_pos = array3(tip.p);
    spec.tip_rot = row_major(tip.R);
  }
  return spec;
}

void set_mujoco_state(const mjModel* m, mjData* d, const State& s) {
  mju_copy(d->qpos, s.qpos.data(), m->nq);
  mju_copy(d->qvel, s.qvel.data(), m->nv);
  mju_copy(d->qacc, s.qacc.data(), m->nv);
  if (m->nu > 0) mju_copy(d->ctrl, s.ctrl.data(), m->nu);
}

MjDataPtr mujoco_data(const Fixture& f, const State& s) {
  MjDataPtr d(mj_makeData(f.mj.get()), mj_deleteData);
  set_mujoco_state(f.mj.get(), d.get(), s);
  return d;
}

namespace {

// A fixture named after its file, with MuJoCo's compiled model of it (every peer's first step).
std::unique_ptr<Fixture> fixture_loaded_by_mujoco(const std::string& path) {
  auto f = std::make_unique<Fixture>();
  f->path = path;
  f->name = std::filesystem::path(path).stem().string();
  char error[1000] = "";
  mjModel* m = mj_loadXML(path.c_str(), nullptr, error, sizeof error);
  if (m == nullptr) throw std::runtime_error("MuJoCo could not load " + path + ": " + error);
  f->mj = MjModelPtr(m, mj_deleteModel);
  return f;
}

}  // namespace

std::unique_ptr<Fixture> make_fixture(const std::string& path) {
  auto f = fixture_loaded_by_mujoco(path);
  const mjModel* m = f->mj.get();

  // lever's model through its own parser; MuJoCo's compiled numbers if the parser refuses it
  try {
    f->model = mjcf::load_file(path);
    f->loader = "mjcf_lite";
  } catch (const Error&) {
    f->model = test::from_mujoco(m);
    f->loader = "from_mujoco";
  }

  const Model& model = f->model;
  f->site = model.site("ee");
  if (f->site < 0) f->site = model.nsite - 1;

  f->state = random_state(model, seed_for(f->name));
  for (int j = 0; j < model.njnt && f->limit_joint < 0; ++j) {
    if (model.jnt_limited[j]) f->limit_joint = j;
  }
  if (f->limit_joint >= 0) {
    State s = f->state;
    s.qpos[model.jnt_qposadr[f->limit_joint]] = model.jnt_range[f->limit_joint][0] - 1e-3;
    f->limit = s;
  }

  try {
    f->chain = chain_spec(model, f->site);
  } catch (const std::invalid_argument& e) {
    f->kdl_note = e.what();
  }
  return f;
}

std::unique_ptr<Fixture> make_scene_fixture(const std::string& path) {
  auto f = fixture_loaded_by_mujoco(path);
  f->scene = true;
  f->model = mjcf::load_file(path);
  f->loader = "mjcf_lite";

  const Model& model = f->model;
  Data d(model);
  if (model.nkey > 0) reset_keyframe(model, d, 0);
  d.ctrl.setZero();
  const int steps = static_cast<int>(std::lround(1.0 / model.opt.timestep));
  for (int k = 0; k < steps; ++k) step(model, d);
  forward(model, d);
  if (d.ncon == 0) throw std::runtime_error(path + ": no contact after one second at rest");
  f->ncon = d.ncon;
  f->state = {d.qpos, d.qvel, d.qacc, d.ctrl};
  // the step's Jacobians are timed where lever's derivatives cover the scene's contacts (a pair
  // they do not, a round geom against a mesh say, is refused by name)
  try {
    Derivatives deriv(model);
    Data probe(model);
    probe.qpos = d.qpos;
    probe.qvel = d.qvel;
    probe.ctrl = d.ctrl;
    step_derivatives(model, probe, deriv);
    f->differentiable = true;
  } catch (const Error&) {
    f->differentiable = false;
  }
  f->site = model.site("ee");  // the site Jacobian's, as for the arms
  if (f->site < 0) f->site = model.nsite - 1;
  return f;
}

bool is_sensor_model(const Model& model) {
  return model.nsensor > 0 && !model.contacts_possible;
}

std::unique_ptr<Fixture> make_sensor_fixture(const std::string& path) {
  auto f = fixture_loaded_by_mujoco(path);
  f->sensors = true;
  f->model = mjcf::load_file(path);
  f->loader = "mjcf_lite";
  const Model& model = f->model;
  if (!is_sensor_model(model) || model.nkey == 0) {
    throw std::runtime_error(path + ": the sensor benchmark needs sensors, a keyframe and no contact");
  }
  Data d(model);
  reset_keyframe(model, d, 0);
  f->state = {d.qpos, d.qvel, Eigen::VectorXd::Zero(model.nv), d.ctrl};
  f->site = model.nsite - 1;
  return f;
}

}  // namespace lever::bench
