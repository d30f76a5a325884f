// Mass and inertia: each geom type from its solid-body formula, geoms combined about their centre
// of mass, explicit <inertial>, inertiafromgeom, inertiagrouprange, bounds and settotalmass. Every
// expected value is computed here from the textbook formula.
#include <catch2/catch.hpp>
#include <lever/mjcf.hpp>
#include <numbers>

#include <lever/harness/models.hpp>

namespace {

// Model stores flags as bytes (so that each is an array view); the expected values as such.
std::vector<uint8_t> flag_bytes(std::initializer_list<bool> values) {
  return std::vector<uint8_t>(values.begin(), values.end());
}

using lever::Model;
using std::numbers::pi;

constexpr double kDensity = 1000;  // MuJoCo's default geom density, kg/m^3

// one movable body (id 1) holding `inside`
Model jointed_body_with(const std::string& inside, const std::string& compiler = "") {
  return lever::mjcf::load_string("<mujoco>" + compiler + R"(
  <worldbody>
    <body name="b" pos="0 0 1">
      <joint/>
      )" + inside + R"(
    </body>
  </worldbody>
</mujoco>)");
}

void check_close(double ours, double expected) {
  INFO("lever " << ours << " vs formula " << expected);
  CHECK(std::abs(ours - expected) <= 1e-12 * std::max(1.0, std::abs(expected)));
}

void check_close(const Eigen::Vector3d& ours, const Eigen::Vector3d& expected) {
  for (int k = 0; k < 3; ++k) check_close(ours[k], expected[k]);
}

}  // namespace

TEST_CASE("a single geom's mass and inertia follow its solid-body formula", "[mjcf][inertia]") {
  SECTION("sphere") {
    const double r = 0.1, m = kDensity * 4.0 / 3.0 * pi * r * r * r, i = 0.4 * m * r * r;
    const Model model = jointed_body_with(R"(<geom type="sphere" size="0.1"/>)");
    check_close(model.body_mass[1], m);
    check_close(model.body_inertia[1], {i, i, i});
  }
  SECTION("box (half-sizes)") {
    const double a = 0.1, b = 0.2, c = 0.3, m = kDensity * 8 * a * b * c;
    const Model model = jointed_body_with(R"(<geom type="box" size="0.1 0.2 0.3"/>)");
    check_close(model.body_mass[1], m);
    check_close(model.body_inertia[1],
                {m * (b * b + c * c) / 3, m * (a * a + c * c) / 3, m * (a * a + b * b) / 3});
  }
  SECTION("cylinder (radius, half-length)") {
    const double r = 0.05, h = 0.4, m = kDensity * pi * r * r * h;
    const Model model = jointed_body_with(R"(<geom type="cylinder" size="0.05 0.2"/>)");
    check_close(model.body_mass[1], m);
    const double across = m * (3 * r * r + h * h) / 12;
    check_close(model.body_inertia[1], {across, across, m * r * r / 2});
  }
  SECTION("ellipsoid (semi-axes)") {
    const double a = 0.1, b = 0.2, c = 0.3, m = kDensity * 4.0 / 3.0 * pi * a * b * c;
    const Model model = jointed_body_with(R"(<geom type="ellipsoid" size="0.1 0.2 0.3"/>)");
    check_close(model.body_mass[1], m);
    check_close(model.body_inertia[1],
                {m * (b * b + c * c) / 5, m * (a * a + c * c) / 5, m * (a * a + b * b) / 5});
  }
  SECTION("capsule: a cylinder and two hemispheres") {
    const double r = 0.025, h = 0.5;
    const double cylinder = kDensity * pi * r * r * h;
    const double spheres = kDensity * 4.0 / 3.0 * pi * r * r * r;
    // each hemisphere's centre of mass is 3r/8 beyond its flat face, h/2 from the centre
    const double d = h / 2 + 3 * r / 8;
    const double hemisphere_own =
        2.0 / 5.0 * r * r * (spheres / 2) - (spheres / 2) * (3 * r / 8) * (3 * r / 8);
    const double across =
        cylinder * (3 * r * r + h * h) / 12 + 2 * (hemisphere_own + spheres / 2 * d * d);
    const double along = cylinder * r * r / 2 + 2.0 / 5.0 * spheres * r * r;
    const Model model = jointed_body_with(R"(<geom type="capsule" size="0.025 0.25"/>)");
    check_close(model.body_mass[1], cylinder + spheres);
    check_close(model.body_inertia[1], {across, across, along});
  }
}

