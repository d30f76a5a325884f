// Meshes as MuJoCo 2.2.2 compiles them for collision, on real files read in place from the shared
// robot files (../shared/robots, never copied): lever's mesh_vert (STL vertices merged as MuJoCo
// merges them, then centred and turned to the principal axes), its qhull hull graphs, the mesh
// geoms' frames, sizes and bounding radii, and the bodies' masses from their meshes, field by
// field against MuJoCo's mjModel.
#include <catch2/catch.hpp>
#include <lever/mjcf.hpp>

#include <string>

#include <lever/harness/models.hpp>

#include "mujoco_xml.hpp"

namespace {

void compare_with_mujoco(const std::string& xml, const std::string& name, int meshes_read) {
  const lever::Model ours = lever::mjcf::load_string(xml, name);
  std::string error;
  const auto theirs = lever::test::mujoco_compile(xml, &error);
  INFO(name << "; MuJoCo: " << error);
  REQUIRE(theirs);
  int read = 0;
  for (int k = 0; k < ours.nmesh; ++k) read += ours.mesh_vertnum[static_cast<size_t>(k)] > 0;
  CHECK(read == meshes_read);
  CHECK(ours.warnings.empty());
  for (const std::string& difference : lever::test::compare_parameters(ours, *theirs)) {
    FAIL_CHECK(difference);
  }
  for (const std::string& difference : lever::test::compare_constants(ours, *theirs)) {
    FAIL_CHECK(difference);
  }
}

}  // namespace

TEST_CASE("the Menagerie's Panda arm: its collision meshes and hulls are MuJoCo's",
          "[compile][mesh]") {
  const std::string path =
      lever::test::robots_dir() + "/menagerie-2022/franka_emika_panda/panda_nohand.xml";
  // the file as it is, its meshdir made absolute so that MuJoCo reads the same files from text
  std::string xml = lever::test::read_text(path);
  REQUIRE_FALSE(xml.empty());
  const std::string relative = "meshdir=\"assets\"";
  const size_t at = xml.find(relative);
  REQUIRE(at != std::string::npos);
  xml.replace(at, relative.size(),
              "meshdir=\"" + lever::test::robots_dir() + "/menagerie-2022/franka_emika_panda/assets\"");
  compare_with_mujoco(xml, "panda_nohand.xml", 10);
}

TEST_CASE("a gripper of the Panda hand's and the 2F-85's meshes: masses and hulls are MuJoCo's",
          "[compile][mesh]") {
  // the hand and the fingers give their bodies mass (hand.stl, finger_0.obj; the hand's visual
  // mesh too: its group is in inertiagrouprange, as in MuJoCo); the 2F-85's pad (scaled) and
  // coupler only collide (their body has an <inertial>)
  const std::string robots = lever::test::robots_dir() + "/menagerie-2022/";
  const std::string xml = R"(<mujoco>
  <compiler meshdir=")" + robots + R"("/>
  <asset>
    <mesh name="hand" file="franka_emika_panda/assets/hand.stl"/>
    <mesh name="finger" file="franka_emika_panda/assets/finger_0.obj"/>
    <mesh name="hand_look" file="franka_emika_panda/assets/hand_1.obj"/>
    <mesh name="pad" file="robotiq_2f85/assets/pad.stl" scale="1.5 1 1"/>
    <mesh name="coupler" file="robotiq_2f85/assets/coupler.stl"/>
  </asset>
  <worldbody>
    <geom type="plane" size="1 1 0.1"/>
    <body name="hand" pos="0 0 0.3">
      <joint name="lift" type="slide" axis="0 0 1"/>
      <geom type="mesh" mesh="hand"/>
      <geom type="mesh" mesh="hand_look" contype="0" conaffinity="0" group="2"/>
      <body name="left" pos="0 0 0.0584">
        <joint name="left" type="slide" axis="0 1 0"/>
        <geom type="mesh" mesh="finger"/>
      </body>
      <body name="right" pos="0 0 0.0584" quat="0 0 0 1">
        <joint name="right" type="slide" axis="0 1 0"/>
        <geom type="mesh" mesh="finger"/>
      </body>
      <body name="pads" pos="0 0 0.12">
        <joint type="hinge" axis="1 0 0"/>
        <inertial pos="0 0 0" mass="0.1" diaginertia="1e-4 1e-4 1e-4"/>
        <geom type="mesh" mesh="pad"/>
        <geom type="mesh" mesh="coupler" pos="0 0.03 0"/>
      </body>
    </body>
    <body name="box" pos="0 0 0.05">
      <freejoint/>
      <geom type="box" size="0.02 0.02 0.02"/>
    </body>
  </worldbody>
</mujoco>)";
  compare_with_mujoco(xml, "gripper_meshes.xml", 5);
}

TEST_CASE("shell inertia of real meshes is MuJoCo's, legacy and exact", "[compile][mesh]") {
  // shellinertia: the geom's frame from the surface's centre and axes, its inertia from the
  // surface's box, its volume the surface area when exact (else the solid's inertia box)
  const std::string robots = lever::test::robots_dir() + "/menagerie-2022/";
  for (const char* exact : {"false", "true"}) {
    const std::string xml = R"(<mujoco>
  <compiler exactmeshinertia=")" + std::string(exact) + R"(" meshdir=")" + robots + R"("/>
  <asset>
    <mesh name="hand" file="franka_emika_panda/assets/hand.stl"/>
    <mesh name="finger" file="franka_emika_panda/assets/finger_0.obj"/>
  </asset>
  <default><geom shellinertia="true"/></default>
  <worldbody>
    <body name="hand">
      <joint type="slide" axis="0 0 1"/>
      <geom type="mesh" mesh="hand" pos="0.1 0 0" euler="0.3 0 0"/>
      <body name="finger" pos="0 0 0.06">
        <joint type="slide" axis="0 1 0"/>
        <geom type="mesh" mesh="finger" density="500"/>
        <geom type="mesh" mesh="hand" shellinertia="false" contype="0" conaffinity="0"/>
      </body>
    </body>
  </worldbody>
</mujoco>)";
    compare_with_mujoco(xml, std::string("shell_") + exact + ".xml", 2);
  }
}
