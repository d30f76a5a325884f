// (4) Inertia claims: each body's explicit mass and principal moments beside those MuJoCo would
// infer from its geoms (density 1000), the gravity torque that makes at each joint's worst pose,
// bodies whose mass came from geoms, non-colliding geoms that add mass, and the lesson's
// demonstration that a visual-only geom adds mass unless its group is outside inertiagrouprange.
#include <lever/data.hpp>
#include <lever/dynamics.hpp>
#include <lever/kinematics.hpp>
#include <lever/mjcf.hpp>

#include <lever/check.hpp>
#include "util.hpp"

namespace lever::check {

namespace {

// A body with a 1 kg colliding box and a 2 kg non-colliding sphere in group 3.
std::string demo_xml(const std::string& compiler_attributes) {
  return "<mujoco model=\"visual_geom_mass\"><compiler" + compiler_attributes +
         "/><worldbody><body name=\"b\"><joint type=\"slide\" axis=\"0 0 1\"/>"
         "<geom type=\"box\" size=\"0.05 0.05 0.05\" mass=\"1\"/>"
         "<geom type=\"sphere\" size=\"0.05\" mass=\"2\" contype=\"0\" conaffinity=\"0\" "
         "group=\"3\"/>"
         "</body></worldbody></mujoco>";
}

void run_demo(Inertia& result) {
  const Model wide = mjcf::load_string(demo_xml(""), "visual_geom_mass");
  const Model narrow =
      mjcf::load_string(demo_xml(" inertiagrouprange=\"0 2\""), "visual_geom_mass");
  result.demo_default_mass = wide.body_mass[1];
  result.demo_default_range = wide.compiler.inertiagrouprange;
  result.demo_narrow_mass = narrow.body_mass[1];
  result.demo_narrow_range = narrow.compiler.inertiagrouprange;
}

bool collides(const Model& model, int g) {
  return model.geom_contype[g] != 0 || model.geom_conaffinity[g] != 0;
}

// Geoms that do not collide yet count towards their body's mass.
void find_visual_mass(const Model& model, Inertia& result) {
  const auto range = model.compiler.inertiagrouprange;
  for (int g = 0; g < model.ngeom; ++g) {
    const int b = model.geom_bodyid[g];
    const bool counted = b > 0 && !model.body_explicit_inertial[b] &&
                         model.compiler.inertia_from_geoms_allowed &&
                         model.geom_group[g] >= range[0] && model.geom_group[g] <= range[1];
    if (counted && !collides(model, g) && model.geom_mass[g] > 0) {
      result.visual_mass.push_back(
          {geom_label(model, g), body_label(model, b), model.geom_group[g], model.geom_mass[g]});
    }
  }
}

double gravity_torque(const Model& model, const Eigen::VectorXd& q, int dof) {
  Data data(model);
  data.qpos = q;
  kinematics(model, data);
  bias(model, data);
  return data.qfrc_bias[dof];
}

}  // namespace

Inertia check_inertia(const Inputs& inputs, const TorqueBudget& budget) {
  const Model& model = inputs.model;
  Inertia result;
  result.inertiagrouprange = model.compiler.inertiagrouprange;
  result.inferred_available = inputs.inferred != nullptr;
  result.inferred_error = inputs.inferred_error;
  for (int b = 1; b < model.nbody; ++b) {
    BodyInertia body;
    body.name = body_label(model, b);
    body.explicit_inertial = model.body_explicit_inertial[b];
    body.mass = model.body_mass[b];
    body.principal = sorted_moments(model.body_inertia[b]);
    if (inputs.inferred) {
      body.inferred_mass = inputs.inferred->body_mass[b];
      body.inferred_principal = sorted_moments(inputs.inferred->body_inertia[b]);
    }
    result.bodies.push_back(body);
    if (!body.explicit_inertial && body.mass > 0)
      result.bodies_without_inertial.push_back(body.name);
  }
  // at each joint's worst pose from (3), which a model with ball or free joints skips
  if (inputs.inferred && static_cast<int>(budget.joints.size()) == model.njnt) {
    for (int j = 0; j < model.njnt; ++j) {
      const JointBudget& joint = budget.joints[j];
      result.torques.push_back(
          {joint.joint, joint.worst_torque,
           gravity_torque(*inputs.inferred, joint.worst_pose, model.jnt_dofadr[j])});
    }
  }
  find_visual_mass(model, result);
  run_demo(result);
  return result;
}

}  // namespace lever::check
