// <include file="..."/> on its own (no MuJoCo; tests/compile/robot_files_test.cpp compares the
// Menagerie scenes, which include their robots, with MuJoCo 2.2.2): the included file's elements in
// place of the element, paths from the main model file's folder also when nested, compiler/meshdir
// over the merged model, and every error located in the file and line where it is.
#include <catch2/catch.hpp>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <lever/mjcf.hpp>
#include <lever/mjcf/write.hpp>
#include <string>

namespace {

// a scratch folder of model files, removed at the end
struct IncludeFolder {
  std::filesystem::path path;
  explicit IncludeFolder(const std::string& name) {
    path = std::filesystem::temp_directory_path() /
           ("lever_include_" + name + "_" + std::to_string(reinterpret_cast<std::uintptr_t>(this)));
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~IncludeFolder() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  std::string write(const std::string& name, const std::string& text) const {
    std::filesystem::create_directories((path / name).parent_path());
    std::ofstream(path / name, std::ios::binary) << text;
    return (path / name).string();
  }
  std::string at(const std::string& name) const { return (path / name).string(); }
};

// the ParseError a load throws (fails the test if it loads)
lever::mjcf::ParseError load_error(const std::string& file) {
  try {
    lever::mjcf::load_file(file);
  } catch (const lever::mjcf::ParseError& e) {
    return e;
  }
  FAIL("the model loaded");
  throw;
}

// a unit cube (corners 0 and 1), outward faces, as OBJ
const char* const kCubeObj =
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
    "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

}  // namespace

TEST_CASE("included files' elements take the include's place, nested, from the main folder",
          "[mjcf][include]") {
  const IncludeFolder folder("nested");
  folder.write("scene.xml", R"(<mujoco model="scene">
  <include file="robot/arm.xml"/>
  <worldbody>
    <geom name="floor" type="plane" size="1 1 0.1"/>
  </worldbody>
</mujoco>)");
  // the robot's own compiler and asset sections come with it; its root's attributes do not
  folder.write("robot/arm.xml", R"(<mujoco model="arm">
  <compiler angle="radian" meshdir="robot/assets"/>
  <asset><mesh name="cube" file="cube.obj"/></asset>
  <worldbody>
    <body name="upper">
      <joint name="shoulder" range="-1 1"/>
      <geom type="mesh" mesh="cube"/>
      <include file="robot/forearm.xml"/>
    </body>
  </worldbody>
  <include file="robot/actuators.xml"/>
</mujoco>)");
  folder.write("robot/forearm.xml", R"(<mujocoinclude>
  <body name="fore" pos="0 0 1">
    <joint name="elbow" range="-2 2"/>
    <geom size="0.1"/>
  </body>
</mujocoinclude>)");
  folder.write("robot/actuators.xml", R"(<mujoco>
  <actuator><position joint="elbow" kp="10"/></actuator>
</mujoco>)");
  folder.write("robot/assets/cube.obj", kCubeObj);
  const lever::Model m = lever::mjcf::load_file(folder.at("scene.xml"));
  CHECK(m.name == "scene");
  REQUIRE(m.nbody == 3);
  CHECK(m.body_name[1] == "upper");
  CHECK(m.body_name[2] == "fore");
  CHECK(m.body_parentid[2] == 1);
  REQUIRE(m.njnt == 2);
  CHECK(m.jnt_range[1][1] == 2.0);  // angle="radian" from the included <compiler>
  CHECK(m.nu == 1);
  CHECK(m.actuator_trnid[0][0] == 1);
  // the mesh was read from meshdir, relative to the main file's folder: a 1000 kg cube
  CHECK(m.body_mass[1] == Approx(1000.0).epsilon(1e-6));
  CHECK(m.visual.meshdir == "robot/assets");
}

TEST_CASE("an error in an included file is located in that file", "[mjcf][include]") {
  const IncludeFolder folder("located");
  folder.write("scene.xml",
               "<mujoco>\n  <worldbody>\n    <include file=\"part.xml\"/>\n"
               "  </worldbody>\n</mujoco>\n");
  const std::string part = folder.write(
      "part.xml",
      "<mujoco>\n  <body name=\"b\">\n    <joint rnage=\"0 1\"/>\n  </body>\n</mujoco>\n");
  lever::mjcf::ParseError e = load_error(folder.at("scene.xml"));
  CHECK(e.file() == part);
  CHECK(e.line() == 3);
  CHECK(e.element() == "joint");
  CHECK(e.attribute() == "rnage");
  CHECK_THAT(e.what(), Catch::StartsWith(part + ":3: error: <joint>: unknown attribute 'rnage'"));

  // malformed XML in the included file: its file and line too
  folder.write("part.xml", "<mujoco>\n  <body name=\"b\">\n  </bodyy>\n</mujoco>\n");
  e = load_error(folder.at("scene.xml"));
  CHECK(e.file() == part);
  CHECK(e.line() == 2);  // tinyxml2 reports a mismatched closing tag at its element's line
  CHECK_THAT(e.problem(), Catch::StartsWith("malformed XML"));

  // a problem found when compiling: still the included element's place
  folder.write("part.xml", "<mujoco>\n  <body name=\"b\">\n    <joint/>\n  </body>\n</mujoco>\n");
  e = load_error(folder.at("scene.xml"));
  CHECK(e.file() == part);
  CHECK(e.line() == 2);
  CHECK_THAT(e.problem(), Catch::Contains("needs positive mass"));
}

TEST_CASE("a missing, repeated or cyclic include names both files and the line",
          "[mjcf][include]") {
  const IncludeFolder folder("bad");
  const std::string scene = folder.write(
      "scene.xml", "<mujoco>\n  <include file=\"a.xml\"/>\n  <worldbody/>\n</mujoco>\n");

  SECTION("missing") {
    const lever::mjcf::ParseError e = load_error(scene);
    CHECK(e.file() == scene);
    CHECK(e.line() == 2);
    CHECK(e.element() == "include");
    CHECK(e.attribute() == "file");
    CHECK_THAT(e.problem(),
               Catch::Contains("cannot include 'a.xml'") && Catch::Contains(folder.at("a.xml")));
  }
  SECTION("a nested path written from the including file's folder") {
    folder.write("a.xml", "<mujoco>\n  <include file=\"b.xml\"/>\n</mujoco>\n");
    folder.write("sub/c.xml", "<mujoco><worldbody/></mujoco>\n");
    folder.write("b.xml", "<mujoco>\n\n  <include file=\"sub/c.xml\"/>\n</mujoco>\n");
    CHECK_NOTHROW(lever::mjcf::load_file(scene));
    // sub/d.xml includes "c.xml", meaning sub/c.xml: MuJoCo looks beside the main file
    folder.write("b.xml", "<mujoco>\n\n  <include file=\"sub/d.xml\"/>\n</mujoco>\n");
    const std::string d =
        folder.write("sub/d.xml", "<mujoco>\n  <include file=\"c.xml\"/>\n</mujoco>\n");
    const lever::mjcf::ParseError e = load_error(scene);
    CHECK(e.file() == d);
    CHECK(e.line() == 2);
    CHECK_THAT(e.problem(), Catch::Contains("relative to the folder of the main model file") &&
                                Catch::Contains(folder.at("sub/c.xml") + "' exists beside"));
  }
  SECTION("a cycle") {
    const std::string a =
        folder.write("a.xml", "<mujoco>\n  <include file=\"b.xml\"/>\n</mujoco>\n");
    const std::string b =
        folder.write("b.xml", "<mujoco>\n  <worldbody/>\n  <include file=\"a.xml\"/>\n</mujoco>\n");
    const lever::mjcf::ParseError e = load_error(scene);
    CHECK(e.file() == b);
    CHECK(e.line() == 3);
    CHECK_THAT(e.problem(), Catch::Contains("'" + a + "' is already included, at " + scene + ":2"));
  }
  SECTION("the main file itself") {
    folder.write("a.xml", "<mujoco>\n  <include file=\"scene.xml\"/>\n</mujoco>\n");
    const lever::mjcf::ParseError e = load_error(scene);
    CHECK(e.file() == folder.at("a.xml"));
    CHECK(e.line() == 2);
    CHECK_THAT(e.problem(), Catch::Contains("is the model file itself"));
  }
  SECTION("the same file twice, as MuJoCo refuses it") {
    folder.write("a.xml", "<mujoco>\n  <worldbody/>\n</mujoco>\n");
    const std::string twice = folder.write(
        "twice.xml",
        "<mujoco>\n  <include file=\"a.xml\"/>\n  <include file=\"a.xml\"/>\n</mujoco>\n");
    const lever::mjcf::ParseError e = load_error(twice);
    CHECK(e.line() == 3);
    CHECK_THAT(e.problem(), Catch::Contains("already included, at " + twice + ":2"));
  }
  SECTION("an include with children, an empty file, another attribute") {
    folder.write("a.xml", "<mujoco/>\n");
    lever::mjcf::ParseError e = load_error(scene);
    CHECK(e.line() == 2);
    CHECK_THAT(e.problem(), Catch::Contains("has no elements inside its root element <mujoco>"));
    folder.write("a.xml", "<mujoco><worldbody/></mujoco>\n");
    folder.write(
        "kids.xml",
        "<mujoco>\n  <include file=\"a.xml\">\n    <worldbody/>\n  </include>\n</mujoco>\n");
    e = load_error(folder.at("kids.xml"));
    CHECK(e.line() == 3);
    CHECK_THAT(e.problem(), Catch::Contains("an <include> cannot have children"));
    folder.write("attr.xml", "<mujoco>\n  <include fiel=\"a.xml\"/>\n</mujoco>\n");
    e = load_error(folder.at("attr.xml"));
    CHECK(e.attribute() == "fiel");
    CHECK_THAT(e.problem(), Catch::Contains("did you mean 'file'?"));
  }
}

TEST_CASE("a model with includes is not written back", "[mjcf][include]") {
  const IncludeFolder folder("write");
  folder.write("part.xml", R"(<mujoco><worldbody><body name="b"><joint/><geom size="0.1"/></body>
  </worldbody></mujoco>)");
  const std::string scene =
      folder.write("scene.xml", R"(<mujoco><include file="part.xml"/></mujoco>)");
  const lever::Model m = lever::mjcf::load_file(scene);
  CHECK(m.nbody == 2);
  CHECK_THROWS_WITH(lever::mjcf::write_file(scene, m, folder.at("out.xml")),
                    Catch::Contains("the model includes other files"));
  CHECK_FALSE(std::filesystem::exists(folder.at("out.xml")));
}

TEST_CASE("the nesting limit counts included elements at their include's level",
          "[mjcf][include]") {
  const IncludeFolder folder("deep");
  const auto bodies = [](int n) {
    std::string open, close;
    for (int i = 0; i < n; ++i) {
      open += "<body>";
      close += "</body>";
    }
    return std::make_pair(open, close);
  };
  // 60 levels in each file: each alone is within lever's 100, together they are not
  const auto [outer_open, outer_close] = bodies(60);
  const auto [inner_open, inner_close] = bodies(60);
  folder.write("inner.xml", "<mujoco>" + inner_open + inner_close + "</mujoco>\n");
  const std::string scene = folder.write("scene.xml", "<mujoco><worldbody>" + outer_open +
                                                          "\n<include file=\"inner.xml\"/>" +
                                                          outer_close + "</worldbody></mujoco>\n");
  const lever::mjcf::ParseError e = load_error(scene);
  CHECK(e.file() == scene);
  CHECK(e.line() == 2);
  CHECK_THAT(e.problem(), Catch::Contains("nested more than 100 levels deep"));
  // 30 levels inside fit
  const auto [few_open, few_close] = bodies(30);
  folder.write("inner.xml", "<mujoco>" + few_open + few_close + "</mujoco>\n");
  CHECK(lever::mjcf::load_file(scene).nbody == 91);
}
