// The sensor stages (MuJoCo 2.2.2's engine_sensor.c): after each stage of forward(), the
// sensors that stage can evaluate (sensor_needstage) write their numbers at sensor_adr in
// data.sensordata (user sensors by the model's sensor_callback, MuJoCo's mjcb_sensor); then, with
// <flag sensornoise="enable">, each gets its noise, and last each is clipped at its cutoff.
#include <cmath>

#include "basics/basics.hpp"
#include "sensors/sensors.hpp"

namespace lever {

const char* sensor_type_name(SensorType type) {
  static constexpr const char* names[] = {
      "touch",          "accelerometer",  "velocimeter",    "gyro",          "force",
      "torque",         "magnetometer",   "rangefinder",    "jointpos",      "jointvel",
      "tendonpos",      "tendonvel",      "actuatorpos",    "actuatorvel",   "actuatorfrc",
      "ballquat",       "ballangvel",     "jointlimitpos",  "jointlimitvel", "jointlimitfrc",
      "tendonlimitpos", "tendonlimitvel", "tendonlimitfrc", "framepos",      "framequat",
      "framexaxis",     "frameyaxis",     "framezaxis",     "framelinvel",   "frameangvel",
      "framelinacc",    "frameangacc",    "subtreecom",     "subtreelinvel", "subtreeangmom",
      "clock",          "user"};
  const int i = static_cast<int>(type);
  return i >= 0 && i < static_cast<int>(std::size(names)) ? names[i] : "unknown";
}

SensorLayout sensor_layout(SensorType type) {
  using T = SensorType;
  using D = SensorDataType;
  using S = SensorStage;
  using O = ObjectType;
  switch (type) {
    case T::kTouch: return {1, D::kPositive, S::kAcceleration, O::kSite};
    case T::kAccelerometer:
    case T::kForce:
    case T::kTorque: return {3, D::kReal, S::kAcceleration, O::kSite};
    case T::kVelocimeter:
    case T::kGyro: return {3, D::kReal, S::kVelocity, O::kSite};
    case T::kMagnetometer: return {3, D::kReal, S::kPosition, O::kSite};
    case T::kRangefinder: return {1, D::kPositive, S::kPosition, O::kSite};
    case T::kJointPos:
    case T::kJointLimitPos: return {1, D::kReal, S::kPosition, O::kJoint};
    case T::kJointVel:
    case T::kJointLimitVel: return {1, D::kReal, S::kVelocity, O::kJoint};
    case T::kJointLimitFrc: return {1, D::kReal, S::kAcceleration, O::kJoint};
    case T::kTendonPos:
    case T::kTendonLimitPos: return {1, D::kReal, S::kPosition, O::kTendon};
    case T::kTendonVel:
    case T::kTendonLimitVel: return {1, D::kReal, S::kVelocity, O::kTendon};
    case T::kTendonLimitFrc: return {1, D::kReal, S::kAcceleration, O::kTendon};
    case T::kActuatorPos: return {1, D::kReal, S::kPosition, O::kActuator};
    case T::kActuatorVel: return {1, D::kReal, S::kVelocity, O::kActuator};
    case T::kActuatorFrc: return {1, D::kReal, S::kAcceleration, O::kActuator};
    case T::kBallQuat: return {4, D::kQuaternion, S::kPosition, O::kJoint};
    case T::kBallAngVel: return {3, D::kReal, S::kVelocity, O::kJoint};
    case T::kFramePos: return {3, D::kReal, S::kPosition, O::kXBody};
    case T::kFrameQuat: return {4, D::kQuaternion, S::kPosition, O::kXBody};
    case T::kFrameXAxis:
    case T::kFrameYAxis:
    case T::kFrameZAxis: return {3, D::kAxis, S::kPosition, O::kXBody};
    case T::kFrameLinVel:
    case T::kFrameAngVel: return {3, D::kReal, S::kVelocity, O::kXBody};
    case T::kFrameLinAcc:
    case T::kFrameAngAcc: return {3, D::kReal, S::kAcceleration, O::kXBody};
    case T::kSubtreeCom: return {3, D::kReal, S::kPosition, O::kBody};
    case T::kSubtreeLinVel:
    case T::kSubtreeAngMom: return {3, D::kReal, S::kVelocity, O::kBody};
    case T::kClock: return {1, D::kReal, S::kPosition, O::kUnknown};
    case T::kUser: break;
  }
  return {0, D::kReal, S::kAcceleration, O::kUnknown};
}

bool sensor_type_supported(SensorType type) {
  const int t = static_cast<int>(type);
  return t >= 0 && t <= static_cast<int>(SensorType::kUser);
}

namespace {

using Eigen::Vector3d;

// ---- frames: where an object is, and how it moves ------------------------------------------------

// An object's frame: a body's inertial frame (kBody) or its own (kXBody), a geom's, a site's.
struct Frame {
  const Vector3d* pos;
  const Mat3* R;
  int body;
};

Frame frame_of(const Model& model, const Data& data, ObjectType type, int id) {
  switch (type) {
    case ObjectType::kBody: return {&data.xipos[id], &data.ximat[id], id};
    case ObjectType::kXBody: return {&data.xpos[id], &data.xmat[id], id};
    case ObjectType::kGeom: return {&data.geom_xpos[id], &data.geom_xmat[id], model.geom_bodyid[id]};
    default: return {&data.site_xpos[id], &data.site_xmat[id], model.site_bodyid[id]};
  }
}

// Its orientation as a quaternion: the body's, turned by the object's constant rotation on it.
Quat quat_of(const Model& model, const Data& data, ObjectType type, int id) {
  switch (type) {
    case ObjectType::kBody: return quat_mul(data.xquat[id], model.body_iquat[id]);
    case ObjectType::kXBody: return data.xquat[id];
    case ObjectType::kGeom: return quat_mul(data.xquat[model.geom_bodyid[id]], model.geom_quat[id]);
    default: return quat_mul(data.xquat[model.site_bodyid[id]], model.site_quat[id]);
  }
}

// A c-frame motion (cvel, cacc) of the frame's body as seen at the frame's origin: the linear
// part gains w x (origin - centre); in world axes, or in the frame's own with `local`.
Motion motion_at(const Model& model, const Data& data, const Motion& v, const Frame& f,
                 bool local) {
  const Vector3d offset = *f.pos - data.subtree_com[model.body_rootid[f.body]];
  Motion out;
  out.head<3>() = v.head<3>();
  out.tail<3>() = v.tail<3>() - cross(offset, v.head<3>());
  if (local) {
    out.head<3>() = rotate_back(*f.R, Vector3d(out.head<3>()));
    out.tail<3>() = rotate_back(*f.R, Vector3d(out.tail<3>()));
  }
  return out;
}

// The object's velocity [angular; linear] (MuJoCo's mj_objectVelocity).
Motion velocity_of(const Model& model, const Data& data, const Frame& f, bool local) {
  return motion_at(model, data, data.cvel[f.body], f, local);
}

// Its acceleration [angular; linear] (mj_objectAcceleration): cacc moved to the origin, plus
// w x v, since a point's acceleration is not the spatial acceleration's linear part.
Motion acceleration_of(const Model& model, const Data& data, const Frame& f, bool local) {
  const Motion v = motion_at(model, data, data.cvel[f.body], f, local);
  Motion a = motion_at(model, data, data.cacc[f.body], f, local);
  a.tail<3>() += cross(v.head<3>(), v.tail<3>());
  return a;
}

void put3(double* out, const Vector3d& v) {
  out[0] = v[0];
  out[1] = v[1];
  out[2] = v[2];
}

// The first limit row of joint (tendon) j and what `pick` takes from it, or 0 when it is within
// its range (no row); `kind` is kLimitJoint or kLimitTendon.
template <class Pick>
double limit_value(const Data& data, ConstraintType kind, int j, Pick pick) {
  for (int r = 0; r < data.nefc; ++r) {
    if (data.efc_type[r] == kind && data.efc_id[r] == j) return pick(r);
  }
  return 0.0;
}

// The limit rows a limit sensor reads: a joint's or a tendon's.
ConstraintType limit_kind(SensorType type) {
  const bool tendon = type == SensorType::kTendonLimitPos || type == SensorType::kTendonLimitVel ||
                      type == SensorType::kTendonLimitFrc;
  return tendon ? ConstraintType::kLimitTendon : ConstraintType::kLimitJoint;
}

// ---- noise and cutoff ------------------------------------------------------------------------

// One draw of splitmix64, the Data's own generator (so runs repeat and Data share nothing).
std::uint64_t next_random(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

// Uniform in [-1, 1].
double uniform_symmetric(std::uint64_t& state) {
  return 2.0 * (static_cast<double>(next_random(state) >> 11) * 0x1.0p-53) - 1.0;
}

// Two independent standard normal numbers, by Marsaglia's polar method (MuJoCo's
// mju_standardNormal draws them the same way from the C library's rand()).
void standard_normal_pair(std::uint64_t& state, double& first, double& second) {
  double x, y, w;
  do {
    x = uniform_symmetric(state);
    y = uniform_symmetric(state);
    w = x * x + y * y;
  } while (w >= 1.0 || w == 0.0);
  const double scale = std::sqrt(-2.0 * std::log(w) / w);
  first = x * scale;
  second = y * scale;
}

// MuJoCo's add_noise: a real number gets noise * N(0, 1); a positive one too, kept >= 0, and
// only where it is positive (a touch sensor that feels nothing stays at 0); an axis or a
// quaternion is turned by an angle noise * N(0, 1) about a random axis.
void add_noise(const Model& model, Data& data, SensorStage stage) {
  for (int s = 0; s < model.nsensor; ++s) {
    if (model.sensor_needstage[s] != stage || !(model.sensor_noise[s] > 0)) continue;
    const double noise = model.sensor_noise[s];
    double* x = data.sensordata.data() + model.sensor_adr[s];
    const SensorDataType type = model.sensor_datatype[s];
    if (type == SensorDataType::kReal || type == SensorDataType::kPositive) {
      for (int k = 0; k < model.sensor_dim[s]; ++k) {
        double n, unused;
        standard_normal_pair(data.sensor_noise_state, n, unused);  // one of each pair, as MuJoCo
        if (type == SensorDataType::kReal) {
          x[k] += n * noise;
        } else if (x[k] > 0) {
          x[k] = std::max(0.0, x[k] + n * noise);
        }
      }
      continue;
    }
    double angle, a0, a1, a2;
    standard_normal_pair(data.sensor_noise_state, angle, a0);
    standard_normal_pair(data.sensor_noise_state, a1, a2);
    Vector3d axis(a0, a1, a2);
    const double length = axis.norm();
    axis = length < detail::kMinVal ? Vector3d(1, 0, 0) : Vector3d(axis / length);
    const Quat turn = quat_from_axis_angle(axis, angle * noise);
    if (type == SensorDataType::kAxis) {
      put3(x, quat_to_mat(turn) * Vector3d(x[0], x[1], x[2]));
    } else {
      const Quat q = quat_mul(Quat(x[0], x[1], x[2], x[3]), turn);
      for (int k = 0; k < 4; ++k) x[k] = q[k];
    }
  }
}

// MuJoCo's apply_cutoff: a real number clipped to [-cutoff, cutoff], a positive one to cutoff.
void apply_cutoff(const Model& model, Data& data, SensorStage stage) {
  for (int s = 0; s < model.nsensor; ++s) {
    if (model.sensor_needstage[s] != stage || !(model.sensor_cutoff[s] > 0)) continue;
    const double cutoff = model.sensor_cutoff[s];
    double* x = data.sensordata.data() + model.sensor_adr[s];
    for (int k = 0; k < model.sensor_dim[s]; ++k) {
      if (model.sensor_datatype[s] == SensorDataType::kReal) {
        x[k] = std::min(cutoff, std::max(-cutoff, x[k]));
      } else if (model.sensor_datatype[s] == SensorDataType::kPositive) {
        x[k] = std::min(cutoff, x[k]);
      }
    }
  }
}

// The user sensors of this stage, by the model's callback (MuJoCo's mjcb_sensor): without one,
// their numbers stay what they were.
void evaluate_user_sensors(const Model& model, Data& data, SensorStage stage) {
  if (!model.sensor_callback) return;
  for (int s = 0; s < model.nsensor; ++s) {
    if (model.sensor_type[s] == SensorType::kUser && model.sensor_needstage[s] == stage) {
      model.sensor_callback(model, data, stage);
      return;
    }
  }
}

void finish_stage(const Model& model, Data& data, SensorStage stage) {
  if (model.opt.enabled(kEnableSensornoise)) add_noise(model, data, stage);
  apply_cutoff(model, data, stage);
}

// ---- the frame sensors ---------------------------------------------------------------------------

// framepos and the axes: in world coordinates, or relative to the reference frame, in its axes.
void frame_position(const Model& model, const Data& data, int s, double* out) {
  const Frame f = frame_of(model, data, model.sensor_objtype[s], model.sensor_objid[s]);
  const SensorType type = model.sensor_type[s];
  Vector3d v = type == SensorType::kFramePos
                   ? *f.pos
                   : Vector3d(f.R->col(static_cast<int>(type) -
                                       static_cast<int>(SensorType::kFrameXAxis)));
  if (model.sensor_refid[s] >= 0) {
    const Frame ref = frame_of(model, data, model.sensor_reftype[s], model.sensor_refid[s]);
    if (type == SensorType::kFramePos) v -= *ref.pos;
    v = rotate_back(*ref.R, v);
  }
  put3(out, v);
}

void frame_quat(const Model& model, const Data& data, int s, double* out) {
  Quat q = quat_of(model, data, model.sensor_objtype[s], model.sensor_objid[s]);
  if (model.sensor_refid[s] >= 0) {
    const Quat ref = quat_of(model, data, model.sensor_reftype[s], model.sensor_refid[s]);
    q = quat_mul(Quat(ref[0], -ref[1], -ref[2], -ref[3]), q);
  }
  for (int k = 0; k < 4; ++k) out[k] = q[k];
}

// framelinvel and frameangvel: in world axes, or relative to the reference frame (its own
// velocity taken away, the linear part corrected for its turning), in its axes.
void frame_velocity(const Model& model, const Data& data, int s, double* out) {
  const Frame f = frame_of(model, data, model.sensor_objtype[s], model.sensor_objid[s]);
  Motion v = velocity_of(model, data, f, false);
  if (model.sensor_refid[s] >= 0) {
    const Frame ref = frame_of(model, data, model.sensor_reftype[s], model.sensor_refid[s]);
    const Motion vr = velocity_of(model, data, ref, false);
    Motion relative = v - vr;
    relative.tail<3>() += cross(*f.pos - *ref.pos, vr.head<3>());
    v.head<3>() = rotate_back(*ref.R, Vector3d(relative.head<3>()));
    v.tail<3>() = rotate_back(*ref.R, Vector3d(relative.tail<3>()));
  }
  put3(out, model.sensor_type[s] == SensorType::kFrameLinVel ? Vector3d(v.tail<3>())
                                                              : Vector3d(v.head<3>()));
}

// ---- touch --------------------------------------------------------------------------------------

// The normal forces of the contacts of the site's body whose force, drawn as a ray from the
// contact point into the body, crosses the site's volume (MuJoCo's touch sensor).
double touch(const Model& model, const Data& data, int site) {
  const int body = model.site_bodyid[site];
  double total = 0;
  for (int i = 0; i < data.ncon; ++i) {
    const Contact& c = data.contact[i];
    const int body1 = model.geom_bodyid[c.geom1], body2 = model.geom_bodyid[c.geom2];
    if (c.efc_address < 0 || (body != body1 && body != body2)) continue;
    // the normal force: every pyramid edge pushes along the normal; else the first row
    double normal = 0;
    const double* f = data.efc_force.data() + c.efc_address;
    if (data.efc_type[c.efc_address] == ConstraintType::kContactPyramidal) {
      for (int k = 0; k < 2 * (c.dim - 1); ++k) normal += f[k];
    } else {
      normal = f[0];
    }
    if (normal <= 0) continue;
    // the normal points from geom1 into geom2: into the body when the site's body is geom2's...
    Vector3d direction = c.frame.row(0).transpose() * normal;
    direction.normalize();
    if (body == body2) direction = -direction;  // ... so the ray is turned for geom2's body
    if (ray_shape(data.site_xpos[site], data.site_xmat[site], model.site_size[site], c.pos,
                  direction, model.site_type[site]) >= 0) {
      total += normal;
    }
  }
  return total;
}

}  // namespace

// ---- the stages ---------------------------------------------------------------------------------

void sensor_position(const Model& model, Data& data) {
  if (model.nsensor == 0 || model.opt.disabled(kDisableSensor)) return;
  for (int s = 0; s < model.nsensor; ++s) {
    if (model.sensor_needstage[s] != SensorStage::kPosition) continue;
    const int id = model.sensor_objid[s];
    double* out = data.sensordata.data() + model.sensor_adr[s];
    switch (model.sensor_type[s]) {
      case SensorType::kMagnetometer:
        put3(out, rotate_back(data.site_xmat[id], model.opt.magnetic));
        break;
      case SensorType::kRangefinder: {
        int geom = -1;
        out[0] = ray(model, data, data.site_xpos[id], Vector3d(data.site_xmat[id].col(2)),
                     model.site_bodyid[id], &geom);
        break;
      }
      case SensorType::kJointPos: out[0] = data.qpos[model.jnt_qposadr[id]]; break;
      case SensorType::kActuatorPos: out[0] = data.actuator_length[id]; break;
      case SensorType::kBallQuat:
        for (int k = 0; k < 4; ++k) out[k] = data.qpos[model.jnt_qposadr[id] + k];
        break;
      case SensorType::kJointLimitPos:
      case SensorType::kTendonLimitPos:
        out[0] = limit_value(data, limit_kind(model.sensor_type[s]), id,
                             [&](int r) { return data.efc_pos[r] - data.efc_margin[r]; });
        break;
      case SensorType::kTendonPos: out[0] = data.ten_length[id]; break;
      case SensorType::kFramePos:
      case SensorType::kFrameXAxis:
      case SensorType::kFrameYAxis:
      case SensorType::kFrameZAxis: frame_position(model, data, s, out); break;
      case SensorType::kFrameQuat: frame_quat(model, data, s, out); break;
      case SensorType::kSubtreeCom: put3(out, data.subtree_com[id]); break;
      case SensorType::kClock: out[0] = data.time; break;
      default: break;  // validate() admits no other type at this stage
    }
  }
  evaluate_user_sensors(model, data, SensorStage::kPosition);
  finish_stage(model, data, SensorStage::kPosition);
}

void sensor_velocity(const Model& model, Data& data) {
  if (model.nsensor == 0 || model.opt.disabled(kDisableSensor)) return;
  bool subtrees_done = false;
  for (int s = 0; s < model.nsensor; ++s) {
    if (model.sensor_needstage[s] != SensorStage::kVelocity) continue;
    const SensorType type = model.sensor_type[s];
    const int id = model.sensor_objid[s];
    double* out = data.sensordata.data() + model.sensor_adr[s];
    if (!subtrees_done &&
        (type == SensorType::kSubtreeLinVel || type == SensorType::kSubtreeAngMom)) {
      subtree_velocities(model, data);
      subtrees_done = true;
    }
    switch (type) {
      case SensorType::kVelocimeter:
      case SensorType::kGyro: {
        const Motion v =
            velocity_of(model, data, frame_of(model, data, ObjectType::kSite, id), true);
        put3(out, type == SensorType::kGyro ? Vector3d(v.head<3>()) : Vector3d(v.tail<3>()));
        break;
      }
      case SensorType::kJointVel: out[0] = data.qvel[model.jnt_dofadr[id]]; break;
      case SensorType::kActuatorVel: out[0] = data.actuator_velocity[id]; break;
      case SensorType::kBallAngVel:
        for (int k = 0; k < 3; ++k) out[k] = data.qvel[model.jnt_dofadr[id] + k];
        break;
      case SensorType::kJointLimitVel:
      case SensorType::kTendonLimitVel:
        out[0] = limit_value(data, limit_kind(type), id, [&](int r) { return data.efc_vel[r]; });
        break;
      case SensorType::kTendonVel: out[0] = data.ten_velocity[id]; break;
      case SensorType::kFrameLinVel:
      case SensorType::kFrameAngVel: frame_velocity(model, data, s, out); break;
      case SensorType::kSubtreeLinVel: put3(out, data.subtree_linvel[id]); break;
      case SensorType::kSubtreeAngMom: put3(out, data.subtree_angmom[id]); break;
      default: break;
    }
  }
  evaluate_user_sensors(model, data, SensorStage::kVelocity);
  finish_stage(model, data, SensorStage::kVelocity);
}

void sensor_acceleration(const Model& model, Data& data) {
  if (model.nsensor == 0 || model.opt.disabled(kDisableSensor)) return;
  bool forces_done = false;
  for (int s = 0; s < model.nsensor; ++s) {
    if (model.sensor_needstage[s] != SensorStage::kAcceleration) continue;
    const SensorType type = model.sensor_type[s];
    const int id = model.sensor_objid[s];
    double* out = data.sensordata.data() + model.sensor_adr[s];
    // the forces inside the tree, once, for the first sensor that reads them
    const bool reads_forces = type != SensorType::kTouch && type != SensorType::kActuatorFrc &&
                              type != SensorType::kJointLimitFrc &&
                              type != SensorType::kTendonLimitFrc;
    if (reads_forces && !forces_done) {
      rne_post_constraint(model, data);
      forces_done = true;
    }
    switch (type) {
      case SensorType::kTouch: out[0] = touch(model, data, id); break;
      case SensorType::kAccelerometer: {
        const Motion a =
            acceleration_of(model, data, frame_of(model, data, ObjectType::kSite, id), true);
        put3(out, a.tail<3>());
        break;
      }
      case SensorType::kForce:
      case SensorType::kTorque: {
        // what the parent exerts on the subtree, about the site, in the site's axes
        const int body = model.site_bodyid[id];
        const Force f = data.cfrc_int[body];
        const Vector3d moved = f.head<3>() - cross(data.site_xpos[id] -
                                                       data.subtree_com[model.body_rootid[body]],
                                                   f.tail<3>());
        put3(out, rotate_back(data.site_xmat[id],
                              type == SensorType::kTorque ? moved : Vector3d(f.tail<3>())));
        break;
      }
      case SensorType::kActuatorFrc: out[0] = data.actuator_force[id]; break;
      case SensorType::kJointLimitFrc:
      case SensorType::kTendonLimitFrc:
        out[0] = limit_value(data, limit_kind(type), id, [&](int r) { return data.efc_force[r]; });
        break;
      case SensorType::kFrameLinAcc:
      case SensorType::kFrameAngAcc: {
        const Motion a = acceleration_of(
            model, data,
            frame_of(model, data, model.sensor_objtype[s], model.sensor_objid[s]), false);
        put3(out, type == SensorType::kFrameLinAcc ? Vector3d(a.tail<3>())
                                                   : Vector3d(a.head<3>()));
        break;
      }
      default: break;
    }
  }
  evaluate_user_sensors(model, data, SensorStage::kAcceleration);
  finish_stage(model, data, SensorStage::kAcceleration);
}

}  // namespace lever