TEST_CASE("density and mass attributes", "[mjcf][inertia]") {
  const double r = 0.1, volume = 4.0 / 3.0 * pi * r * r * r;
  check_close(jointed_body_with(R"(<geom size="0.1" density="500"/>)").body_mass[1], 500 * volume);
  const Model given = jointed_body_with(R"(<geom size="0.1" mass="2" density="9"/>)");
  CHECK(given.body_mass[1] == 2);
  check_close(given.body_inertia[1][0], 0.4 * 2 * r * r);
}

TEST_CASE("one geom lends the body its frame and its unsorted moments", "[mjcf][inertia]") {
  const Model m = jointed_body_with(R"(<geom type="box" size="0.3 0.2 0.1" pos="0.1 0.2 0.3"
      euler="0 0 90"/>)");
  CHECK(m.body_ipos[1] == m.geom_pos[0]);
  CHECK(m.body_iquat[1] == m.geom_quat[0]);
  CHECK(m.body_inertia[1][0] < m.body_inertia[1][2]);  // (Ix, Iy, Iz) of the box, not sorted
  CHECK(m.body_explicit_inertial[1] == false);
}

TEST_CASE("several geoms combine about their centre of mass, sorted principal moments",
          "[mjcf][inertia]") {
  // two equal spheres at x = -d and x = +d
  const double r = 0.05, d = 0.2, m = kDensity * 4.0 / 3.0 * pi * r * r * r;
  const Model model = jointed_body_with(R"(<geom size="0.05" pos="-0.2 0 0"/>
      <geom size="0.05" pos="0.2 0 0"/>)");
  check_close(model.body_mass[1], 2 * m);
  check_close(model.body_ipos[1], {0, 0, 0});
  const double own = 0.4 * m * r * r, across = 2 * (own + m * d * d);
  check_close(model.body_inertia[1], {across, across, 2 * own});  // decreasing

  // unequal masses: the centre of mass sits nearer the heavier one
  const Model unequal = jointed_body_with(R"(<geom size="0.05" pos="0 0 0" mass="3"/>
      <geom size="0.05" pos="0.4 0 0" mass="1"/>)");
  check_close(unequal.body_ipos[1], {0.1, 0, 0});
  check_close(unequal.body_mass[1], 4);
}

TEST_CASE("explicit <inertial>: diaginertia as given, fullinertia diagonalized",
          "[mjcf][inertia]") {
  const Model diag =
      jointed_body_with(R"(<inertial pos="0.1 0 0" mass="2" diaginertia="0.3 0.1 0.25"/>
      <geom size="0.1"/>)");
  CHECK(diag.body_mass[1] == 2);
  CHECK(diag.body_ipos[1] == Eigen::Vector3d(0.1, 0, 0));
  CHECK(diag.body_inertia[1] == Eigen::Vector3d(0.3, 0.1, 0.25));
  CHECK(diag.body_explicit_inertial[1]);
  // the geom's own mass is still known, although it does not count
  check_close(diag.geom_mass[0], kDensity * 4.0 / 3.0 * pi * 0.001);

  const Model full =
      jointed_body_with(R"(<inertial pos="0 0 0" mass="1" fullinertia="0.1 0.2 0.3 0 0 0"/>)");
  check_close(full.body_inertia[1], {0.3, 0.2, 0.1});
  // the principal frame maps its x axis onto the body's z axis (the 0.3 moment)
  const Eigen::Vector4d q = full.body_iquat[1];
  const Eigen::Matrix3d R = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).toRotationMatrix();
  check_close(Eigen::Vector3d((R * Eigen::Vector3d::UnitX()).cwiseAbs()), {0, 0, 1});
}

