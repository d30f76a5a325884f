// Where a closed-form pair's answer turns faster than its first order: an upright cylinder's disc
// flat on a plane. MuJoCo's mjc_PlaneCylinder puts its contacts on the rim along the direction of
// the axis's tilt, normalised from the tilt's sine (the cylinder's x axis at no tilt at all), so
// at a tilt of 1e-9, or none (a cylinder come to rest), a motion of 1e-8 swings them round the
// rim: lever's own differences at eps 1e-7 and 1e-6 disagree by hundreds to millions of times the
// bound, and the derivative is refused by name. A cylinder tilted by 0.2 rad (one contact) and by
// 0.01 rad (three) is differentiated and agrees with lever's and MuJoCo 2.2.2's differences;
// tests/diff/contact_scenes/free_objects.xml at rest is refused for its upright can, and without
// the can (boxes flat on the table, a capsule on its end, a ball, an egg) agrees. The other
// closed-form pairs' flat cases are smooth where the contacts are held points (a box's corners
// on a plane or inside a larger face, a capsule's ends lying on a plane or a face, a lying
// cylinder's two discs) and agree; a box face on an equal box face (corners on corners) is
// refused.
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
#include "step_checks.hpp"

namespace lever::test::flat_discs {

namespace {

using namespace lever::test::step_differences;

// A free body (its attributes and geom, angles in radians) over a static geom, written for both
// engines to compile.
std::string scene_file(const std::string& name, const std::string& below,
                       const std::string& body) {
  const std::string file =
      (std::filesystem::temp_directory_path() / ("lever_flat_" + name + ".xml")).string();
  std::ofstream(file) << "<mujoco model=\"" << name << "\"><compiler angle=\"radian\"/>"
                      << "<option timestep=\"0.002\"/><worldbody>" << below << "<body " << body
                      << "</body></worldbody></mujoco>";
  return file;
}

const std::string kPlane = "<geom type=\"plane\" size=\"1 1 0.1\" margin=\"0.002\"/>";
const std::string kTable = "<geom type=\"box\" size=\"0.2 0.2 0.05\"/>";

// A cylinder (radius 5 cm, half-length 3 cm) over the plane, tilted by `tilt` rad about x and
// turned 0.5 rad about its axis, its lowest rim point at `lowest`.
std::string cylinder_file(const std::string& name, double tilt, double lowest) {
  const double z = lowest + 0.03 * std::cos(tilt) + 0.05 * std::sin(tilt);
  return scene_file(name, kPlane,
                    "pos=\"0 0 " + std::to_string(z) + "\" euler=\"" + std::to_string(tilt) +
                        " 0 0.5\"><freejoint/><geom type=\"cylinder\" size=\"0.05 0.03\" "
                        "mass=\"1\"/>");
}

// free_objects.xml, without its can where `can` is false
std::string free_objects_file(bool can) {
  std::string xml = read_text(source_dir() + "/tests/diff/contact_scenes/free_objects.xml");
  if (!can) {
    const std::size_t from = xml.find("<body name=\"can\"");
    REQUIRE(from != std::string::npos);
    const std::string close = "</body>";
    xml.erase(from, xml.find(close, from) + close.size() - from);
  }
  const std::string file = (std::filesystem::temp_directory_path() /
                            (can ? "lever_flat_free_objects.xml" : "lever_flat_no_can.xml"))
                               .string();
  std::ofstream(file) << xml;
  return file;
}

State moving(const Model& model) {
  State s = state_of(model);
  s.qvel << 0.01, -0.02, 0.005, 0.1, -0.05, 0.2;
  return s;
}

// How far apart lever's own differences at eps 1e-7 and 1e-6 are, in bounds: about 1 where the
// step is smooth at their reach (1e-7's rounding), far more where it is not.
double differences_apart(const Model& model, const State& s) {
  const Differences fine = lever_differences(model, s, 1e-7);
  const Differences coarse = lever_differences(model, s, 1e-6);
  return ratio_to_bound(fine.A, coarse.A);
}

// The step's derivative at s refused, naming the pair; lever's own differences at eps 1e-7 and
// 1e-6 disagree by more than `apart` bounds.
void check_refused(const Model& model, const State& s, const std::string& pair, double apart) {
  Derivatives deriv(model);
  Data data(model);
  apply(s, data);
  CHECK_THROWS_WITH(step_derivatives(model, data, deriv),
                    Catch::Contains("(" + pair + ") is where the closed form's answer turns"));
  const double measured = differences_apart(model, s);
  UNSCOPED_INFO(pair << ": differences at 1e-7 and 1e-6 " << measured << " bounds apart");
  CHECK(measured > apart);
}

}  // namespace

TEST_CASE("derivatives with contacts: an upright cylinder's disc flat on a plane is refused",
          "[derivatives][contacts]") {
  // come to rest from no tilt (it stays none), and placed at a tilt of 1e-9
  Model model = mjcf::load_file(cylinder_file("flat", 0, 0.001));
  model.opt.tolerance = 0;
  const State rest = settle(model, state_of(model), 300);
  Data data(model);
  apply(rest, data);
  forward(model, data);
  REQUIRE(data.ncon == 3);
  CHECK(std::hypot(data.geom_xmat[1](0, 2), data.geom_xmat[1](1, 2)) < 1e-12);  // the tilt
  CHECK_THROWS_WITH(step_derivatives(model, data, *std::make_unique<Derivatives>(model)),
                    Catch::Contains("disc flat on the plane"));
  check_refused(model, rest, "plane-cylinder", 1e3);

  Model tilted = mjcf::load_file(cylinder_file("tilt_1e-9", 1e-9, -0.002));
  tilted.opt.tolerance = 0;
  check_refused(tilted, moving(tilted), "plane-cylinder", 1e3);
}

TEST_CASE("derivatives with contacts: cylinders tilted by 0.2 and 0.01 rad on a plane",
          "[derivatives][mujoco][contacts]") {
  for (const auto& [tilt, contacts] : {std::pair{0.2, 1}, std::pair{0.01, 3}}) {
    diff::Twin twin(cylinder_file("tilted", tilt, -0.003), diff::Path::kEngine);
    converge(twin);
    const State s = moving(twin.model);
    {
      Data data(twin.model);
      apply(s, data);
      forward(twin.model, data);
      REQUIRE(data.ncon == contacts);
    }
    for (const Integrator integrator :
         {Integrator::kEuler, Integrator::kRK4, Integrator::kImplicit}) {
      twin.set_integrator(integrator);
      INFO("tilt " << tilt);
      const double worst = check_step_derivatives(twin, s);
      UNSCOPED_INFO("tilt " << tilt << ", " << integrator_name(integrator) << ": worst " << worst
                            << " of the bound");
    }
  }
}

TEST_CASE("derivatives with contacts: free_objects at rest, its upright can refused",
          "[derivatives][mujoco][contacts]") {
  for (const bool can : {true, false}) {
    diff::Twin twin(free_objects_file(can), diff::Path::kEngine);
    converge(twin);
    const State s = settle(twin.model, state_of(twin.model), 500);
    INFO((can ? "with the can" : "without the can"));
    if (can) {
      check_refused(twin.model, s, "plane-cylinder", 1e2);
    } else {
      CHECK(differences_apart(twin.model, s) < 1);
      // the contacts rest within solimp's width: MuJoCo's eps 1e-5 differences extrapolated
      const double worst = check_step_derivatives(twin, s, true);
      UNSCOPED_INFO("free_objects without the can: worst " << worst << " of the bound");
    }
  }
}

TEST_CASE("derivatives with contacts: closed-form pairs lying flat",
          "[derivatives][mujoco][contacts]") {
  struct Flat {
    std::string name, below, body;
  };
  const std::string lying = "1.5707963267948966";
  const Flat smooth[] = {
      {"box_on_plane", kPlane,
       "pos=\"0 0 0.028\" euler=\"0 0 0.5\"><freejoint/>"
       "<geom type=\"box\" size=\"0.03 0.04 0.03\" mass=\"1\"/>"},
      {"capsule_on_plane", kPlane,
       "pos=\"0 0 0.018\" euler=\"" + lying + " 0 0.5\"><freejoint/>"
       "<geom type=\"capsule\" size=\"0.02 0.05\" mass=\"1\"/>"},
      {"cylinder_lying", kPlane,
       "pos=\"0 0 0.048\" euler=\"" + lying + " 0 0.5\"><freejoint/>"
       "<geom type=\"cylinder\" size=\"0.05 0.04\" mass=\"1\"/>"},
      {"capsule_on_face", kTable,
       "pos=\"0.01 0.02 0.068\" euler=\"0 " + lying + " 0.2\"><freejoint/>"
       "<geom type=\"capsule\" size=\"0.02 0.05\" mass=\"1\"/>"},
      {"box_on_face", kTable,
       "pos=\"0.01 0.02 0.077\"><freejoint/><geom type=\"box\" size=\"0.03 0.04 0.03\" "
       "mass=\"1\"/>"},
  };
  for (const Flat& flat : smooth) {
    diff::Twin twin(scene_file(flat.name, flat.below, flat.body), diff::Path::kEngine);
    converge(twin);
    INFO(flat.name);
    const State s = moving(twin.model);
    CHECK(differences_apart(twin.model, s) < 1);
    const double worst = check_step_derivatives(twin, s);
    UNSCOPED_INFO(flat.name << ": worst " << worst << " of the bound");
  }
  // a box's face on an equal box's face, corners on corners: which clips which turns with the
  // motion
  Model model = mjcf::load_file(
      scene_file("box_on_equal_box", "<geom type=\"box\" size=\"0.03 0.04 0.05\"/>",
                 "pos=\"0 0 0.077\"><freejoint/><geom type=\"box\" size=\"0.03 0.04 0.03\" "
                 "mass=\"1\"/>"));
  model.opt.tolerance = 0;
  check_refused(model, moving(model), "box-box", 1e3);
}

}  // namespace lever::test::flat_discs
