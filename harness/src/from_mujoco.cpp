#include <lever/harness/from_mujoco.hpp>

#include <lever/fields.hpp>

#include <array>
#include <stdexcept>

namespace lever::test {

namespace {
Eigen::Vector3d vec3(const mjtNum* p) { return Eigen::Vector3d(p[0], p[1], p[2]); }
Eigen::Vector4d vec4(const mjtNum* p) { return Eigen::Vector4d(p[0], p[1], p[2], p[3]); }
std::string name_of(const mjModel* m, int type, int id) {
  const char* n = mj_id2name(m, type, id);
  return n ? n : "";
}

// ---- contact ----------------------------------------------------------------------
// The geoms' contact parameters and bounding spheres, <contact> pairs and exclusions, and the
// contact options and sizes. MuJoCo features lever's collision stage does not model are refused
// here, so that a comparison never runs on a model lever would read differently.
void copy_contact(const mjModel* m, Model& model) {
  if (m->opt.collision != mjCOL_ALL) {
    throw std::runtime_error("from_mujoco: lever collides all pairs (option collision=\"all\")");
  }
  // the flags (lever's bits are MuJoCo's) and the contact override's parameters
  model.opt.disableflags = m->opt.disableflags;
  model.opt.enableflags = m->opt.enableflags;
  model.opt.o_margin = m->opt.o_margin;
  for (int k = 0; k < 2; ++k) model.opt.o_solref[k] = m->opt.o_solref[k];
  for (int k = 0; k < 5; ++k) model.opt.o_solimp[k] = m->opt.o_solimp[k];
  if (m->opt.cone != mjCONE_PYRAMIDAL && m->opt.cone != mjCONE_ELLIPTIC) {
    throw std::runtime_error("from_mujoco: unknown friction cone");
  }
  model.opt.cone = m->opt.cone == mjCONE_PYRAMIDAL ? Cone::kPyramidal : Cone::kElliptic;
  model.opt.impratio = m->opt.impratio;
  model.opt.jacobian = static_cast<JacobianLayout>(m->opt.jacobian);  // mjtJacobian's values
  if (m->opt.solver != mjSOL_PGS && m->opt.solver != mjSOL_CG && m->opt.solver != mjSOL_NEWTON) {
    throw std::runtime_error("from_mujoco: unknown constraint solver");
  }
  model.opt.solver = static_cast<Solver>(m->opt.solver);  // mjtSolver's values
  model.opt.iterations = m->opt.iterations;
  model.opt.tolerance = m->opt.tolerance;
  model.opt.mpr_tolerance = m->opt.mpr_tolerance;
  model.opt.mpr_iterations = m->opt.mpr_iterations;
  model.nconmax = m->nconmax;
  model.njmax = m->njmax;

  for (int g = 0; g < m->ngeom; ++g) {
    model.geom_condim[g] = m->geom_condim[g];
    model.geom_priority[g] = m->geom_priority[g];
    model.geom_solmix[g] = m->geom_solmix[g];
    model.geom_friction[g] = vec3(m->geom_friction + 3 * g);
    model.geom_solref[g] = {m->geom_solref[mjNREF * g], m->geom_solref[mjNREF * g + 1]};
    for (int k = 0; k < 5; ++k) model.geom_solimp[g][k] = m->geom_solimp[mjNIMP * g + k];
    model.geom_margin[g] = m->geom_margin[g];
    model.geom_gap[g] = m->geom_gap[g];
    model.geom_rbound[g] = m->geom_rbound[g];
    model.geom_dataid[g] = m->geom_type[g] == mjGEOM_MESH ? m->geom_dataid[g] : -1;
  }
  // meshes: vertices (floats, held as the doubles they convert to) and hull graphs
  for (int k = 0; k < m->nmesh; ++k) {
    model.mesh_vertadr[k] = m->mesh_vertadr[k];
    model.mesh_vertnum[k] = m->mesh_vertnum[k];
    model.mesh_graphadr[k] = m->mesh_graphadr[k];
  }
  for (int v = 0; v < m->nmeshvert; ++v) {
    const float* p = m->mesh_vert + 3 * v;
    model.mesh_vert[v] = Eigen::Vector3d(p[0], p[1], p[2]);
  }
  for (int i = 0; i < m->nmeshgraph; ++i) model.mesh_graph[i] = m->mesh_graph[i];
  for (int k = 0; k < m->nmesh; ++k) {
    model.mesh_faceadr[k] = m->mesh_faceadr[k];
    model.mesh_facenum[k] = m->mesh_facenum[k];
  }
  for (int f = 0; f < m->nmeshface; ++f) {
    for (int k = 0; k < 3; ++k) model.mesh_face[f][k] = m->mesh_face[3 * f + k];
  }
  for (int p = 0; p < m->npair; ++p) {
    model.pair_dim[p] = m->pair_dim[p];
    model.pair_geom1[p] = m->pair_geom1[p];
    model.pair_geom2[p] = m->pair_geom2[p];
    model.pair_signature[p] = m->pair_signature[p];
    model.pair_solref[p] = {m->pair_solref[mjNREF * p], m->pair_solref[mjNREF * p + 1]};
    for (int k = 0; k < 5; ++k) {
      model.pair_solimp[p][k] = m->pair_solimp[mjNIMP * p + k];
      model.pair_friction[p][k] = m->pair_friction[5 * p + k];
    }
    model.pair_margin[p] = m->pair_margin[p];
    model.pair_gap[p] = m->pair_gap[p];
  }
  for (int e = 0; e < m->nexclude; ++e) model.exclude_signature[e] = m->exclude_signature[e];
}

// ---- sensors: every sensor_ array, the magnetic field; lever's numbering of
// types and objects is MuJoCo's (validate() refuses what lever cannot evaluate)
void copy_sensors(const mjModel* m, Model& model) {
  model.opt.magnetic = vec3(m->opt.magnetic);
  for (int s = 0; s < m->nsensor; ++s) {
    model.sensor_name[s] = name_of(m, mjOBJ_SENSOR, s);
    model.sensor_type[s] = static_cast<SensorType>(m->sensor_type[s]);
    model.sensor_datatype[s] = static_cast<SensorDataType>(m->sensor_datatype[s]);
    model.sensor_needstage[s] = static_cast<SensorStage>(m->sensor_needstage[s]);
    model.sensor_objtype[s] = static_cast<ObjectType>(m->sensor_objtype[s]);
    model.sensor_objid[s] = m->sensor_objid[s];
    model.sensor_reftype[s] = static_cast<ObjectType>(m->sensor_reftype[s]);
    model.sensor_refid[s] = m->sensor_refid[s];
    model.sensor_dim[s] = m->sensor_dim[s];
    model.sensor_adr[s] = m->sensor_adr[s];
    model.sensor_cutoff[s] = m->sensor_cutoff[s];
    model.sensor_noise[s] = m->sensor_noise[s];
  }
}

// Equality constraints (connect, weld, joint and tendon couplings) and the dofs' friction loss.
void copy_constraints(const mjModel* m, Model& model) {
  for (int i = 0; i < m->nv; ++i) {
    model.dof_frictionloss[i] = m->dof_frictionloss[i];
    model.dof_solref[i] = {m->dof_solref[mjNREF * i], m->dof_solref[mjNREF * i + 1]};
    for (int k = 0; k < 5; ++k) model.dof_solimp[i][k] = m->dof_solimp[mjNIMP * i + k];
  }
  for (int e = 0; e < m->neq; ++e) {
    switch (m->eq_type[e]) {
      case mjEQ_CONNECT: model.eq_type[e] = EqualityType::kConnect; break;
      case mjEQ_WELD: model.eq_type[e] = EqualityType::kWeld; break;
      case mjEQ_JOINT: model.eq_type[e] = EqualityType::kJoint; break;
      case mjEQ_TENDON: model.eq_type[e] = EqualityType::kTendon; break;
      default:
        throw std::runtime_error("from_mujoco: equality constraint " + std::to_string(e) +
                                 " is a distance constraint; lever has none");
    }
    model.eq_name[e] = name_of(m, mjOBJ_EQUALITY, e);
    model.eq_obj1id[e] = m->eq_obj1id[e];
    model.eq_obj2id[e] = m->eq_obj2id[e];
    model.eq_active[e] = m->eq_active[e] != 0;
    model.eq_solref[e] = {m->eq_solref[mjNREF * e], m->eq_solref[mjNREF * e + 1]};
    for (int k = 0; k < 5; ++k) model.eq_solimp[e][k] = m->eq_solimp[mjNIMP * e + k];
    for (int k = 0; k < mjNEQDATA; ++k) model.eq_data[e][k] = m->eq_data[mjNEQDATA * e + k];
  }
}

// Tendons and their paths, as MuJoCo compiled them (validate() refuses the spatial ones).
void copy_tendons(const mjModel* m, Model& model) {
  for (int t = 0; t < m->ntendon; ++t) {
    model.tendon_name[t] = name_of(m, mjOBJ_TENDON, t);
    model.tendon_adr[t] = m->tendon_adr[t];
    model.tendon_num[t] = m->tendon_num[t];
    model.tendon_limited[t] = m->tendon_limited[t];
    model.tendon_width[t] = m->tendon_width[t];
    model.tendon_solref_lim[t] = {m->tendon_solref_lim[mjNREF * t], m->tendon_solref_lim[mjNREF * t + 1]};
    model.tendon_solref_fri[t] = {m->tendon_solref_fri[mjNREF * t], m->tendon_solref_fri[mjNREF * t + 1]};
    for (int k = 0; k < 5; ++k) {
      model.tendon_solimp_lim[t][k] = m->tendon_solimp_lim[mjNIMP * t + k];
      model.tendon_solimp_fri[t][k] = m->tendon_solimp_fri[mjNIMP * t + k];
    }
    model.tendon_range[t] = {m->tendon_range[2 * t], m->tendon_range[2 * t + 1]};
    model.tendon_margin[t] = m->tendon_margin[t];
    model.tendon_stiffness[t] = m->tendon_stiffness[t];
    model.tendon_damping[t] = m->tendon_damping[t];
    model.tendon_frictionloss[t] = m->tendon_frictionloss[t];
    model.tendon_lengthspring[t] = m->tendon_lengthspring[t];
  }
  for (int w = 0; w < m->nwrap; ++w) {
    model.wrap_type[w] = static_cast<WrapType>(m->wrap_type[w]);
    model.wrap_objid[w] = m->wrap_objid[w];
    model.wrap_prm[w] = m->wrap_prm[w];
  }
}

}  // namespace

MjModelPtr mujoco_load(const std::string& path) {
  char error[1000] = "";
  mjModel* m = mj_loadXML(path.c_str(), nullptr, error, sizeof error);
  if (!m) throw std::runtime_error("MuJoCo could not load " + path + ": " + error);
  return MjModelPtr(m, mj_deleteModel);
}

MjModelPtr mujoco_load_string(const std::string& xml) {
  mjVFS vfs;
  mj_defaultVFS(&vfs);
  mj_makeEmptyFileVFS(&vfs, "model.xml", static_cast<int>(xml.size()));
  const int index = mj_findFileVFS(&vfs, "model.xml");
  std::copy(xml.begin(), xml.end(), static_cast<char*>(vfs.filedata[index]));
  char error[1000] = "";
  mjModel* m = mj_loadXML("model.xml", &vfs, error, sizeof error);
  mj_deleteVFS(&vfs);
  if (!m) throw std::runtime_error(std::string("MuJoCo could not load the XML: ") + error);
  return MjModelPtr(m, mj_deleteModel);
}

MjDataPtr mujoco_data(const mjModel* m) { return MjDataPtr(mj_makeData(m), mj_deleteData); }

Model from_mujoco(const mjModel* m) {
  Model model;
  model.name = "from_mujoco";
  model.opt.timestep = m->opt.timestep;
  model.opt.gravity = vec3(m->opt.gravity);
  model.opt.viscosity = m->opt.viscosity;
  model.opt.density = m->opt.density;
  model.opt.wind = vec3(m->opt.wind);
  for (int g = 0; g < m->ngeom; ++g) {
    if (m->geom_fluid[mjNFLUID * g] > 0) {
      throw std::runtime_error("from_mujoco: geom " + std::to_string(g) +
                               " uses the ellipsoid fluid model (fluidshape); lever has the "
                               "inertia-box model only");
    }
  }
  if (m->opt.integrator == mjINT_EULER) {
    model.opt.integrator = Integrator::kEuler;
  } else if (m->opt.integrator == mjINT_RK4) {
    model.opt.integrator = Integrator::kRK4;
  } else if (m->opt.integrator == mjINT_IMPLICIT) {
    model.opt.integrator = Integrator::kImplicit;
  } else {
    throw std::runtime_error("from_mujoco: integrator not supported by lever");
  }
  // the counts, then every array sized from them (lever::size_model), then each row copied
  model.nq = m->nq;
  model.nv = m->nv;
  model.nu = m->nu;
  model.na = m->na;
  model.nbody = m->nbody;
  model.njnt = m->njnt;
  model.ngeom = m->ngeom;
  model.nsite = m->nsite;
  model.nkey = m->nkey;
  model.npair = m->npair;
  model.nexclude = m->nexclude;
  model.nmesh = m->nmesh;
  model.nmeshvert = m->nmeshvert;
  model.nmeshgraph = m->nmeshgraph;
  model.nmeshface = m->nmeshface;
  model.nsensor = m->nsensor;
  model.nsensordata = m->nsensordata;
  model.neq = m->neq;
  model.nmocap = m->nmocap;
  model.nuser_body = m->nuser_body;
  model.nuser_jnt = m->nuser_jnt;
  model.nuser_geom = m->nuser_geom;
  model.nuser_site = m->nuser_site;
  model.nuser_tendon = m->nuser_tendon;
  model.nuser_actuator = m->nuser_actuator;
  model.nuser_sensor = m->nuser_sensor;
  model.ntendon = m->ntendon;
  model.nwrap = m->nwrap;
  size_model(model);
  // user data, row-major as MuJoCo's
  const auto copy_user = [](const mjtNum* from, ArenaRowMatrix& to) {
    for (Eigen::Index i = 0; i < to.size(); ++i) to.data()[i] = from[i];
  };
  copy_user(m->body_user, model.body_user);
  copy_user(m->jnt_user, model.jnt_user);
  copy_user(m->geom_user, model.geom_user);
  copy_user(m->site_user, model.site_user);
  copy_user(m->tendon_user, model.tendon_user);
  copy_user(m->actuator_user, model.actuator_user);
  copy_user(m->sensor_user, model.sensor_user);

  for (int b = 0; b < m->nbody; ++b) {
    model.body_name[b] = name_of(m, mjOBJ_BODY, b);
    model.body_parentid[b] = m->body_parentid[b];
    model.body_rootid[b] = m->body_rootid[b];
    model.body_jntnum[b] = m->body_jntnum[b];
    model.body_jntadr[b] = m->body_jntadr[b];
    model.body_dofnum[b] = m->body_dofnum[b];
    model.body_dofadr[b] = m->body_dofadr[b];
    model.body_geomnum[b] = m->body_geomnum[b];
    model.body_geomadr[b] = m->body_geomadr[b];
    model.body_pos[b] = vec3(m->body_pos + 3 * b);
    model.body_quat[b] = vec4(m->body_quat + 4 * b);
    model.body_ipos[b] = vec3(m->body_ipos + 3 * b);
    model.body_iquat[b] = vec4(m->body_iquat + 4 * b);
    model.body_mass[b] = m->body_mass[b];
    model.body_inertia[b] = vec3(m->body_inertia + 3 * b);
    model.body_explicit_inertial[b] = false;  // lever's own: not known from an mjModel
    model.body_line[b] = 0;
    model.body_mocapid[b] = m->body_mocapid[b];
  }
  for (int j = 0; j < m->njnt; ++j) {
    model.jnt_name[j] = name_of(m, mjOBJ_JOINT, j);
    switch (m->jnt_type[j]) {  // lever's numbering is MuJoCo's
      case mjJNT_FREE:
      case mjJNT_BALL:
      case mjJNT_SLIDE:
      case mjJNT_HINGE: model.jnt_type[j] = static_cast<JointType>(m->jnt_type[j]); break;
      default: throw std::runtime_error("from_mujoco: joint type not supported by lever");
    }
    model.jnt_qposadr[j] = m->jnt_qposadr[j];
    model.jnt_dofadr[j] = m->jnt_dofadr[j];
    model.jnt_bodyid[j] = m->jnt_bodyid[j];
    model.jnt_limited[j] = m->jnt_limited[j] != 0;
    model.jnt_solref[j] = {m->jnt_solref[mjNREF * j], m->jnt_solref[mjNREF * j + 1]};
    for (int k = 0; k < 5; ++k) model.jnt_solimp[j][k] = m->jnt_solimp[mjNIMP * j + k];
    model.jnt_pos[j] = vec3(m->jnt_pos + 3 * j);
    model.jnt_axis[j] = vec3(m->jnt_axis + 3 * j);
    model.jnt_stiffness[j] = m->jnt_stiffness[j];
    model.jnt_range[j] = {m->jnt_range[2 * j], m->jnt_range[2 * j + 1]};
    model.jnt_margin[j] = m->jnt_margin[j];
  }
  model.qpos0 = Eigen::Map<const Eigen::VectorXd>(m->qpos0, m->nq);
  model.qpos_spring = Eigen::Map<const Eigen::VectorXd>(m->qpos_spring, m->nq);
  for (int i = 0; i < m->nv; ++i) {
    model.dof_bodyid[i] = m->dof_bodyid[i];
    model.dof_jntid[i] = m->dof_jntid[i];
    model.dof_parentid[i] = m->dof_parentid[i];
    model.dof_armature[i] = m->dof_armature[i];
    model.dof_damping[i] = m->dof_damping[i];
  }
  for (int g = 0; g < m->ngeom; ++g) {
    model.geom_name[g] = name_of(m, mjOBJ_GEOM, g);
    model.geom_type[g] = static_cast<GeomType>(m->geom_type[g]);
    model.geom_bodyid[g] = m->geom_bodyid[g];
    model.geom_contype[g] = m->geom_contype[g];
    model.geom_conaffinity[g] = m->geom_conaffinity[g];
    model.geom_group[g] = m->geom_group[g];
    model.geom_size[g] = vec3(m->geom_size + 3 * g);
    model.geom_pos[g] = vec3(m->geom_pos + 3 * g);
    model.geom_quat[g] = vec4(m->geom_quat + 4 * g);
    const float* rgba = m->geom_rgba + 4 * g;
    model.geom_rgba[g] = Eigen::Vector4d(rgba[0], rgba[1], rgba[2], rgba[3]);
    model.geom_mass[g] = 0.0;  // lever's own: not known from an mjModel
  }
  copy_contact(m, model);
  copy_constraints(m, model);
  for (int s = 0; s < m->nsite; ++s) {
    model.site_name[s] = name_of(m, mjOBJ_SITE, s);
    model.site_bodyid[s] = m->site_bodyid[s];
    model.site_pos[s] = vec3(m->site_pos + 3 * s);
    model.site_quat[s] = vec4(m->site_quat + 4 * s);
    model.site_size[s] = vec3(m->site_size + 3 * s);
    model.site_type[s] = static_cast<GeomType>(m->site_type[s]);
  }
  copy_sensors(m, model);
  copy_tendons(m, model);
  for (int a = 0; a < m->nu; ++a) {
    // user-defined dynamics, gains and biases keep MuJoCo's values (mjtDyn, mjtGain, mjtBias):
    // the caller sets the model's callbacks
    model.actuator_name[a] = name_of(m, mjOBJ_ACTUATOR, a);
    model.actuator_trntype[a] = static_cast<TransmissionType>(m->actuator_trntype[a]);
    model.actuator_trnid[a] = {m->actuator_trnid[2 * a], m->actuator_trnid[2 * a + 1]};
    model.actuator_cranklength[a] = m->actuator_cranklength[a];
    model.actuator_dyntype[a] = static_cast<DynType>(m->actuator_dyntype[a]);
    for (int k = 0; k < kDynParameters; ++k) {
      model.actuator_dynprm[a][k] = m->actuator_dynprm[mjNDYN * a + k];
    }
    model.actuator_actlimited[a] = m->actuator_actlimited[a] != 0;
    model.actuator_actrange[a] = {m->actuator_actrange[2 * a], m->actuator_actrange[2 * a + 1]};
    model.actuator_lengthrange[a] = {m->actuator_lengthrange[2 * a],
                                     m->actuator_lengthrange[2 * a + 1]};
    model.actuator_gaintype[a] = static_cast<GainType>(m->actuator_gaintype[a]);
    model.actuator_biastype[a] = static_cast<BiasType>(m->actuator_biastype[a]);
    for (int k = 0; k < kGainParameters; ++k) {
      model.actuator_gainprm[a][k] = m->actuator_gainprm[mjNGAIN * a + k];
    }
    for (int k = 0; k < kBiasParameters; ++k) {
      model.actuator_biasprm[a][k] = m->actuator_biasprm[mjNBIAS * a + k];
    }
    for (int k = 0; k < 6; ++k) model.actuator_gear[a][k] = m->actuator_gear[6 * a + k];
    model.actuator_ctrllimited[a] = m->actuator_ctrllimited[a] != 0;
    model.actuator_forcelimited[a] = m->actuator_forcelimited[a] != 0;
    model.actuator_ctrlrange[a] = {m->actuator_ctrlrange[2 * a], m->actuator_ctrlrange[2 * a + 1]};
    model.actuator_forcerange[a] = {m->actuator_forcerange[2 * a],
                                    m->actuator_forcerange[2 * a + 1]};
  }
  for (int k = 0; k < m->nkey; ++k) {
    model.key_name[k] = name_of(m, mjOBJ_KEY, k);
    model.key_time[k] = m->key_time[k];
    for (int i = 0; i < m->nq; ++i) model.key_qpos(k, i) = m->key_qpos[m->nq * k + i];
    for (int i = 0; i < m->nv; ++i) model.key_qvel(k, i) = m->key_qvel[m->nv * k + i];
    for (int i = 0; i < m->nu; ++i) model.key_ctrl(k, i) = m->key_ctrl[m->nu * k + i];
    for (int i = 0; i < m->na; ++i) model.key_act(k, i) = m->key_act[m->na * k + i];
    for (int i = 0; i < 3 * m->nmocap; ++i) model.key_mpos(k, i) = m->key_mpos[3 * m->nmocap * k + i];
    for (int i = 0; i < 4 * m->nmocap; ++i) {
      model.key_mquat(k, i) = m->key_mquat[4 * m->nmocap * k + i];
    }
  }
  set_const(model);
  return model;
}

}  // namespace lever::test
