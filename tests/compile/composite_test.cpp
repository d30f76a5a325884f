// <composite> against MuJoCo 2.2.2: every real file that uses one (MuJoCo 2.2.2's samples, from
// ../shared/robots) compiled by both, the generated bodies, joints, geoms, sites, tendons,
// equality constraints, exclusions and names compared array by array (compare_parameters,
// compare_constants: bit for bit or within 1e-12). Bad composites are refused at their element
// and attribute.
#include <catch2/catch.hpp>
#include <filesystem>
#include <lever/harness/models.hpp>
#include <lever/error.hpp>
#include <lever/mjcf.hpp>
#include <lever/mjcf/write.hpp>

#include "compile_checks.hpp"

namespace {

namespace fs = std::filesystem;

struct CompositeFile {
  const char* path;  // under the robots folder
  int bodies;        // the model's nbody, so that the composite is seen to be generated
};

}  // namespace

TEST_CASE("the real files' composites compile as MuJoCo 2.2.2 compiles them",
          "[compile][composite][robots]") {
  const std::string root = lever::test::robots_dir() + "/mujoco-2.2.2";
  if (!fs::exists(root)) {
    WARN("no real model files at " << root << ": skipped");
    return;
  }
  const std::vector<CompositeFile> files = {
      {"hammock/hammock.xml", 1 + 16 + 99},     // the humanoid and an 11 x 9 grid
      {"composite/grid2pin.xml", 1 + 1 + 81},   // scene.xml's mocap body and a 9 x 9 grid
      {"flag/flag.xml", 1 + 171},               // a 9 x 19 cloth
      {"composite/cloth.xml", 1 + 1 + 81},
      {"composite/particle.xml", 1 + 1 + 1000},
      {"adhesion/active_adhesion.xml", 1 + 7 + 64},
      {"composite/rope.xml", 1 + 1 + 21},
      {"composite/loop.xml", 1 + 1 + 20},
      {"composite/softbox.xml", 1 + 1 + 1 + 218},  // a 7 x 7 x 7 shell: 7^3 - 5^3
  };
  for (const CompositeFile& f : files) {
    const std::string path = root + "/" + f.path;
    INFO(f.path);
    const lever::Model ours = lever::mjcf::load_file(path);
    char error[1000] = "";
    const lever::test::MjModelHandle theirs(mj_loadXML(path.c_str(), nullptr, error,
                                                       sizeof error),
                                            mj_deleteModel);
    INFO("MuJoCo: " << error);
    REQUIRE(theirs);
    CHECK(ours.nbody == f.bodies);
    for (const std::string& d : lever::test::compare_models(ours, *theirs)) FAIL_CHECK(d);
  }
}

namespace {

// The error lever gives for a model whose worldbody holds `body`.
lever::mjcf::ParseError composite_error(const std::string& body) {
  const std::string xml = "<mujoco>\n<worldbody>\n" + body + "\n</worldbody>\n</mujoco>\n";
  try {
    lever::mjcf::load_string(xml, "bad.xml");
  } catch (const lever::mjcf::ParseError& e) {
    // MuJoCo refuses it too
    std::string error;
    CHECK_FALSE(lever::test::mujoco_compile(xml, &error));
    return e;
  }
  FAIL("lever loaded " << body);
  throw;
}

}  // namespace

TEST_CASE("bad composites are refused at their element and attribute", "[compile][composite]") {
  struct Bad {
    const char* body;
    const char* element;
    const char* attribute;
    const char* says;
  };
  const std::vector<Bad> cases = {
      {R"(<composite type="blob" count="2" spacing="1"/>)", "composite", "type", "blob"},
      {R"(<composite type="grid" count="0 2 1" spacing="1"/>)", "composite", "count", "positive"},
      {R"(<composite type="grid" count="3 -1 1" spacing="1"/>)", "composite", "count", "positive"},
      {R"(<composite type="grid" count="3 2 1" spacing="0"/>)", "composite", "spacing", "positive"},
      {R"(<composite type="grid" count="3 2 1" spacing="-0.1"/>)", "composite", "spacing",
       "positive"},
      {R"(<composite type="grid" count="1 3 1" spacing="1"/>)", "composite", "count", "last"},
      {R"(<composite type="grid" count="3 3 3" spacing="1"/>)", "composite", "count", "1D or 2D"},
      {R"(<composite type="grid" count="3 3"/>)", "composite", "spacing", "spacing"},
      {R"(<composite type="rope" count="3 1 1" spacing="1"/>)", "composite", "", "B<x>"},
      {R"(<body name="Bx"><composite type="rope" count="3 1 1" spacing="1"/></body>)",
       "composite", "", "x coordinate"},
      {R"(<body name="B7"><composite type="rope" count="3 1 1" spacing="1"/></body>)",
       "composite", "", "out of range"},
      {R"(<body name="B1_1"><composite type="cloth" count="3 1 1" spacing="1"/></body>)",
       "composite", "count", "two-dimensional"},
      {R"(<body name="B1"><composite type="cloth" count="3 3 1" spacing="1"/></body>)",
       "composite", "", "B<x>_<y>"},
      {R"(<composite type="box" count="3 3 1" spacing="1"/>)", "composite", "count",
       "three-dimensional"},
      {"<composite type=\"grid\" count=\"3 3 1\" spacing=\"1\">\n<geom type=\"box\"/>\n"
       "</composite>",
       "geom", "type", "spheres, capsules or ellipsoids"},
      {"<composite type=\"grid\" count=\"3 3 1\" spacing=\"1\">\n<joint kind=\"bend\"/>\n"
       "</composite>",
       "joint", "kind", "bend"},
      {"<composite type=\"grid\" count=\"3 1 1\" spacing=\"1\">\n<tendon kind=\"shear\"/>\n"
       "</composite>",
       "tendon", "kind", "2D grid"},
      {"<composite type=\"grid\" count=\"3 2 1\" spacing=\"1\">\n<skin subgrid=\"2\"/>\n"
       "</composite>",
       "skin", "subgrid", "3 x 3"},
      {"<composite type=\"grid\" count=\"3 3 1\" spacing=\"1\">\n<skin group=\"6\"/>\n"
       "</composite>",
       "skin", "group", "0 and 5"},
      {"<composite type=\"grid\" count=\"3 3 1\" spacing=\"1\">\n<skin material=\"none\"/>\n"
       "</composite>",
       "skin", "material", "none"},
      {"<composite type=\"grid\" count=\"3 3 1\" spacing=\"1\">\n<tendon kind=\"main\">\n"
       "<fixed/></tendon>\n</composite>",
       "fixed", "", "no child elements"},
  };
  for (const Bad& c : cases) {
    INFO(c.body);
    const lever::mjcf::ParseError e = composite_error(c.body);
    INFO(e.what());
    CHECK(e.file() == "bad.xml");
    CHECK(e.line() >= 3);
    CHECK(e.element() == c.element);
    CHECK(e.attribute() == c.attribute);
    CHECK(e.problem().find(c.says) != std::string::npos);
  }
}

