// The contact geometry's derivative for the pairs MuJoCo collides by MPR (libccd's search on the
// two support functions), against centred differences of lever's own step (eps 1e-6) and of
// MuJoCo 2.2.2's mj_step at tolerance 0 (eps 1e-6 and 1e-5; step_checks.hpp), within 1e-6 of the
// matrix's scale, A under Euler, RK4 and implicit (B too on the mesh gripper).
//
// A face on a face (box-mesh and mesh-mesh at margin 0): the answer is a closed form of the last
// portal's three support points, and the point depends on which triangle of the two faces'
// Minkowski face the portal is, so the portal the search ended on is held: a slab mesh lying
// turned on a box's face and on a slab mesh's, and bench/scenes/mesh_gripper.xml's finger meshes
// holding the box. A round geom or a margin: the support points move with the search's
// directions, and the whole search is replayed on dual numbers, its decisions held: a sphere, a
// capsule, a tilted cylinder and an ellipsoid on a box mesh, an ellipsoid and a tilted cylinder on
// a box, a cylinder on a capsule, an ellipsoid on a sphere, and a rock mesh on a box and on a box
// mesh with margins. Where the portal or the search's path flips with the direction of a motion
// (the slab with its edges along the box's; a cylinder on a sphere at a state where a support
// point changes sides), the derivative is refused by name, and MuJoCo's own differences at eps
// 1e-7 and 1e-6 show why: they disagree by a thousand times the bound. And multiccd's extra
// contacts, each the search run again with the geoms turned about the first contact's tangents
// (which move with it): a tilted slab mesh and a tilted cylinder on a box.
#include <catch2/catch.hpp>
#include <lever/diff/twin.hpp>

#include <lever/derivatives.hpp>
#include <lever/lever.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <lever/harness/models.hpp>
#include "step_checks.hpp"