TEST_CASE("inertiafromgeom and inertiagrouprange choose the mass source", "[mjcf][inertia]") {
  const std::string geoms = R"(<inertial pos="0 0 0" mass="5" diaginertia="1 1 1"/>
      <geom size="0.1" mass="1"/>
      <geom size="0.1" mass="2" group="3" pos="0.3 0 0"/>)";
  CHECK(jointed_body_with(geoms).body_mass[1] == 5);
  const Model from_geoms = jointed_body_with(geoms, R"(<compiler inertiafromgeom="true"/>)");
  CHECK(from_geoms.body_mass[1] == 3);
  CHECK(from_geoms.body_explicit_inertial[1] == false);
  const Model narrow =
      jointed_body_with(geoms, R"(<compiler inertiafromgeom="true" inertiagrouprange="0 2"/>)");
  CHECK(narrow.body_mass[1] == 1);
  CHECK(narrow.geom_mass == std::vector<double>{1, 2});  // the left-out geom keeps its own mass
  const Model nothing =
      jointed_body_with(geoms, R"(<compiler inertiafromgeom="true" inertiagrouprange="4 5"/>)");
  CHECK(nothing.body_mass[1] == 5);  // no geom selected: the <inertial> stays
  CHECK(nothing.body_explicit_inertial[1]);

  // inertiafromgeom="false": a body with geoms but no <inertial> has no mass
  const Model off = lever::mjcf::load_string(R"(<mujoco>
  <compiler inertiafromgeom="false"/>
  <worldbody><body name="s" pos="1 2 3"><geom size="0.1"/></body></worldbody>
</mujoco>)");
  CHECK(off.body_mass[1] == 0);
  CHECK(!off.compiler.inertia_from_geoms_allowed);
}

TEST_CASE("a body without mass takes its own frame as inertial frame", "[mjcf][inertia]") {
  // MuJoCo copies the body's pos and quat (relative to its parent) into ipos and iquat
  const Model m = lever::mjcf::load_string(R"(<mujoco>
  <worldbody><body name="empty" pos="1 2 3" quat="0 1 0 0"/></worldbody>
</mujoco>)");
  CHECK(m.body_mass[1] == 0);
  CHECK(m.body_ipos[1] == Eigen::Vector3d(1, 2, 3));
  CHECK(m.body_iquat[1] == Eigen::Vector4d(0, 1, 0, 0));
}

TEST_CASE("boundmass, boundinertia, balanceinertia and settotalmass", "[mjcf][inertia]") {
  const Model bounded =
      jointed_body_with(R"(<inertial pos="0 0 0" mass="0.1" diaginertia="0.01 0.02 0.02"/>)",
                        R"(<compiler boundmass="0.5" boundinertia="0.015"/>)");
  CHECK(bounded.body_mass[1] == 0.5);
  CHECK(bounded.body_inertia[1] == Eigen::Vector3d(0.015, 0.02, 0.02));

  const Model balanced =
      jointed_body_with(R"(<inertial pos="0 0 0" mass="1" diaginertia="0.1 0.1 0.5"/>)",
                        R"(<compiler balanceinertia="true"/>)");
  check_close(balanced.body_inertia[1], {0.7 / 3, 0.7 / 3, 0.7 / 3});

  const Model scaled = lever::mjcf::load_string(R"(<mujoco>
  <compiler settotalmass="9"/>
  <worldbody>
    <body name="a"><joint/><inertial pos="0 0 0" mass="1" diaginertia="1 1 1"/></body>
    <body name="b"><inertial pos="0 0 0" mass="2" diaginertia="2 2 2"/></body>
  </worldbody>
</mujoco>)");
  // every body is scaled, static ones included, with its inertia
  check_close(scaled.body_mass[1], 3);
  check_close(scaled.body_mass[2], 6);
  check_close(scaled.body_inertia[2], {6, 6, 6});
}

TEST_CASE("infer_inertia_from_geoms ignores every <inertial>", "[mjcf][inertia]") {
  // the lesson's arm2: each link as a solid capsule of density 1000
  lever::mjcf::LoadOptions options;
  options.infer_inertia_from_geoms = true;
  const Model m = lever::mjcf::load_file(lever::test::model_path("models/arm2.xml"), options);
  const double r1 = 0.025, h1 = 0.5, r2 = 0.02, h2 = 0.4;
  check_close(m.body_mass[1], kDensity * pi * (r1 * r1 * h1 + 4.0 / 3.0 * r1 * r1 * r1));
  check_close(m.body_mass[2], kDensity * pi * (r2 * r2 * h2 + 4.0 / 3.0 * r2 * r2 * r2));
  CHECK(m.body_explicit_inertial == flag_bytes({false, false, false}));
  CHECK(m.body_ipos[1] == Eigen::Vector3d(0.25, 0, 0));
  // the lesson prints these masses to three decimals (1.047 and 0.536 kg): its text agrees with
  // the capsule formula above to that printed precision, hence the relative 1e-3
  CHECK(m.body_mass[1] == Approx(1.047).epsilon(1e-3));
  CHECK(m.body_mass[2] == Approx(0.536).epsilon(1e-3));
}