TEST_CASE("a composite's elements take MuJoCo's built-in defaults, not the model's classes",
          "[compile][composite]") {
  // the main class's joint damping, geom size and tendon stiffness reach only the elements
  // written by hand; a childclass does not reach the composite either
  const std::string xml = R"(<mujoco>
  <default>
    <joint damping="5"/>
    <geom size="0.3" rgba="1 0 0 1"/>
    <tendon stiffness="7"/>
    <equality solref="0.05 1" active="false"/>
    <default class="other"><joint damping="9"/></default>
  </default>
  <worldbody>
    <body name="B1" childclass="other" pos="0 0 1">
      <freejoint/>
      <composite prefix="" type="loop" count="6 1 1" spacing="0.1">
        <joint kind="main" stiffness="0.5"/>
        <joint kind="twist" damping="0.1" solreffix="0.04"/>
        <joint kind="stretch" stiffness="2"/>
        <geom type="capsule" size="0.01 0.02" condim="4"/>
      </composite>
    </body>
    <composite prefix="g" type="grid" count="4 3 1" spacing="0.1" offset="1 0 1">
      <pin coord="0 0"/>
      <pin coord="3"/>
      <geom size="0.02" mass="0.1"/>
      <site size="0.01" group="2"/>
      <tendon kind="main" stiffness="3" width="0.01" range="0 1"/>
      <tendon kind="shear" damping="0.2" solimpfix="0.5"/>
    </composite>
    <body name="xB0_0" pos="0 1 1">
      <composite prefix="x" type="cloth" count="3 4 1" spacing="0.1" flatinertia="0.1">
        <joint kind="main" damping="0.01" range="-10 10"/>
        <joint kind="stretch"/>
        <tendon kind="shear"/>
        <geom type="ellipsoid" size="0.04 0.01 0.04" density="300"/>
      </composite>
    </body>
    <body name="c" pos="1 1 1">
      <composite prefix="c" type="cylinder" count="4 4 3" spacing="0.1" solrefsmooth="0.1 2">
        <geom size="0.01"/>
        <joint kind="main" solimpfix="0.1 0.2"/>
      </composite>
    </body>
    <body name="e" pos="-1 1 1">
      <composite prefix="e" type="ellipsoid" count="3 4 3" spacing="0.1">
        <geom type="capsule" size="0.01 0.02"/>
      </composite>
    </body>
    <composite prefix="p" type="particle" count="2 2 2" spacing="0.1" offset="-1 -1 1">
      <geom size="0.02" contype="2"/>
      <joint kind="main" armature="0.01"/>
    </composite>
  </worldbody>
</mujoco>)";
  lever::test::check_compiles_as_mujoco("defaults.xml", xml);
  const lever::Model ours = lever::mjcf::load_string(xml, "defaults.xml");
  // something of every kind was generated
  CHECK(ours.ntendon > 20);
  CHECK(ours.neq > 40);
  CHECK(ours.nexclude == 1);
}


TEST_CASE("a model with a composite is not written back element by element",
          "[compile][composite]") {
  // its generated bodies have no element of their own to take an inertial
  const std::string xml = R"(<mujoco>
  <worldbody>
    <composite type="grid" count="3 1 1" spacing="0.1"><geom size="0.02"/></composite>
  </worldbody>
</mujoco>)";
  const lever::Model model = lever::mjcf::load_string(xml, "grid.xml");
  try {
    lever::mjcf::write_string(xml, model, "grid.xml");
    FAIL("written");
  } catch (const lever::Error& e) {
    const std::string why = e.what();
    INFO(why);
    CHECK(why.find("generated by a <composite> (line 3)") != std::string::npos);
  }
}
