// `lever check --json`: the report as one JSON object, sections as keys, numbers at full precision
// (infinite and undefined figures, such as an unbounded motor's limit, as null).
#include <lever/check.hpp>
#include <lever/io/json.hpp>

namespace lever::check {

namespace {

using Json = json::Writer;

void pair(Json& j, const std::array<double, 2>& r) {
  j.begin_array().value(r[0]).value(r[1]).end_array();
}

void matrix(Json& j, const Eigen::MatrixXd& M) {
  j.begin_array();
  for (Eigen::Index r = 0; r < M.rows(); ++r) j.values(M.row(r).transpose());
  j.end_array();
}

void strings(Json& j, const std::vector<std::string>& list) {
  j.begin_array();
  for (const std::string& s : list) j.value(s);
  j.end_array();
}

void structure(Json& j, const Structure& s) {
  j.key("joints").begin_array();
  for (const JointInfo& x : s.joints) {
    j.begin_object().key("name").value(x.name).key("type").value(x.type);
    j.key("axis").values(x.axis).key("range");
    pair(j, x.range);
    j.key("limited").value(x.limited).key("damping").value(x.damping);
    j.key("armature").value(x.armature).key("stiffness").value(x.stiffness);
    j.key("qpos0").value(x.qpos0).end_object();
  }
  j.end_array().key("motors").begin_array();
  for (const MotorInfo& m : s.motors) {
    j.begin_object().key("name").value(m.name).key("joint").value(m.joint);
    j.key("gear").value(m.gear).key("ctrlrange");
    pair(j, m.ctrlrange);
    j.key("ctrllimited").value(m.ctrllimited).key("forcerange");
    pair(j, m.forcerange);
    j.key("forcelimited").value(m.forcelimited).key("joint_torque");
    pair(j, m.joint_torque);
    j.key("servo").value(m.servo).key("kp").value(m.kp).key("kv").value(m.kv);
    j.key("gainprm").begin_array().value(m.gainprm[0]).value(m.gainprm[1]).value(m.gainprm[2]);
    j.end_array().key("biasprm").begin_array().value(m.biasprm[0]).value(m.biasprm[1]);
    j.value(m.biasprm[2]).end_array();
    j.end_object();
  }
  j.end_array().key("sites").begin_array();
  for (size_t i = 0; i < s.sites.size(); ++i) {
    j.begin_object().key("name").value(s.sites[i]).key("body").value(s.site_bodies[i]).end_object();
  }
  j.end_array().key("bodies").begin_array();
  for (const BodyInfo& b : s.bodies) {
    j.begin_object().key("name").value(b.name).key("mass").value(b.mass);
    j.key("principal_moments").values(b.principal);
    j.key("explicit_inertial").value(b.explicit_inertial).end_object();
  }
  j.end_array();
}

void kinematics(Json& j, const Kinematics& k) {
  j.key("poses").value(k.poses).key("sites").begin_array();
  for (const SiteKinematics& s : k.sites) {
    j.begin_object().key("site").value(s.site);
    j.key("max_error_transforms").value(s.max_error_transforms).key("planar");
    if (!s.planar) {
      j.begin_object().end_object();
    } else {
      const PlanarChain& c = *s.planar;
      j.begin_object().key("joints");
      strings(j, c.joints);
      j.key("normal").values(c.normal).key("u").values(c.u).key("w").values(c.w);
      j.key("origin").values(c.origin);
      j.key("lengths").values(
          Eigen::Map<const Eigen::VectorXd>(c.lengths.data(), c.lengths.size()));
      j.key("angles0").values(
          Eigen::Map<const Eigen::VectorXd>(c.angles0.data(), c.angles0.size()));
      j.key("offset").value(c.offset).key("max_error").value(c.max_error).end_object();
    }
    j.end_object();
  }
  j.end_array();
}

void budget(Json& j, const TorqueBudget& b) {
  j.key("formula_poses").value(b.formula_poses).key("formula_max_error").value(b.formula_max_error);
  j.key("search").value(b.search).key("evaluations").value(b.evaluations);
  j.key("gravity").value(b.gravity).key("joints").begin_array();
  for (const JointBudget& x : b.joints) {
    j.begin_object().key("joint").value(x.joint).key("worst_gravity_torque").value(x.worst_torque);
    j.key("worst_pose").values(x.worst_pose).key("loaded").value(x.loaded);
    j.key("motors");
    strings(j, x.motors);
    j.key("torque_range");
    pair(j, x.torque_range);
    j.key("motor_limit").value(x.limit).key("ratio").value(x.ratio);
    j.key("spare_torque").value(x.spare).key("acceleration").value(x.acceleration);
    j.key("rigid_torques").values(x.rigid_torques);
    j.key("servo").value(x.servo).key("servo_stiffness").value(x.stiffness);
    j.key("servo_offset").value(x.sag).key("hold_target").value(x.hold_target);
    j.key("target_outside_ctrlrange").value(x.target_outside).end_object();
  }
  j.end_array().key("payload").begin_array();
  for (const SitePayload& p : b.payload) {
    j.begin_object().key("site").value(p.site);
    j.key("per_joint")
        .values(Eigen::Map<const Eigen::VectorXd>(p.per_joint.data(), p.per_joint.size()));
    j.key("min").value(p.min).key("binding_joint").value(p.binding_joint).end_object();
  }
  j.end_array().key("mass_matrices").begin_array();
  for (const PoseInertia& p : b.poses) {
    j.begin_object().key("qpos").values(p.q).key("M");
    matrix(j, p.M);
    j.key("joints").begin_array();
    for (const int k : p.joints) j.value(b.joints[k].joint);
    j.end_array().end_object();
  }
  j.end_array();
}

void inertia(Json& j, const Inertia& in) {
  j.key("inferred_available").value(in.inferred_available);
  j.key("inferred_error").value(in.inferred_error).key("bodies").begin_array();
  for (const BodyInertia& b : in.bodies) {
    j.begin_object().key("name").value(b.name).key("explicit_inertial").value(b.explicit_inertial);
    j.key("mass").value(b.mass).key("principal_moments").values(b.principal);
    if (in.inferred_available) {
      j.key("inferred_mass").value(b.inferred_mass);
      j.key("inferred_principal_moments").values(b.inferred_principal);
    }
    j.end_object();
  }
  j.end_array().key("gravity_torque_at_worst_pose").begin_array();
  for (const JointTorqueInferred& t : in.torques) {
    j.begin_object().key("joint").value(t.joint).key("explicit").value(t.explicit_torque);
    j.key("from_geoms").value(t.inferred_torque).end_object();
  }
  j.end_array().key("inertiagrouprange").begin_array();
  j.value(in.inertiagrouprange[0]).value(in.inertiagrouprange[1]).end_array();
  j.key("bodies_without_inertial");
  strings(j, in.bodies_without_inertial);
  j.key("visual_geoms_with_mass").begin_array();
  for (const VisualMass& v : in.visual_mass) {
    j.begin_object().key("geom").value(v.geom).key("body").value(v.body);
    j.key("group").value(v.group).key("mass").value(v.mass).end_object();
  }
  j.end_array().key("demo").begin_object();
  j.key("default_range")
      .begin_array()
      .value(in.demo_default_range[0])
      .value(in.demo_default_range[1])
      .end_array();
  j.key("default_mass").value(in.demo_default_mass);
  j.key("narrow_range")
      .begin_array()
      .value(in.demo_narrow_range[0])
      .value(in.demo_narrow_range[1])
      .end_array();
  j.key("narrow_mass").value(in.demo_narrow_mass).end_object();
}

void stops(Json& j, const SoftStops& st) {
  j.key("settle_qvel").value(st.settle_qvel).key("settle_time").value(st.settle_time);
  j.key("relax_qvel")
      .value(st.relax_qvel)
      .key("relax_bound")
      .value(st.relax_bound)
      .key("time_bound")
      .value(st.time_bound);
  j.key("runs").value(st.runs).key("stops").begin_array();
  for (const StopRest& s : st.stops) {
    j.begin_object().key("joint").value(s.joint).key("side").value(s.upper ? "upper" : "lower");
    j.key("stop").value(s.stop).key("margin").value(s.margin).key("loadable").value(s.loadable);
    if (s.loadable) {
      j.key("from_qpos0").value(s.from_qpos0).key("start").values(s.start);
      j.key("time")
          .value(s.time)
          .key("relax_time")
          .value(s.relax_time)
          .key("settled")
          .value(s.settled)
          .key("max_qvel")
          .value(s.max_qvel);
      j.key("rests_on_stop").value(s.rests_on_stop).key("qpos").value(s.q);
      j.key("past_stop").value(s.past).key("rows").value(s.rows);
      j.key("qfrc_constraint").value(s.qfrc_constraint).key("qfrc_bias").value(s.qfrc_bias);
      j.key("qfrc_passive").value(s.qfrc_passive);
      j.key("final_qpos").values(s.final_qpos).key("warnings").value(s.warnings);
    }
    j.end_object();
  }
  j.end_array();
}

void clamping(Json& j, const Clamping& c) {
  j.key("ctrl").values(c.ctrl).key("actuator_force").values(c.actuator_force);
  j.key("warnings").value(c.warnings).key("unbounded");
  strings(j, c.unbounded);
  j.key("servo").begin_array();
  for (const uint8_t s : c.servo) j.value(s != 0);
  j.end_array().key("target").values(c.target).key("force_before_forcerange").values(c.raw_force);
  j.key("qpos").values(c.qpos);
}

void jacobian_at(Json& j, const JacobianAt& at) {
  j.begin_object().key("where").value(at.where).key("qpos").values(at.q);
  j.key("sigma").values(at.sigma).key("manipulability").value(at.manipulability);
  j.key("condition").value(at.condition).key("least_moving_motion").values(at.null_motion);
  j.key("aligned").begin_array();
  for (const JointAlignment& a : at.aligned) {
    j.begin_object().key("joints").begin_array().value(a.first).value(a.second).end_array();
    j.key("collinear").value(a.collinear).key("angle").value(a.angle);
    j.key("distance").value(a.distance).end_object();
  }
  j.end_array().end_object();
}

void singular(Json& j, const SingularPoses& sp) {
  j.key("search").value(sp.search).key("evaluations").value(sp.evaluations);
  j.key("parallel_tolerance").value(sp.parallel_tolerance).key("sites").begin_array();
  for (const SiteSingularity& s : sp.sites) {
    j.begin_object().key("site").value(s.site).key("rows").value(s.rows).key("rank").value(s.rank);
    j.key("states").begin_array();
    for (const JacobianAt& at : s.states) jacobian_at(j, at);
    j.end_array().key("worst").begin_array();
    for (const JacobianAt& at : s.worst) jacobian_at(j, at);
    j.end_array().end_object();
  }
  j.end_array();
}

void values(Json& j, const std::vector<double>& v) {
  j.values(Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size())));
}