namespace lever::test::mpr_pairs {

namespace {

using namespace lever::test::step_differences;

constexpr Integrator kIntegrators[] = {Integrator::kEuler, Integrator::kRK4,
                                       Integrator::kImplicit};

// bench/scenes/mesh_gripper.xml with its meshes read from lever::test::robots_dir()
std::string gripper_file() {
  std::ifstream in(source_dir() + "/bench/scenes/mesh_gripper.xml");
  std::stringstream text;
  text << in.rdbuf();
  std::string xml = text.str();
  const std::string beside_checkout = "../../../shared/robots";
  const std::size_t at = xml.find(beside_checkout);
  REQUIRE(at != std::string::npos);
  xml.replace(at, beside_checkout.size(), robots_dir());
  const std::string file =
      (std::filesystem::temp_directory_path() / "lever_face_mesh_gripper.xml").string();
  std::ofstream(file) << xml;
  return file;
}

// A 6 x 4 x 2 cm slab mesh (a free body) lying on a static box's top face (z 0.05), or on a
// static slab mesh's, turned by yaw degrees about z, its bottom face 3 mm into the top.
std::string slab_file(const std::string& name, double yaw, bool on_mesh) {
  const std::string file =
      (std::filesystem::temp_directory_path() / ("lever_face_" + name + ".xml")).string();
  std::ofstream(file)
      << "<mujoco model=\"" << name << "\"><option timestep=\"0.002\"/><asset>"
      << "<mesh name=\"slab\" vertex=\"-0.03 -0.02 -0.01  0.03 -0.02 -0.01  0.03 0.02 -0.01  "
         "-0.03 0.02 -0.01  -0.03 -0.02 0.01  0.03 -0.02 0.01  0.03 0.02 0.01  -0.03 0.02 0.01\"/>"
      << "<mesh name=\"table\" vertex=\"-0.2 -0.2 -0.05  0.2 -0.2 -0.05  0.2 0.2 -0.05  "
         "-0.2 0.2 -0.05  -0.2 -0.2 0.05  0.2 -0.2 0.05  0.2 0.2 0.05  -0.2 0.2 0.05\"/>"
      << "</asset><worldbody>"
      << (on_mesh ? "<geom type=\"mesh\" mesh=\"table\"/>"
                  : "<geom type=\"box\" size=\"0.2 0.2 0.05\"/>")
      << "<body pos=\"0.01 0.02 0.057\" euler=\"0 0 " << yaw
      << "\"><freejoint/><geom type=\"mesh\" mesh=\"slab\" mass=\"1\"/></body></worldbody>"
      << "</mujoco>";
  return file;
}

State moving(const Model& model) {
  State s = state_of(model);
  s.qvel << 0.001, -0.002, 0.0005, 0.01, -0.005, 0.02;
  return s;
}

// Whether contact i's normal is a face normal of both its geoms (an axis of a box, a mesh's face:
// the mesh's vertices farthest along it, at least three). A geometric test of the scene, not a
// comparison with MuJoCo: 1e-9 is far above a rotated unit vector's rounding (1e-16) and far below
// any tilt the scenes are built with (a face is level, or turned by a degree or more).
bool face_on_face(const Model& model, const Data& data, int i) {
  const Contact& c = data.contact[static_cast<std::size_t>(i)];
  const auto face = [&](int g, const Eigen::Vector3d& up) {
    if (model.geom_type[g] == GeomType::kBox) {
      const Eigen::Vector3d local = data.geom_xmat[g].transpose() * up;
      return local.cwiseAbs().maxCoeff() > 1 - 1e-9;
    }
    const int mesh = model.geom_dataid[g];
    double top = -1e300;
    for (int k = 0; k < model.mesh_vertnum[mesh]; ++k) {
      const Eigen::Vector3d& vertex = model.mesh_vert[model.mesh_vertadr[mesh] + k];
      top = std::max(top, up.dot(data.geom_xmat[g] * vertex));
    }
    int on_top = 0;
    for (int k = 0; k < model.mesh_vertnum[mesh]; ++k) {
      on_top += up.dot(data.geom_xmat[g] * model.mesh_vert[model.mesh_vertadr[mesh] + k]) >
                top - 1e-9;
    }
    return on_top >= 3;
  };
  const Eigen::Vector3d n = c.frame.row(0).transpose();
  return face(c.geom1, n) && face(c.geom2, -n);
}

}  // namespace

TEST_CASE("derivatives with contacts: a face on a face (MPR's last portal held)",
          "[derivatives][mujoco][contacts]") {
  struct Slab {
    std::string name;
    double yaw;
    bool on_mesh;
  };
  for (const Slab& slab : {Slab{"slab_on_box", 30, false}, Slab{"slab_on_slab", 30, true}}) {
    for (const Integrator integrator : kIntegrators) {
      diff::Twin twin(slab_file(slab.name, slab.yaw, slab.on_mesh), diff::Path::kEngine);
      twin.set_integrator(integrator);
      converge(twin);
      INFO(slab.name);
      const State s = moving(twin.model);
      Data data(twin.model);
      apply(s, data);
      forward(twin.model, data);
      REQUIRE(data.ncon == 1);
      CHECK(face_on_face(twin.model, data, 0));
      CHECK(data.contact[0].dist < -0.0029);  // past solimp's width: the impedance is flat
      // (the slab springs out of the box within the step, so the flag may be set: the step's
      // start is what Euler and implicit differentiate, and RK4's stages are held as they are)
      Derivatives deriv(twin.model);
      apply(s, data);
      step_derivatives(twin.model, data, deriv);
      const double worst = check_against_differences(twin, s, deriv, false);
      UNSCOPED_INFO(slab.name << ", " << integrator_name(integrator) << ": worst " << worst
                              << " of the bound");
      CHECK(worst <= 1);
    }
  }
}

TEST_CASE("derivatives with contacts: the mesh gripper's finger pads holding the box",
          "[derivatives][mujoco][contacts]") {
  const std::string file = gripper_file();
  for (const Integrator integrator : kIntegrators) {
    diff::Twin twin(file, diff::Path::kEngine);
    twin.set_integrator(integrator);
    converge(twin);
    const Model& model = twin.model;
    // closed on the box from the keyframe (the servos' targets 5 mm, inside ctrlrange), then the
    // fingers pressed 1.5 mm further in and the box 1.2 mm into the table, every contact past
    // solimp's width (1 mm), where the impedance is flat (within it, its curvature puts the
    // differences' truncation at 0.3 of the bound at eps 1e-6 and 30 at 1e-5, measured)
    State s = state_of(model);
    for (int i = 0; i < model.nq; ++i) s.qpos[i] = model.key_qpos(0, i);
    s.ctrl.setConstant(0.005);
    s = settle(model, s, 300);
    s.qpos[0] -= 0.0015;
    s.qpos[1] -= 0.0015;
    s.qpos[4] -= 0.0012;
    Data data(model);
    apply(s, data);
    forward(model, data);
    int fingers = 0;
    for (int i = 0; i < data.ncon; ++i) {
      const Contact& c = data.contact[static_cast<std::size_t>(i)];
      if (model.geom_type[c.geom1] == GeomType::kBox &&
          model.geom_type[c.geom2] == GeomType::kMesh) {
        ++fingers;
      }
      CHECK(c.dist < -0.001);
    }
    REQUIRE(fingers == 2);
    const double worst = check_step_derivatives(twin, s);
    UNSCOPED_INFO("mesh gripper, " << integrator_name(integrator) << ": worst " << worst
                                   << " of the bound");
    CHECK(worst <= 1);
  }
}

TEST_CASE("derivatives with contacts: a face on a face whose portal flips is refused",
          "[derivatives][mujoco][contacts]") {
  // the slab's edges along the box's: MPR's portal at the state is one of two triangles, and the
  // other for either sign of a turn; MuJoCo's differences at eps 1e-7 and 1e-6 disagree
  diff::Twin twin(slab_file("slab_aligned", 0, false), diff::Path::kEngine);
  converge(twin);
  const State s = moving(twin.model);
  Derivatives deriv(twin.model);
  Data data(twin.model);
  apply(s, data);
  CHECK_THROWS_WITH(step_derivatives(twin.model, data, deriv),
                    Catch::Contains("ends on a portal that changes"));
  const Differences fine = mujoco_differences(twin, s, 1e-7);
  const Differences coarse = mujoco_differences(twin, s, 1e-6);
  CHECK(ratio_to_bound(fine.A, coarse.A) > 1e3);
}

namespace {

// A free body (its attributes and geom) over a static geom, written for both engines to compile.
std::string round_pair_file(const std::string& name, const std::string& below,
                            const std::string& body, bool multiccd = false) {
  const std::string file =
      (std::filesystem::temp_directory_path() / ("lever_mpr_" + name + ".xml")).string();
  std::ofstream(file)
      << "<mujoco model=\"" << name << "\"><option timestep=\"0.002\">"
      << (multiccd ? "<flag multiccd=\"enable\"/>" : "") << "</option><asset>"
      << "<mesh name=\"slab\" vertex=\"-0.03 -0.02 -0.01  0.03 -0.02 -0.01  0.03 0.02 -0.01  "
         "-0.03 0.02 -0.01  -0.03 -0.02 0.01  0.03 -0.02 0.01  0.03 0.02 0.01  -0.03 0.02 0.01\"/>"
      << "<mesh name=\"table\" vertex=\"-0.2 -0.2 -0.05  0.2 -0.2 -0.05  0.2 0.2 -0.05  "
         "-0.2 0.2 -0.05  -0.2 -0.2 0.05  0.2 -0.2 0.05  0.2 0.2 0.05  -0.2 0.2 0.05\"/>"
      << "<mesh name=\"rock\" vertex=\"-0.04 -0.03 -0.02  0.05 -0.035 -0.025  "
         "0.045 0.04 -0.02  -0.035 0.03 -0.03  -0.03 -0.02 0.03  0.04 -0.03 0.02  "
         "0.03 0.035 0.025  -0.04 0.02 0.02\"/></asset><worldbody>"
      << below << "<body " << body << "</body></worldbody></mujoco>";
  return file;
}

struct RoundPair {
  std::string name, below, body;
};

const std::string kTableMesh = "<geom type=\"mesh\" mesh=\"table\"/>";
const std::string kBox = "<geom type=\"box\" size=\"0.2 0.2 0.05\"/>";
const std::string kCylinder = "<freejoint/><geom type=\"cylinder\" size=\"0.03 0.04\" mass=\"1\"/>";
const std::string kEllipsoid =
    "<freejoint/><geom type=\"ellipsoid\" size=\"0.04 0.035 0.03\" mass=\"1\"/>";

}  // namespace

TEST_CASE("derivatives with contacts: a round geom or a margin (MPR's search replayed)",
          "[derivatives][mujoco][contacts]") {
  // each pressed 2 to 14 mm in, past solimp's width (1 mm): the impedance is flat
  const RoundPair pairs[] = {
      {"sphere_on_mesh", kTableMesh,
       "pos=\"0.01 0.02 0.077\"><freejoint/><geom type=\"sphere\" size=\"0.03\" mass=\"1\"/>"},
      {"capsule_on_mesh", kTableMesh,
       "pos=\"0.01 0.02 0.067\" euler=\"0 89 10\"><freejoint/>"
       "<geom type=\"capsule\" size=\"0.02 0.05\" mass=\"1\"/>"},
      {"cylinder_on_mesh", kTableMesh, "pos=\"0.01 0.02 0.0842\" euler=\"20 10 0\">" + kCylinder},
      {"ellipsoid_on_mesh", kTableMesh, "pos=\"0.01 0.02 0.077\" euler=\"10 5 20\">" + kEllipsoid},
      {"cylinder_on_box", kBox, "pos=\"0.01 0.02 0.0842\" euler=\"20 10 0\">" + kCylinder},
      {"ellipsoid_on_box", kBox, "pos=\"0.01 0.02 0.077\" euler=\"10 5 20\">" + kEllipsoid},
      {"cylinder_on_capsule", "<geom type=\"capsule\" size=\"0.05 0.1\" euler=\"0 90 0\"/>",
       "pos=\"0.01 0.02 0.077\" euler=\"90 3 40\">" + kCylinder},
      {"ellipsoid_on_sphere", "<geom type=\"sphere\" size=\"0.05\"/>",
       "pos=\"0.01 0.02 0.0745\" euler=\"10 5 20\">" + kEllipsoid},
      {"rock_on_box_margin", "<geom type=\"box\" size=\"0.2 0.2 0.05\" margin=\"0.002\"/>",
       "pos=\"0.01 0.02 0.078\" euler=\"4 -3 10\"><freejoint/>"
       "<geom type=\"mesh\" mesh=\"rock\" mass=\"1\" margin=\"0.002\"/>"},
      {"rock_on_mesh_margin", "<geom type=\"mesh\" mesh=\"table\" margin=\"0.002\"/>",
       "pos=\"0.01 0.02 0.078\" euler=\"4 -3 10\"><freejoint/>"
       "<geom type=\"mesh\" mesh=\"rock\" mass=\"1\" margin=\"0.002\"/>"},
  };
  for (const RoundPair& pair : pairs) {
    const std::string file = round_pair_file(pair.name, pair.below, pair.body);
    for (const Integrator integrator : kIntegrators) {
      diff::Twin twin(file, diff::Path::kEngine);
      twin.set_integrator(integrator);
      converge(twin);
      INFO(pair.name);
      const State s = moving(twin.model);
      Data data(twin.model);
      apply(s, data);
      forward(twin.model, data);
      REQUIRE(data.ncon == 1);
      REQUIRE(collides_by_mpr(twin.model.geom_type[data.contact[0].geom1],
                              twin.model.geom_type[data.contact[0].geom2]));
      const double margin = twin.model.geom_margin[data.contact[0].geom1];
      CHECK(data.contact[0].dist - margin < -0.002);
      Derivatives deriv(twin.model);
      apply(s, data);
      step_derivatives(twin.model, data, deriv);
      const double worst = check_against_differences(twin, s, deriv, false);
      UNSCOPED_INFO(pair.name << ", " << integrator_name(integrator) << ": worst " << worst
                              << " of the bound");
      CHECK(worst <= 1);
    }
  }
}

TEST_CASE("derivatives with contacts: multiccd's extra contacts (searches turned about the first)",
          "[derivatives][mujoco][contacts]") {
  // a slab mesh tilted half a degree on a box's face (two contacts: the first and a turned
  // search's) and a cylinder tilted on its rim (three)
  const RoundPair pairs[] = {
      {"slab_tilted_multiccd", kBox,
       "pos=\"0.01 0.02 0.057\" euler=\"0.5 0.3 30\"><freejoint/>"
       "<geom type=\"mesh\" mesh=\"slab\" mass=\"1\"/>"},
      {"cylinder_multiccd", kBox, "pos=\"0.01 0.02 0.0842\" euler=\"20 10 0\">" + kCylinder},
  };
  const int contacts[] = {2, 3};
  for (int p = 0; p < 2; ++p) {
    const RoundPair& pair = pairs[p];
    const std::string file = round_pair_file(pair.name, pair.below, pair.body, true);
    for (const Integrator integrator : kIntegrators) {
      diff::Twin twin(file, diff::Path::kEngine);
      twin.set_integrator(integrator);
      converge(twin);
      INFO(pair.name);
      const State s = moving(twin.model);
      Data data(twin.model);
      apply(s, data);
      forward(twin.model, data);
      REQUIRE(data.ncon == contacts[p]);
      Derivatives deriv(twin.model);
      apply(s, data);
      step_derivatives(twin.model, data, deriv);
      const double worst = check_against_differences(twin, s, deriv, false);
      UNSCOPED_INFO(pair.name << ", " << integrator_name(integrator) << ": worst " << worst
                              << " of the bound");
      CHECK(worst <= 1);
    }
  }
}

TEST_CASE("derivatives with contacts: an MPR search whose path flips is refused",
          "[derivatives][mujoco][contacts]") {
  // a cylinder lying across a sphere, at a state where a support point of the search changes
  // sides with the direction of a motion
  diff::Twin twin(round_pair_file("cylinder_on_sphere", "<geom type=\"sphere\" size=\"0.05\"/>",
                                  "pos=\"0.01 0.02 0.077\" euler=\"90 3 40\">" + kCylinder),
                  diff::Path::kEngine);
  converge(twin);
  const State s = moving(twin.model);
  Derivatives deriv(twin.model);
  Data data(twin.model);
  apply(s, data);
  CHECK_THROWS_WITH(step_derivatives(twin.model, data, deriv),
                    Catch::Contains("(sphere-cylinder, MPR) is where MPR's search changes"));
  const Differences fine = mujoco_differences(twin, s, 1e-7);
  const Differences coarse = mujoco_differences(twin, s, 1e-6);
  CHECK(ratio_to_bound(fine.A, coarse.A) > 1e3);
}

}  // namespace lever::test::mpr_pairs

