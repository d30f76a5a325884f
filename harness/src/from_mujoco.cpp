#include <lever/harness/from_mujoco.hpp>

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

// ---- contact (issue 19) ----------------------------------------------------------------------
// The geoms' contact parameters and bounding spheres, <contact> pairs and exclusions, and the
// contact options and sizes. MuJoCo features lever's collision stage does not model are refused
// here, so that a comparison never runs on a model lever would read differently.
void copy_contact(const mjModel* m, Model& model) {
  if (m->opt.collision != mjCOL_ALL) {
    throw std::runtime_error("from_mujoco: lever collides all pairs (option collision=\"all\")");
  }
  if (m->opt.disableflags & (mjDSBL_CONSTRAINT | mjDSBL_CONTACT | mjDSBL_FILTERPARENT)) {
    throw std::runtime_error(
        "from_mujoco: lever has no flags to disable constraints, contacts or the parent filter");
  }
  if (m->opt.enableflags & mjENBL_OVERRIDE) {
    throw std::runtime_error("from_mujoco: lever has no contact override");
  }
  if (m->opt.cone != mjCONE_PYRAMIDAL && m->opt.cone != mjCONE_ELLIPTIC) {
    throw std::runtime_error("from_mujoco: unknown friction cone");
  }
  model.opt.cone = m->opt.cone == mjCONE_PYRAMIDAL ? Cone::kPyramidal : Cone::kElliptic;
  model.opt.impratio = m->opt.impratio;
  model.nconmax = m->nconmax;
  model.njmax = m->njmax;

  for (int g = 0; g < m->ngeom; ++g) {
    model.geom_condim.push_back(m->geom_condim[g]);
    model.geom_priority.push_back(m->geom_priority[g]);
    model.geom_solmix.push_back(m->geom_solmix[g]);
    model.geom_friction.push_back(vec3(m->geom_friction + 3 * g));
    model.geom_solref.push_back({m->geom_solref[mjNREF * g], m->geom_solref[mjNREF * g + 1]});
    std::array<double, 5> solimp;
    for (int k = 0; k < 5; ++k) solimp[k] = m->geom_solimp[mjNIMP * g + k];
    model.geom_solimp.push_back(solimp);
    model.geom_margin.push_back(m->geom_margin[g]);
    model.geom_gap.push_back(m->geom_gap[g]);
    model.geom_rbound.push_back(m->geom_rbound[g]);
  }

  model.npair = m->npair;
  for (int p = 0; p < m->npair; ++p) {
    model.pair_dim.push_back(m->pair_dim[p]);
    model.pair_geom1.push_back(m->pair_geom1[p]);
    model.pair_geom2.push_back(m->pair_geom2[p]);
    model.pair_signature.push_back(m->pair_signature[p]);
    model.pair_solref.push_back({m->pair_solref[mjNREF * p], m->pair_solref[mjNREF * p + 1]});
    std::array<double, 5> solimp, friction;
    for (int k = 0; k < 5; ++k) {
      solimp[k] = m->pair_solimp[mjNIMP * p + k];
      friction[k] = m->pair_friction[5 * p + k];
    }
    model.pair_solimp.push_back(solimp);
    model.pair_friction.push_back(friction);
    model.pair_margin.push_back(m->pair_margin[p]);
    model.pair_gap.push_back(m->pair_gap[p]);
  }
  model.nexclude = m->nexclude;
  for (int e = 0; e < m->nexclude; ++e) model.exclude_signature.push_back(m->exclude_signature[e]);
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
  if (m->opt.integrator == mjINT_EULER) {
    model.opt.integrator = Integrator::kEuler;
  } else if (m->opt.integrator == mjINT_RK4) {
    model.opt.integrator = Integrator::kRK4;
  } else if (m->opt.integrator == mjINT_IMPLICIT) {
    model.opt.integrator = Integrator::kImplicit;
  } else {
    throw std::runtime_error("from_mujoco: integrator not supported by lever");
  }
  model.nq = m->nq;
  model.nv = m->nv;
  model.nu = m->nu;
  model.nbody = m->nbody;
  model.njnt = m->njnt;
  model.ngeom = m->ngeom;
  model.nsite = m->nsite;

  model.body_name.clear();
  model.body_parentid.clear();
  model.body_rootid.clear();
  model.body_jntnum.clear();
  model.body_jntadr.clear();
  model.body_dofnum.clear();
  model.body_dofadr.clear();
  model.body_geomnum.clear();
  model.body_geomadr.clear();
  model.body_pos.clear();
  model.body_quat.clear();
  model.body_ipos.clear();
  model.body_iquat.clear();
  model.body_mass.clear();
  model.body_inertia.clear();
  model.body_explicit_inertial.clear();
  model.body_line.clear();
  for (int b = 0; b < m->nbody; ++b) {
    model.body_name.push_back(name_of(m, mjOBJ_BODY, b));
    model.body_parentid.push_back(m->body_parentid[b]);
    model.body_rootid.push_back(m->body_rootid[b]);
    model.body_jntnum.push_back(m->body_jntnum[b]);
    model.body_jntadr.push_back(m->body_jntadr[b]);
    model.body_dofnum.push_back(m->body_dofnum[b]);
    model.body_dofadr.push_back(m->body_dofadr[b]);
    model.body_geomnum.push_back(m->body_geomnum[b]);
    model.body_geomadr.push_back(m->body_geomadr[b]);
    model.body_pos.push_back(vec3(m->body_pos + 3 * b));
    model.body_quat.push_back(vec4(m->body_quat + 4 * b));
    model.body_ipos.push_back(vec3(m->body_ipos + 3 * b));
    model.body_iquat.push_back(vec4(m->body_iquat + 4 * b));
    model.body_mass.push_back(m->body_mass[b]);
    model.body_inertia.push_back(vec3(m->body_inertia + 3 * b));
    model.body_explicit_inertial.push_back(false);
    model.body_line.push_back(0);
  }
  for (int j = 0; j < m->njnt; ++j) {
    model.jnt_name.push_back(name_of(m, mjOBJ_JOINT, j));
    switch (m->jnt_type[j]) {  // lever's numbering is MuJoCo's
      case mjJNT_FREE:
      case mjJNT_BALL:
      case mjJNT_SLIDE:
      case mjJNT_HINGE: model.jnt_type.push_back(static_cast<JointType>(m->jnt_type[j])); break;
      default: throw std::runtime_error("from_mujoco: joint type not supported by lever");
    }
    model.jnt_qposadr.push_back(m->jnt_qposadr[j]);
    model.jnt_dofadr.push_back(m->jnt_dofadr[j]);
    model.jnt_bodyid.push_back(m->jnt_bodyid[j]);
    model.jnt_limited.push_back(m->jnt_limited[j] != 0);
    model.jnt_solref.push_back({m->jnt_solref[mjNREF * j], m->jnt_solref[mjNREF * j + 1]});
    std::array<double, 5> solimp;
    for (int k = 0; k < 5; ++k) solimp[k] = m->jnt_solimp[mjNIMP * j + k];
    model.jnt_solimp.push_back(solimp);
    model.jnt_pos.push_back(vec3(m->jnt_pos + 3 * j));
    model.jnt_axis.push_back(vec3(m->jnt_axis + 3 * j));
    model.jnt_stiffness.push_back(m->jnt_stiffness[j]);
    model.jnt_range.push_back({m->jnt_range[2 * j], m->jnt_range[2 * j + 1]});
    model.jnt_margin.push_back(m->jnt_margin[j]);
  }
  model.qpos0 = Eigen::Map<const Eigen::VectorXd>(m->qpos0, m->nq);
  model.qpos_spring = Eigen::Map<const Eigen::VectorXd>(m->qpos_spring, m->nq);
  for (int i = 0; i < m->nv; ++i) {
    model.dof_bodyid.push_back(m->dof_bodyid[i]);
    model.dof_jntid.push_back(m->dof_jntid[i]);
    model.dof_parentid.push_back(m->dof_parentid[i]);
    model.dof_armature.push_back(m->dof_armature[i]);
    model.dof_damping.push_back(m->dof_damping[i]);
  }
  for (int g = 0; g < m->ngeom; ++g) {
    model.geom_name.push_back(name_of(m, mjOBJ_GEOM, g));
    model.geom_type.push_back(static_cast<GeomType>(m->geom_type[g]));
    model.geom_bodyid.push_back(m->geom_bodyid[g]);
    model.geom_contype.push_back(m->geom_contype[g]);
    model.geom_conaffinity.push_back(m->geom_conaffinity[g]);
    model.geom_group.push_back(m->geom_group[g]);
    model.geom_size.push_back(vec3(m->geom_size + 3 * g));
    model.geom_pos.push_back(vec3(m->geom_pos + 3 * g));
    model.geom_quat.push_back(vec4(m->geom_quat + 4 * g));
    const float* rgba = m->geom_rgba + 4 * g;
    model.geom_rgba.emplace_back(rgba[0], rgba[1], rgba[2], rgba[3]);
    model.geom_mass.push_back(0.0);
  }
  copy_contact(m, model);
  for (int s = 0; s < m->nsite; ++s) {
    model.site_name.push_back(name_of(m, mjOBJ_SITE, s));
    model.site_bodyid.push_back(m->site_bodyid[s]);
    model.site_pos.push_back(vec3(m->site_pos + 3 * s));
    model.site_quat.push_back(vec4(m->site_quat + 4 * s));
    model.site_size.push_back(vec3(m->site_size + 3 * s));
  }
  for (int a = 0; a < m->nu; ++a) {
    const bool affine_or_fixed_gain =
        m->actuator_gaintype[a] == mjGAIN_FIXED || m->actuator_gaintype[a] == mjGAIN_AFFINE;
    const bool affine_or_no_bias =
        m->actuator_biastype[a] == mjBIAS_NONE || m->actuator_biastype[a] == mjBIAS_AFFINE;
    if (m->actuator_trntype[a] != mjTRN_JOINT || m->actuator_dyntype[a] != mjDYN_NONE ||
        !affine_or_fixed_gain || !affine_or_no_bias) {
      throw std::runtime_error(
          "from_mujoco: only stateless joint actuators with affine gain and bias are supported");
    }
    model.actuator_name.push_back(name_of(m, mjOBJ_ACTUATOR, a));
    model.actuator_trnid.push_back(m->actuator_trnid[2 * a]);
    model.actuator_dyntype.push_back(DynType::kNone);
    model.actuator_gaintype.push_back(static_cast<GainType>(m->actuator_gaintype[a]));
    model.actuator_biastype.push_back(static_cast<BiasType>(m->actuator_biastype[a]));
    std::array<double, kGainParameters> gainprm;
    std::array<double, kBiasParameters> biasprm;
    for (int k = 0; k < kGainParameters; ++k) gainprm[k] = m->actuator_gainprm[mjNGAIN * a + k];
    for (int k = 0; k < kBiasParameters; ++k) biasprm[k] = m->actuator_biasprm[mjNBIAS * a + k];
    model.actuator_gainprm.push_back(gainprm);
    model.actuator_biasprm.push_back(biasprm);
    std::array<double, 6> gear;
    for (int k = 0; k < 6; ++k) gear[k] = m->actuator_gear[6 * a + k];
    model.actuator_gear.push_back(gear);
    model.actuator_ctrllimited.push_back(m->actuator_ctrllimited[a] != 0);
    model.actuator_forcelimited.push_back(m->actuator_forcelimited[a] != 0);
    model.actuator_ctrlrange.push_back(
        {m->actuator_ctrlrange[2 * a], m->actuator_ctrlrange[2 * a + 1]});
    model.actuator_forcerange.push_back(
        {m->actuator_forcerange[2 * a], m->actuator_forcerange[2 * a + 1]});
  }
  model.nkey = m->nkey;
  model.key_name.clear();
  model.key_time.clear();
  model.key_qpos.resize(m->nkey, m->nq);
  model.key_qvel.resize(m->nkey, m->nv);
  model.key_ctrl.resize(m->nkey, m->nu);
  for (int k = 0; k < m->nkey; ++k) {
    model.key_name.push_back(name_of(m, mjOBJ_KEY, k));
    model.key_time.push_back(m->key_time[k]);
    for (int i = 0; i < m->nq; ++i) model.key_qpos(k, i) = m->key_qpos[m->nq * k + i];
    for (int i = 0; i < m->nv; ++i) model.key_qvel(k, i) = m->key_qvel[m->nv * k + i];
    for (int i = 0; i < m->nu; ++i) model.key_ctrl(k, i) = m->key_ctrl[m->nu * k + i];
  }
  set_const(model);
  return model;
}

}  // namespace lever::test