// A search along a timestep or an armature: its grid and every change of stability it found.
void scan(Json& j, const StabilityScan& s) {
  j.begin_object().key("from").value(s.from).key("to").value(s.to).key("points").value(s.points);
  j.key("resolution").value(s.resolution).key("stable_first").value(s.stable_first);
  j.key("changes");
  values(j, s.changes);
  j.end_object();
}

void scans(Json& j, const std::vector<StabilityScan>& list) {
  j.begin_array();
  for (const StabilityScan& s : list) scan(j, s);
  j.end_array();
}

void stability(Json& j, const StepStability& st) {
  j.key("timestep").value(st.timestep).key("integrator").value(st.integrator);
  j.key("fd_eps").value(st.fd_eps).key("slack").value(st.slack).key("dt_cap").value(st.dt_cap);
  j.key("armature_cap").value(st.armature_cap).key("margin").value(st.margin);
  j.key("qvel_bound").value(st.qvel_bound).key("settle_qvel").value(st.settle_qvel);
  j.key("ample").value(st.ample).key("dt_floor").value(st.dt_floor);
  j.key("armature_start").value(st.armature_start);
  j.key("points_per_decade").value(st.points_per_decade).key("joints");
  strings(j, st.joints);
  j.key("states").begin_array();
  for (const StabilityAt& s : st.states) {
    j.begin_object().key("where").value(s.where).key("qpos").values(s.qpos);
    j.key("qvel").values(s.qvel).key("ctrl").values(s.ctrl).key("growth").value(s.growth);
    j.key("rho_model").value(s.rho_model).key("rho_euler").value(s.rho_euler);
    j.key("stable_model").value(s.stable_model).key("stable_euler").value(s.stable_euler);
    j.key("max_timestep_model").value(s.max_dt_model);
    j.key("max_timestep_euler").value(s.max_dt_euler);
    j.key("armature_all").value(s.armature_all).key("armature_each");
    values(j, s.armature_each);
    j.key("armature_alone");
    values(j, s.armature_alone);
    j.key("armature_floor").value(s.armature_floor);
    j.key("timestep_scan_model");
    scan(j, s.dt_scan_model);
    j.key("timestep_scan_euler");
    scan(j, s.dt_scan_euler);
    j.key("armature_scan_all");
    scan(j, s.armature_scan_all);
    j.key("armature_scan_each");
    scans(j, s.armature_scan_each);
    j.key("armature_scan_floor");
    scan(j, s.armature_scan_floor);
    j.key("armature_scan_alone");
    scans(j, s.armature_scan_alone);
    j.key("sweep_timestep");
    values(j, s.sweep_dt);
    j.key("sweep_rho_model");
    values(j, s.sweep_rho_model);
    j.key("sweep_rho_euler");
    values(j, s.sweep_rho_euler);
    j.key("rho_euler_with_armature").value(s.rho_euler_with);
    j.key("rho_euler_each")
        .value(s.rho_euler_each)
        .key("stable_euler_each")
        .value(s.stable_euler_each);
    j.key("runs").begin_array();
    for (const StabilityRun& r : s.runs) {
      j.begin_object().key("integrator").value(r.integrator).key("armature").value(r.armature);
      j.key("steps").value(r.steps).key("max_qvel").value(r.max_qvel);
      j.key("final_qvel").value(r.final_qvel).key("saturated_steps").value(r.saturated);
      j.key("blowup_step").value(r.blowup_step).key("warnings").value(r.warnings);
      j.key("settled").value(r.settled);
      j.key("bounded").value(r.bounded()).end_object();
    }
    j.end_array().end_object();
  }
  j.end_array();
}

}  // namespace

