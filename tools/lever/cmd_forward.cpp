// lever forward: everything the engine computes at one state.
//
//   lever forward MODEL [--key NAME] [--qpos a,b,..] [--qvel ..] [--ctrl ..] [--time T] [--json]
//
// Runs lever::forward() (MuJoCo's mj_forward) at the given state, then the site Jacobians
// (mj_jacSite) and the energy (mj_energyPos + mj_energyVel). Omitted vectors are qpos0 and zeros.
//
// --json: one object: the model's name and sizes (nq, nv, nu, nbody, njnt, ngeom, nsite), time,
// nefc, then every array of Data's field table (lever/fields.hpp: qpos ... qfrc_constraint,
// qfrc_inverse, energy) under mjData's names, laid out as mjData stores them, row-major and
// flattened (xmat: nbody x 9; efc arrays: the nefc live rows, limits then contacts), with
//   M          nv x nv, full and symmetric (MuJoCo's mj_fullM of qM)
//   energy     [potential, kinetic] in J
//   efc_J      nefc x nv, the constraint rows' Jacobian (dense, as MuJoCo's efc_J)
//   ncon       the number of contacts
//   contact    one object per contact: mjContact's fields, the geoms' names and `force`, its force
//              in its frame (mj_contactForce; lever/io/serialize.hpp write_contacts)
// and what the command adds:
//   site_jacp  nsite x 3 x nv (mj_jacSite's jacp for each site, one after the other)
//   site_jacr  nsite x 3 x nv
// Numbers are written in the shortest form that reads back as the same double (nlohmann-json),
// so they compare exactly.
// Without --json: readable tables with names and units (the contacts: geom names, dist, normal,
// normal and friction force; the sensors: name, type and numbers). --time sets data.time (what a
// clock sensor reads).
// Exit 0; 1 when the evaluation raised an engine warning (a state that is NaN or beyond 1e10, an
// acceleration that blows up) or gave a number that is not finite (printed as n/a, or null in
// JSON), each said on stderr; bad input (a list with the wrong count, text that is not a number,
// NaN or inf) exits 2.
#include <cstdio>
#include <string>

#include <lever/io/serialize.hpp>
#include <lever/lever.hpp>
#include <lever/mjcf.hpp>

#include "cli.hpp"
#include "commands.hpp"
#include "forward_state.hpp"

