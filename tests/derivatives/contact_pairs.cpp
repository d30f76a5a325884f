// The contact geometry's derivative for the closed-form pairs beyond those of contacts.cpp's
// scenes: plane-cylinder, capsule-box (an end over a face, the middle over an edge), box-box
// (a face clipped against a face, and two edges crossing), plane-mesh (three hull vertices) and
// MPR's polytope pairs, box-mesh and mesh-mesh (a vertex on a face, an edge across an edge; MPR's
// last portal held),
// each pushing past solimp's width, the narrow phase's case held. A (the scenes have no actuator)
// under Euler, RK4 and implicit against centred differences of lever's own step (eps 1e-6) and of
// MuJoCo 2.2.2's mj_step at tolerance 0 (eps 1e-6 and 1e-5; step_differences.hpp), within 1e-6 of
// the matrix's scale, computed both ways here.
#include <catch2/catch.hpp>
#include <lever/diff/twin.hpp>

#include <lever/derivatives.hpp>
#include <lever/lever.hpp>
#include <lever/mjcf.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <lever/harness/models.hpp>
#include "step_differences.hpp"

namespace lever::test::contact_pair_derivatives {

namespace {

using namespace lever::test::step_differences;

// One free body over a static geom, written for both engines to compile.
struct PairScene {
  std::string name;
  std::string asset;  // a mesh's vertices
  std::string below;  // the static geom
  std::string body;   // the free body's attributes and geom
  int contacts;       // the contacts the narrow phase finds at the state
  bool across_edge;   // the normal is none of the static geom's face normals (an edge's case)
  bool settle = false;  // come to rest first, then pressed 3 mm down
  bool press = false;   // its lowest mesh vertex put 3 mm below the static geom's top (z 0.05)
  int rows = 4;         // the pyramid rows that push per contact, at least
  double top = 0.05;    // the static geom's top, for press
};

std::string pair_scene_file(const PairScene& scene) {
  const std::string file =
      (std::filesystem::temp_directory_path() / ("lever_pair_" + scene.name + ".xml")).string();
  std::ofstream(file) << "<mujoco model=\"" << scene.name << "\"><option timestep=\"0.002\"/>"
                      << scene.asset << "<worldbody>" << scene.below << "<body " << scene.body
                      << "</body></worldbody></mujoco>";
  return file;
}

// The state with the free mesh geom (geom 1) lowered until its lowest vertex is 3 mm below the
// static geom's top, at height `top`.
State pressed_mesh(const Model& model, State s, double top) {
  Data data(model);
  apply(s, data);
  kinematics(model, data);
  const int mesh = model.geom_dataid[1];
  double lowest = 1e300;
  for (int k = 0; k < model.mesh_vertnum[mesh]; ++k) {
    const Eigen::Vector3d x = data.geom_xpos[1] +
                              data.geom_xmat[1] * model.mesh_vert[model.mesh_vertadr[mesh] + k];
    lowest = std::min(lowest, x[2]);
  }
  s.qpos[2] -= lowest - (top - 0.003);
  return s;
}

// The rows that push, the contacts, and the largest |cosine| between the first contact's normal
// and the static geom's (geom 0's) axes: 1 where a face of it holds the contact.
int pushing_rows(const Model& model, const State& s, int& contacts, double& face_alignment) {
  Data data(model);
  apply(s, data);
  forward(model, data);
  contacts = data.ncon;
  face_alignment = 0;
  for (int k = 0; k < 3 && data.ncon > 0; ++k) {
    const double c = data.contact[0].frame.row(0).dot(data.geom_xmat[0].col(k).transpose());
    face_alignment = std::max(face_alignment, std::abs(c));
  }
  int n = 0;
  for (int r = 0; r < data.nefc; ++r) {
    n += data.efc_dof[r] < 0 && data.efc_state[r] == ConstraintState::kActive;
  }
  return n;
}

}  // namespace

TEST_CASE("derivatives with contacts: plane-cylinder, capsule-box and box-box geometry",
          "[derivatives][mujoco][contacts]") {
  // heights: each pushes 2 to 4 mm in (past solimp's width, 1 mm), box-box's face path reports
  // half of that
  const PairScene scenes[] = {
      {"cylinder_upright", "", "<geom type=\"plane\" size=\"1 1 0.1\"/>",
       "pos=\"0 0 0.027\" euler=\"1.2 0.6 0\"><freejoint/>"
       "<geom type=\"cylinder\" size=\"0.05 0.03\" mass=\"1\"/>",
       3, false},
      {"cylinder_lying", "", "<geom type=\"plane\" size=\"1 1 0.1\"/>",
       "pos=\"0 0 0.047\" euler=\"90 0.5 20\"><freejoint/>"
       "<geom type=\"cylinder\" size=\"0.05 0.04\" mass=\"1\"/>",
       2, false},
      {"capsule_on_face", "", "<geom type=\"box\" size=\"0.2 0.2 0.05\"/>",
       "pos=\"0.02 0.01 0.068\" euler=\"0 89 10\"><freejoint/>"
       "<geom type=\"capsule\" size=\"0.02 0.05\" mass=\"1\"/>",
       2, false},
      {"capsule_over_edge", "", "<geom type=\"box\" size=\"0.2 0.2 0.05\"/>",
       "pos=\"0.2 0.01 0.0678\" euler=\"5 100 0\"><freejoint/>"
       "<geom type=\"capsule\" size=\"0.02 0.05\" mass=\"1\"/>",
       1, true},
      {"box_on_face", "", "<geom type=\"box\" size=\"0.2 0.2 0.05\"/>",
       "pos=\"0.01 0.02 0.077\" euler=\"0.5 -0.3 30\"><freejoint/>"
       "<geom type=\"box\" size=\"0.03 0.04 0.03\" mass=\"1\"/>",
       4, false},
      {"box_edges_crossing", "", "<geom type=\"box\" size=\"0.05 0.05 0.05\" euler=\"45 0 0\"/>",
       "pos=\"0.002 0.001 0.1243\" euler=\"0 45 3\"><freejoint/>"
       "<geom type=\"box\" size=\"0.04 0.04 0.04\" mass=\"1\"/>",
       1, true},
      {"mesh_on_plane",
       "<asset><mesh name=\"rock\" vertex=\"-0.04 -0.03 -0.02  0.05 -0.035 -0.025  "
       "0.045 0.04 -0.02  -0.035 0.03 -0.03  -0.03 -0.02 0.03  0.04 -0.03 0.02  "
       "0.03 0.035 0.025  -0.04 0.02 0.02\"/></asset>",
       "<geom type=\"plane\" size=\"1 1 0.1\"/>",
       "pos=\"0 0 0.06\" euler=\"4 -3 10\"><freejoint/><geom type=\"mesh\" mesh=\"rock\" "
       "mass=\"1\"/>",
       3, false, true},
      // MPR's pairs of two polytopes (one contact each: multiccd off): the rock's lowest vertex
      // pressed 3 mm into a box's top face (box-mesh), and into a slab that is a mesh
      // (mesh-mesh)
      {"mesh_on_box",
       "<asset><mesh name=\"rock\" vertex=\"-0.04 -0.03 -0.02  0.05 -0.035 -0.025  "
       "0.045 0.04 -0.02  -0.035 0.03 -0.03  -0.03 -0.02 0.03  0.04 -0.03 0.02  "
       "0.03 0.035 0.025  -0.04 0.02 0.02\"/></asset>",
       "<geom type=\"box\" size=\"0.2 0.2 0.05\"/>",
       "pos=\"0.01 0.02 0.078\" euler=\"4 -3 10\"><freejoint/>"
       "<geom type=\"mesh\" mesh=\"rock\" mass=\"1\"/>",
       1, false, false, true, 2},
      {"mesh_on_mesh",
       "<asset><mesh name=\"rock\" vertex=\"-0.04 -0.03 -0.02  0.05 -0.035 -0.025  "
       "0.045 0.04 -0.02  -0.035 0.03 -0.03  -0.03 -0.02 0.03  0.04 -0.03 0.02  "
       "0.03 0.035 0.025  -0.04 0.02 0.02\"/><mesh name=\"slab\" vertex=\"-0.2 -0.2 -0.05  "
       "0.2 -0.2 -0.05  0.2 0.2 -0.05  -0.2 0.2 -0.05  -0.2 -0.2 0.05  0.2 -0.2 0.05  "
       "0.2 0.2 0.05  -0.2 0.2 0.05\"/></asset>",
       "<geom type=\"mesh\" mesh=\"slab\"/>",
       "pos=\"0.01 0.02 0.078\" euler=\"4 -3 10\"><freejoint/>"
       "<geom type=\"mesh\" mesh=\"rock\" mass=\"1\"/>",
       1, false, false, true, 2},
      // a bar's edge across a box's edge (a box turned 45 degrees about x: its ridge along x),
      // the bar turned 45 degrees about y and 3 about the world's z, so that its lowest edge is
      // level
      {"mesh_edge_across_edge",
       "<asset><mesh name=\"bar\" vertex=\"-0.04 -0.05 -0.03  0.04 -0.05 -0.03  "
       "0.04 0.05 -0.03  -0.04 0.05 -0.03  -0.04 -0.05 0.03  0.04 -0.05 0.03  "
       "0.04 0.05 0.03  -0.04 0.05 0.03\"/></asset>",
       "<geom type=\"box\" size=\"0.05 0.05 0.05\" euler=\"45 0 0\"/>",
       "pos=\"-0.006 0.003 0.125\" quat=\"0.923563 -0.010017 0.382552 0.024184\">"
       "<freejoint/><geom type=\"mesh\" mesh=\"bar\" mass=\"1\"/>",
       1, true, false, true, 2, 0.0707106781186548},
  };
  for (const PairScene& scene : scenes) {
    for (const Integrator integrator :
         {Integrator::kEuler, Integrator::kRK4, Integrator::kImplicit}) {
      diff::Twin twin(pair_scene_file(scene), diff::Path::kEngine);
      twin.set_integrator(integrator);
      converge(twin);
      const Model& model = twin.model;
      INFO(scene.name << ", " << integrator_name(integrator));
      State s = state_of(model);
      if (scene.settle) {
        s = settle(model, s, 400);
        s.qpos[2] -= 0.003;
      }
      if (scene.press) s = pressed_mesh(model, s, scene.top);
      s.qvel << 0.01, -0.02, 0.005, 0.1, -0.05, 0.2;
      int contacts = 0;
      double face_alignment = 0;
      const int pushing = pushing_rows(model, s, contacts, face_alignment);
      CHECK(contacts == scene.contacts);
      if (scene.across_edge) {
        CHECK(face_alignment < 0.999);
      } else {
        CHECK(face_alignment > 1 - 1e-12);
      }
      REQUIRE(pushing >= scene.rows * contacts);
      Derivatives deriv(model);
      Data data(model);
      apply(s, data);
      step_derivatives(model, data, deriv);
      const Differences own = lever_differences(model, s, 1e-6);
      REQUIRE(own.same_active_set);
      CHECK(ratio_to_bound(deriv.A, own.A) <= 1);
      double worst = ratio_to_bound(deriv.A, own.A);
      for (const double eps : {1e-6, 1e-5}) {
        const Differences theirs = mujoco_differences(twin, s, eps);
        const double a = ratio_to_bound(deriv.A, theirs.A);
        INFO("eps " << eps << ": A " << a << " of the bound");
        CHECK(a <= 1);
        worst = std::max(worst, a);
      }
      UNSCOPED_INFO(scene.name << ", " << integrator_name(integrator) << ": worst " << worst
                               << " of the bound");
    }
  }
}

}  // namespace lever::test::contact_pair_derivatives