namespace {

// ---- (9) contacts

template <size_t N>
void numbers(Json& j, const std::array<double, N>& x) {
  j.begin_array();
  for (double v : x) j.value(v);
  j.end_array();
}

void contacts(Json& j, const Contacts& c) {
  if (!c.skipped.empty()) {
    j.key("skipped").value(c.skipped);
    return;
  }
  j.key("pairs").begin_array();
  for (const ContactPairInfo& p : c.pairs) {
    j.begin_object().key("geom1").value(p.geom1).key("geom2").value(p.geom2);
    j.key("explicit_pair").value(p.explicit_pair).key("condim").value(p.condim).key("friction");
    numbers(j, p.friction);
    j.key("solref");
    numbers(j, p.solref);
    j.key("solimp");
    numbers(j, p.solimp);
    j.key("margin").value(p.margin).key("gap").value(p.gap).key("contacts_seen").value(p.seen);
    j.key("agrees").value(p.agrees).end_object();
  }
  j.end_array().key("strays");
  strings(j, c.strays);
  const RestingDepth& r = c.rest;
  j.key("resting_depth").begin_object();
  if (!r.skipped.empty()) {
    j.key("skipped").value(r.skipped);
  } else {
    j.key("body").value(r.body).key("plane").value(r.plane).key("start").value(r.start);
    j.key("mass").value(r.mass).key("gravity").value(r.gravity).key("condim").value(r.condim);
    j.key("cone").value(r.elliptic ? "elliptic" : "pyramidal");
    j.key("contacts").value(r.contacts).key("rows_per_contact").value(r.rows);
    j.key("friction").value(r.friction).key("impratio").value(r.impratio).key("solref");
    numbers(j, r.solref);
    j.key("solimp");
    numbers(j, r.solimp);
    j.key("K").value(r.K).key("invweight").value(r.invweight).key("A").value(r.A);
    j.key("predicted").value(r.predicted).key("impedance").value(r.impedance);
    j.key("simulated").value(r.simulated).key("spread").value(r.spread);
    j.key("time").value(r.time).key("final_speed").value(r.final_speed);
    j.key("settle_speed").value(r.settle_speed).key("settled").value(r.settled);
    j.key("unsupported_warnings").value(r.unsupported);
    j.key("bound").value(r.bound).key("agrees").value(r.agrees());
  }
  j.end_object();
  const Grip& g = c.grip;
  j.key("grip").begin_object();
  if (!g.skipped.empty()) {
    j.key("skipped").value(g.skipped);
  } else {
    j.key("body").value(g.body).key("fingers");
    strings(j, g.fingers);
    j.key("mass").value(g.mass).key("gravity").value(g.gravity).key("mu").value(g.mu);
    j.key("needed_force").value(g.needed).key("servo_force").value(g.servo_force);
    j.key("servo_force_simulated").value(g.servo_force_closed);
    j.key("servo_kp").value(g.servo_kp).key("full_command").value(g.full_command);
    j.key("touch").value(g.touch).key("holds_by_hand").value(g.holds_by_hand());
    j.key("close_time").value(g.close_time).key("hold_time").value(g.hold_time);
    j.key("speedup_threshold")
        .value(g.speedup_threshold)
        .key("fall")
        .value(g.fall)
        .key("creep")
        .value(g.creep);
    j.key("trials").begin_array();
    for (const GripTrial& t : g.trials) {
      j.begin_object().key("command").value(t.command).key("closed_force").value(t.closed_force);
      j.key("force").value(t.force);
      j.key("drop")
          .value(t.drop)
          .key("speedup")
          .value(t.speedup)
          .key("slipped")
          .value(t.slipped)
          .end_object();
    }
    j.end_array().key("hold_force").value(g.hold_force).key("slip_force").value(g.slip_force);
    j.key("resolution").value(g.resolution);
    j.key("pads").begin_array();
    for (const GripPad& p : g.pads) {
      j.begin_object().key("sensor").value(p.sensor).key("finger").value(p.finger);
      j.key("closed").value(p.closed).key("servo_closed").value(p.servo_closed);
      j.key("held").value(p.held).key("servo_held").value(p.servo_held);
      j.key("tolerance").value(p.tolerance).key("agrees").value(p.agrees()).end_object();
    }
    j.end_array();
  }
  j.end_object();
}

void report(Json& j, const Report& r) {
  j.begin_object().key("model").value(r.model).key("source").value(r.source);
  // a section that does not apply holds only why
  const auto section = [&](int n, const char* name, const auto& write) {
    j.key(name).begin_object();
    const std::string why = r.skipped(n);
    if (why.empty()) {
      write();
    } else {
      j.key("skipped").value(why);
    }
    j.end_object();
  };
  j.key("floating_joints").value(r.floating_joints);
  j.key("structure").begin_object();
  structure(j, r.structure);
  j.end_object();
  section(2, "kinematics", [&] { kinematics(j, r.kinematics); });
  section(3, "torque_budget", [&] { budget(j, r.budget); });
  j.key("inertia").begin_object();
  inertia(j, r.inertia);
  j.end_object();
  section(5, "soft_stops", [&] { stops(j, r.stops); });
  j.key("clamping").begin_object();
  clamping(j, r.clamping);
  j.end_object();
  section(7, "singular_poses", [&] { singular(j, r.singular); });
  section(8, "step_stability", [&] { stability(j, r.stability); });
  j.key("contacts").begin_object();
  contacts(j, r.contacts);
  j.end_object().key("findings");
  strings(j, r.findings);
  j.key("exit_status").value(r.exit_status()).end_object();
}
}  // namespace

void write_json(std::FILE* out, const Report& r) {
  Json j(out);
  report(j, r);
  j.newline();
}

std::string to_json(const Report& r) {
  std::string text;
  Json j(&text);
  report(j, r);
  return text;
}

}  // namespace lever::check