namespace lever::cli {

namespace {

// Everything forward() leaves in data, plus what the command adds: site Jacobians and energy.
struct Evaluation {
  Eigen::MatrixXd jacp, jacr;  // (3 * nsite) x nv: site s occupies rows 3s .. 3s+2
};

Evaluation evaluate(const Model& model, Data& data) {
  forward(model, data);
  compute_energy(model, data);
  Evaluation e{Eigen::MatrixXd::Zero(3 * model.nsite, model.nv),
               Eigen::MatrixXd::Zero(3 * model.nsite, model.nv)};
  Eigen::MatrixXd jp(3, model.nv), jr(3, model.nv);
  for (int s = 0; s < model.nsite; ++s) {
    jac_site(model, data, s, jp, jr);
    e.jacp.middleRows(3 * s, 3) = jp;
    e.jacr.middleRows(3 * s, 3) = jr;
  }
  return e;
}

// ---- json ------------------------------------------------------------------------------------

// A matrix row by row, flattened.
void row_major(Json& json, const char* key, const Eigen::MatrixXd& m) {
  json.key(key).begin_array();
  for (Eigen::Index r = 0; r < m.rows(); ++r) {
    for (Eigen::Index c = 0; c < m.cols(); ++c) json.value(m(r, c));
  }
  json.end_array();
}

// The sizes, then every array of Data (the field table, lever/fields.hpp), then the site
// Jacobians.
void print_json(const Model& model, const Data& data, const Evaluation& e) {
  Json json(stdout);
  json.begin_object();
  json.key("model").value(model.name);
  write_model_sizes(json, model);
  write_data_fields(json, model, data);
  row_major(json, "site_jacp", e.jacp);
  row_major(json, "site_jacr", e.jacr);
  json.end_object();
  json.newline();
}

// ---- text ------------------------------------------------------------------------------------

// The joint-limit rows among the constraint rows (contact rows are listed with their contacts).
void print_limit_rows(const Model& model, const Data& data) {
  int limits = 0;
  for (int r = 0; r < data.nefc; ++r) limits += data.efc_type[r] == ConstraintType::kLimitJoint;
  std::printf("\njoint-limit rows: %d of nefc %d\n", limits, data.nefc);
  if (limits == 0) return;
  std::printf("  %-10s %-6s %12s %12s %12s %12s %12s\n", "joint", "stop", "efc_pos", "efc_force",
              "efc_aref", "efc_R", "efc_D");
  for (int r = 0; r < data.nefc; ++r) {
    if (data.efc_type[r] != ConstraintType::kLimitJoint) continue;
    const int j = data.efc_id[r];
    std::printf("  %-10s %-6s %12s %12s %12s %12s %12s\n", label_of(model.jnt_name[j], j).c_str(),
                data.efc_sign[r] > 0 ? "lower" : "upper", num(data.efc_pos[r]).c_str(),
                num(data.efc_force[r]).c_str(), num(data.efc_aref[r]).c_str(),
                num(data.efc_R[r]).c_str(), num(data.efc_D[r]).c_str());
  }
  std::printf("  (efc_pos < 0: past the stop; efc_force > 0 pushes back; efc_pos in rad or m)\n");
}

// The contacts: which geoms, how far apart, the normal, and the force in the contact's frame.
void print_contacts(const Model& model, const Data& data) {
  if (!model.contacts_possible) return;
  std::printf("\ncontacts: ncon %d\n", data.ncon);
  if (data.ncon == 0) return;
  std::printf("  %-3s %-12s %-12s %4s %12s %-38s %-26s %12s %12s\n", "#", "geom1", "geom2", "dim",
              "dist", "pos", "normal", "normal N", "friction N");
  for (int i = 0; i < data.ncon; ++i) {
    const Contact& c = data.contact[static_cast<size_t>(i)];
    const Eigen::Matrix<double, 6, 1> f = contact_force(model, data, i);
    const std::string friction = c.dim > 1 ? num(f.segment<2>(1).norm()) : "-";
    std::printf("  %-3d %-12s %-12s %4d %12s %-38s %-26s %12s %12s%s\n", i,
                label_of(model.geom_name[c.geom1], c.geom1).c_str(),
                label_of(model.geom_name[c.geom2], c.geom2).c_str(), c.dim, num(c.dist).c_str(),
                vec_text(c.pos).c_str(), vec_text(c.frame.row(0).transpose()).c_str(),
                num(f[0]).c_str(), friction.c_str(), c.exclude ? "  (in the gap: no rows)" : "");
  }
  std::printf(
      "  (dist < 0: penetration, m; normal from geom1 into geom2; forces in the contact frame as\n"
      "   mj_contactForce: the normal force pushes the geoms apart, friction N is the size of the\n"
      "   tangential force)\n");
}

// The sensors: each one's name, type and numbers (sensordata from its sensor_adr).
void print_sensors(const Model& model, const Data& data) {
  if (model.nsensor == 0) return;
  std::printf("\nsensors: %d, sensordata in MuJoCo's units (m, rad, s, N, N m)\n", model.nsensor);
  for (int s = 0; s < model.nsensor; ++s) {
    std::string values;
    for (int k = 0; k < model.sensor_dim[s]; ++k) {
      values += (k ? ", " : "") + num(data.sensordata[model.sensor_adr[s] + k]);
    }
    std::printf("  %-16s %-14s %s\n", label_of(model.sensor_name[s], s).c_str(),
                sensor_type_name(model.sensor_type[s]), values.c_str());
  }
}

void print_text(const std::string& path, const Model& model, const Data& data,
                const Evaluation& e) {
  std::printf("model %s (%s) at time %g s\n\n", model.name.c_str(), path.c_str(), data.time);

  std::printf(
      "joints: position, velocity, acceleration, and the joint forces (N m or N) that\n"
      "make up M qacc = qfrc_passive - qfrc_bias + qfrc_actuator + qfrc_constraint\n");
  std::printf("  %-12s %-7s %12s %12s %12s %12s %12s %12s %12s %12s\n", "joint", "units", "qpos",
              "qvel", "qacc_smooth", "qacc", "qfrc_bias", "qfrc_passive", "qfrc_actuator",
              "qfrc_constr.");
  // one row per dof: a free joint's three translations (with their coordinate) and a ball's or a
  // free joint's three rotations about the body axes (their quaternion is listed below the table)
  static const char* const kDofSuffix[] = {".x", ".y", ".z", ".wx", ".wy", ".wz"};
  std::string quaternions;
  for (int j = 0; j < model.njnt; ++j) {
    const JointType type = model.jnt_type[j];
    const int nv = joint_nv(type);
    for (int k = 0; k < nv; ++k) {
      const int v = model.jnt_dofadr[j] + k;
      const bool translation = type == JointType::kSlide || (type == JointType::kFree && k < 3);
      const int suffix = type == JointType::kBall ? k + 3 : k;
      const std::string label = label_of(model.jnt_name[j], j) + (nv > 1 ? kDofSuffix[suffix] : "");
      const std::string qpos =
          type == JointType::kHinge || translation ? num(data.qpos[model.jnt_qposadr[j] + k]) : "";
      std::printf("  %-12s %-7s %12s %12s %12s %12s %12s %12s %12s %12s\n", label.c_str(),
                  translation ? "m,N" : "rad,N m", qpos.c_str(), num(data.qvel[v]).c_str(),
                  num(data.qacc_smooth[v]).c_str(), num(data.qacc[v]).c_str(),
                  num(data.qfrc_bias[v]).c_str(), num(data.qfrc_passive[v]).c_str(),
                  num(data.qfrc_actuator[v]).c_str(), num(data.qfrc_constraint[v]).c_str());
    }
    if (type == JointType::kBall || type == JointType::kFree) {
      const int q = model.jnt_qposadr[j] + (type == JointType::kFree ? 3 : 0);
      quaternions += "  " + label_of(model.jnt_name[j], j) + " quaternion (w x y z) (" +
                     num(data.qpos[q]) + ", " + num(data.qpos[q + 1]) + ", " +
                     num(data.qpos[q + 2]) + ", " + num(data.qpos[q + 3]) + ")\n";
    }
  }
  std::fputs(quaternions.c_str(), stdout);

  if (model.nu > 0) {
    std::printf(
        "\nmotors: ctrl as commanded, actuator_force after clamping to ctrlrange/forcerange\n");
    std::printf("  %-10s %-10s %12s %12s %8s\n", "motor", "joint", "ctrl", "force", "units");
    for (int a = 0; a < model.nu; ++a) {
      const bool clamped = actuator_clamped(model, data, a);
      const TransmissionText target = transmission_text(model, a);
      const bool joint = std::string_view(target.kind) == "joint";
      std::printf("  %-10s %-10s %12s %12s %8s%s\n", label_of(model.actuator_name[a], a).c_str(),
                  (joint ? target.object : std::string(target.kind) + " " + target.object).c_str(),
                  num(data.ctrl[a]).c_str(), num(data.actuator_force[a]).c_str(),
                  actuator_force_units(model, a), clamped ? "  (clamped)" : "");
    }
  }

  std::printf(
      "\nbodies: frame origin xpos and centre of mass xipos (m), orientation xquat (w x y z)\n");
  for (int b = 1; b < model.nbody; ++b) {
    std::printf("  %-10s xpos %-32s xipos %-32s xquat %s\n",
                label_of(model.body_name[b], b).c_str(), vec_text(data.xpos[b]).c_str(),
                vec_text(data.xipos[b]).c_str(), vec_text(data.xquat[b]).c_str());
  }

  if (model.nsite > 0) {
    std::printf(
        "\nsites: site_xpos (m); jacp (m per unit of qvel) and jacr (rad/s per unit of qvel),\n"
        "one row per world axis x, y, z, one column per dof\n");
    for (int s = 0; s < model.nsite; ++s) {
      std::printf("  %-10s site_xpos %s\n", label_of(model.site_name[s], s).c_str(),
                  vec_text(data.site_xpos[s]).c_str());
      for (int r = 0; r < 3; ++r) {
        std::printf("  %-10s %s  %-32s %s  %s\n", "", r == 0 ? "jacp" : "    ",
                    vec_text(e.jacp.row(3 * s + r).transpose()).c_str(), r == 0 ? "jacr" : "    ",
                    vec_text(e.jacr.row(3 * s + r).transpose()).c_str());
      }
    }
  }

  std::printf(
      "\nM: joint-space inertia, full and symmetric, armature included (kg m^2 for hinges)\n");
  for (int r = 0; r < model.nv; ++r)
    std::printf("  %s\n", vec_text(data.M.row(r).transpose(), "%.6g").c_str());

  print_limit_rows(model, data);
  print_contacts(model, data);
  print_sensors(model, data);

  std::printf("\nenergy: potential %s J, kinetic %s J\n", num(data.energy[0]).c_str(),
              num(data.energy[1]).c_str());
}

}  // namespace

void declare_forward(CLI::App& command) {
  command.add_option("MODEL", "the model file (MJCF)")->type_name("FILE")->required();
  add_state_options(
      command, {"start from keyframe NAME (its qpos, qvel, ctrl; the lists below override)",
                "joint positions, nq numbers (default: qpos0)",
                "joint velocities, nv numbers (default: zeros)",
                "motor commands, nu numbers (default: zeros); clamped to ctrlrange as in MuJoCo"});
  add_value(command, "time", "SECONDS", "data.time (default: 0, or the keyframe's): what a clock "
            "sensor reads")->check(number_check());
  add_switch(command, "json",
             "one JSON object keyed by mjData's names (arrays flattened row-major)");
  command.footer(
      "Exit status: 0; 1 when the engine warned or a number came out non-finite (said on\n"
      "standard error); 2 for bad input.");
}

int cmd_forward(const Args& command_line) {
  const auto [args, path, model] = begin("forward", command_line);
  Data data(model);
  set_state_from_args(args, model, data);
  data.time = args.get_double("time", data.time);
  const Evaluation e = evaluate(model, data);
  if (args.has("json")) {
    print_json(model, data, e);
  } else {
    print_text(path, model, data, e);
  }
  // a bad state is evaluated as given, never silently: the engine's warnings, and any number
  // that came out non-finite, are said on stderr and make the exit status 1
  WarningLog warnings;
  warnings.collect(data);
  print_warnings("forward", warnings);
  const bool finite = outputs_finite(data) && e.jacp.allFinite() && e.jacr.allFinite();
  if (!finite) print_non_finite("forward");
  return warnings.count() > 0 || !finite ? kFindings : kOk;
}

}  // namespace lever::cli
