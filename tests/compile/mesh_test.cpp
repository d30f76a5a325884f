// Mesh geoms that give their bodies mass: lever reads the mesh file and must compile the same
// volume, centre, principal axes, geom frame, size, mass and inertia as MuJoCo 2.2.2; and a mesh
// geom that can collide: its frame, size and bounding radius. Each model
// is written with its mesh files into a temporary folder for lever and into MuJoCo's virtual
// file system, and the two compiled models are compared field by field (compare_parameters also
// compares the mesh geoms' size, pos and quat once lever has read their mesh).
#include <array>
#include <catch2/catch.hpp>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <lever/lever.hpp>
#include <lever/mjcf.hpp>
#include <memory>
#include <map>
#include <string>
#include <vector>

#include <lever/harness/models.hpp>

#include "mujoco_xml.hpp"

namespace {

using Vertex = std::array<float, 3>;
using Triangle = std::array<int, 3>;

struct Shape {
  std::vector<Vertex> v;
  std::vector<Triangle> f;  // counter-clockwise seen from outside
};

std::string binary_stl(const Shape& s) {
  std::string bytes(80, ' ');
  const auto put = [&bytes](const void* p, std::size_t n) {
    bytes.append(static_cast<const char*>(p), n);
  };
  const std::uint32_t count = static_cast<std::uint32_t>(s.f.size());
  put(&count, sizeof count);
  for (const Triangle& t : s.f) {
    const float normal[3] = {0, 0, 0};
    put(normal, sizeof normal);
    for (const int i : t) put(s.v[static_cast<size_t>(i)].data(), 3 * sizeof(float));
    const std::uint16_t attribute = 0;
    put(&attribute, sizeof attribute);
  }
  return bytes;
}

// numbers written with 9 significant digits, so that the text is not a float's exact value
std::string number(float x) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.9g", static_cast<double>(x) * 1.0000001);
  return buffer;
}

std::string obj_triangles(const Shape& s) {
  std::string text = "# a test mesh\no shape\n";
  for (const Vertex& p : s.v)
    text += "v " + number(p[0]) + " " + number(p[1]) + " " + number(p[2]) + "\n";
  text += "vn 0 0 1\ns off\n";
  for (const Triangle& t : s.f) {
    text += "f " + std::to_string(t[0] + 1) + "//1 " + std::to_string(t[1] + 1) + "//1 " +
            std::to_string(t[2] + 1) + "//1\n";
  }
  return text;
}

Shape tetrahedron() {
  return {{{0.011f, -0.02f, 0.003f},
           {0.153f, 0.01f, -0.012f},
           {0.02f, 0.121f, 0.017f},
           {0.031f, 0.025f, 0.187f}},
          {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}};
}

// a box with corners moved (not a cuboid, not centred, no symmetry), as 12 triangles; corner
// index = x + 2 y + 4 z
Shape skewed_box() {
  const float x[2] = {-0.05f, 0.07f}, y[2] = {-0.11f, 0.09f}, z[2] = {0.02f, 0.31f};
  Shape s;
  for (int k = 0; k < 8; ++k) {
    const int i = k & 1, j = (k >> 1) & 1, l = (k >> 2) & 1;
    s.v.push_back({x[i] + 0.013f * static_cast<float>(k % 3),
                   y[j] - 0.007f * static_cast<float>(k % 4),
                   z[l] + 0.019f * static_cast<float>((k * 5) % 7) / 7});
  }
  const std::array<std::array<int, 4>, 6> quads{
      {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}}};
  for (const auto& q : quads) {
    s.f.push_back({q[0], q[1], q[2]});
    s.f.push_back({q[0], q[2], q[3]});
  }
  return s;
}

// the same box written as quadrilaterals (convex, so split as (0 1 2), (0 2 3))
std::string obj_quads() {
  const Shape s = skewed_box();
  std::string text;
  for (const Vertex& p : s.v)
    text += "v " + number(p[0]) + " " + number(p[1]) + " " + number(p[2]) + "\n";
  for (size_t q = 0; q < 6; ++q) {
    const Triangle& a = s.f[2 * q];
    const Triangle& b = s.f[2 * q + 1];
    // negative (relative) indices on one face, as OBJ allows
    if (q == 3) {
      text += "f " + std::to_string(a[0] - 8) + " " + std::to_string(a[1] - 8) + " " +
              std::to_string(a[2] - 8) + " " + std::to_string(b[2] - 8) + "\n";
    } else {
      text += "f " + std::to_string(a[0] + 1) + " " + std::to_string(a[1] + 1) + " " +
              std::to_string(a[2] + 1) + " " + std::to_string(b[2] + 1) + "\n";
    }
  }
  return text;
}

struct Folder {
  std::filesystem::path path;
  explicit Folder(const std::string& name) {
    path = std::filesystem::temp_directory_path() /
           ("lever_mesh_" + name + "_" + std::to_string(reinterpret_cast<std::uintptr_t>(this)));
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~Folder() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  void write(const std::string& name, const std::string& bytes) const {
    const std::filesystem::path p = path / name;
    std::filesystem::create_directories(p.parent_path());
    std::ofstream(p, std::ios::binary) << bytes;
  }
};

// lever loads the model from a folder that holds it and its meshes (under `meshdir`); MuJoCo
// from its virtual file system; both must compile, to the same numbers
void check_against_mujoco(const std::string& name, const std::string& xml,
                          const std::map<std::string, std::string>& meshes,
                          const std::string& meshdir = "") {
  INFO(name << ":\n" << xml);
  const Folder folder(name);
  folder.write("model.xml", xml);
  for (const auto& [file, bytes] : meshes) folder.write(meshdir + file, bytes);
  const lever::Model ours = lever::mjcf::load_file((folder.path / "model.xml").string());
  std::string error;
  const lever::test::MjModelHandle theirs = lever::test::mujoco_compile(xml, &error, meshes);
  INFO("MuJoCo: " << error);
  REQUIRE(theirs);
  // the mesh geoms that give mass were read: their size is the mesh's bounding box
  for (int g = 0; g < ours.ngeom; ++g) {
    const size_t i = static_cast<size_t>(g);
    if (ours.geom_type[i] == lever::GeomType::kMesh) CHECK(ours.geom_size[i].minCoeff() > 0);
  }
  for (const std::string& difference : lever::test::compare_parameters(ours, *theirs)) {
    FAIL_CHECK(difference);
  }
  for (const std::string& difference : lever::test::compare_constants(ours, *theirs)) {
    FAIL_CHECK(difference);
  }
}

// two moving bodies whose mass comes from mesh geoms only (one by density, one by mass=), and a
// third that adds a box to a mesh
std::string arm(const std::string& compiler, const std::string& mesh_a, const std::string& mesh_b,
                const std::string& assets_extra = "", const std::string& defaults = "") {
  return R"(<mujoco>
  <compiler )" +
         compiler + R"(/>
  )" + defaults +
         R"(
  <asset>
    <mesh name="a" file=")" +
         mesh_a + R"(" )" + assets_extra + R"(/>
    <mesh name="b" file=")" +
         mesh_b + R"("/>
  </asset>
  <worldbody>
    <body name="l1" pos="0 0 0.1">
      <joint name="j1" axis="0 1 0"/>
      <geom name="g1" type="mesh" mesh="a" pos="0.01 -0.02 0.03" euler="10 20 30" density="2700"/>
      <body name="l2" pos="0.2 0 0" quat="0.9 0.1 0.3 0.2">
        <joint name="j2" axis="1 0 0"/>
        <geom name="g2" type="mesh" mesh="b" mass="1.7"/>
        <body name="l3" pos="0 0.1 0.25">
          <joint name="j3" axis="0 0 1"/>
          <geom name="g3" type="mesh" mesh="a" quat="0.5 0.5 -0.5 0.5"/>
          <geom name="g4" type="box" size="0.02 0.03 0.04" pos="0.05 0 0"/>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>)";
}

const std::map<std::string, std::string> kFiles{
    {"tetra.stl", binary_stl(tetrahedron())},
    {"box.stl", binary_stl(skewed_box())},
    {"tetra.obj", obj_triangles(tetrahedron())},
    {"box.obj", obj_triangles(skewed_box())},
    {"quads.obj", obj_quads()},
};

}  // namespace

TEST_CASE("mesh inertia: binary STL, legacy and exact", "[compile][mesh]") {
  for (const char* exact : {"false", "true"}) {
    const std::string compiler = std::string("exactmeshinertia=\"") + exact + "\"";
    check_against_mujoco("stl", arm(compiler, "tetra.stl", "box.stl"), kFiles);
  }
}

TEST_CASE("mesh inertia: OBJ triangles and quadrilaterals", "[compile][mesh]") {
  for (const char* exact : {"false", "true"}) {
    const std::string compiler = std::string("exactmeshinertia=\"") + exact + "\"";
    check_against_mujoco("obj", arm(compiler, "tetra.obj", "box.obj"), kFiles);
    check_against_mujoco("quads", arm(compiler, "quads.obj", "tetra.obj"), kFiles);
  }
}

TEST_CASE("mesh inertia: refpos, refquat, scale, mirroring, class density", "[compile][mesh]") {
  for (const char* exact : {"false", "true"}) {
    const std::string compiler = std::string("exactmeshinertia=\"") + exact + "\"";
    check_against_mujoco("ref",
                         arm(compiler, "box.stl", "tetra.stl",
                             "refpos=\"0.01 0.02 -0.03\" refquat=\"0.8 0.1 -0.2 0.3\" "
                             "scale=\"1.5 0.7 2\""),
                         kFiles);
    // a negative scale mirrors the mesh: MuJoCo reverses every triangle
    check_against_mujoco("mirror", arm(compiler, "box.obj", "tetra.stl", "scale=\"-1 1.2 1\""),
                         kFiles);
    check_against_mujoco("mirror_obj",
                         arm(compiler, "quads.obj", "tetra.obj", "scale=\"1 -0.5 1\""), kFiles);
    // MuJoCo computes a mesh's inertia at its class's geom density; the mesh default scale
    check_against_mujoco("classes",
                         arm(compiler, "box.stl", "tetra.obj", "class=\"light\"",
                             R"(<default><geom density="300"/><mesh scale="0.5 0.5 0.5"/>
                 <default class="light"><geom density="7.5"/><mesh scale="2 1 1"/></default></default>)"),
                         kFiles);
  }
}

TEST_CASE("mesh files are found under compiler/meshdir beside the model", "[compile][mesh]") {
  check_against_mujoco("meshdir", arm("meshdir=\"parts\"", "tetra.stl", "box.obj"), kFiles,
                       "parts/");
}

TEST_CASE("a mesh file is needed only when it must give mass", "[compile][mesh]") {
  // with an <inertial>, or in a group outside inertiagrouprange, the file is not needed (lever
  // reads it if it can, for a geom that can collide, and goes on without it if not)
  const std::string xml = R"(<mujoco>
  <compiler inertiagrouprange="0 2"/>
  <asset><mesh name="m" file="absent.stl"/></asset>
  <worldbody>
    <body name="a">
      <inertial pos="0 0 0" mass="1" diaginertia="0.1 0.1 0.1"/>
      <joint/>
      <geom type="mesh" mesh="m"/>
    </body>
    <body name="b">
      <joint/>
      <geom type="sphere" size="0.1"/>
      <geom type="mesh" mesh="m" group="3"/>
    </body>
  </worldbody>
</mujoco>)";
  const lever::Model m = lever::mjcf::load_string(xml);
  CHECK(m.geom_size[0].isZero());
  CHECK(m.geom_mass[2] == 0.0);
  // the same geom in group 0 needs the file
  std::string needed = xml;
  needed.replace(needed.find(" group=\"3\""), 10, "");
  CHECK_THROWS_WITH(lever::mjcf::load_string(needed),
                    Catch::Contains("cannot read mesh file 'absent.stl'") &&
                        Catch::Contains("add an <inertial> to body 'b'"));
}

// A mesh geom that can collide but gives no mass (its body has an <inertial>): lever reads its
// file all the same, so that its frame, size and bounding radius (geom_rbound) are MuJoCo's; the
// collision stage then finds the contacts MuJoCo finds wherever it comes near another geom, and
// never warns that it cannot collide it (kContactUnsupported).
TEST_CASE("a mesh geom that can collide has MuJoCo's bounding radius, and collides as MuJoCo's",
          "[compile][mesh][collision]") {
  const std::string xml = R"(<mujoco>
  <asset><mesh name="box" file="box.stl"/></asset>
  <worldbody>
    <geom name="rock" type="sphere" size="0.05"/>
    <body name="part" pos="0 0 0.5">
      <inertial pos="0 0 0" mass="1" diaginertia="0.01 0.01 0.01"/>
      <joint name="lift" type="slide" axis="0 0 1"/>
      <geom name="part" type="mesh" mesh="box" pos="0.01 0 0" euler="10 20 30"/>
    </body>
  </worldbody>
</mujoco>)";
  const std::map<std::string, std::string> files{{"box.stl", binary_stl(skewed_box())}};
  check_against_mujoco("colliding", xml, files);  // geom_size, pos, quat and rbound included

  const Folder folder("colliding_run");
  folder.write("model.xml", xml);
  for (const auto& [file, bytes] : files) folder.write(file, bytes);
  const lever::Model ours = lever::mjcf::load_file((folder.path / "model.xml").string());
  REQUIRE(ours.geom_rbound[1] > 0);
  std::string error;
  const lever::test::MjModelHandle theirs = lever::test::mujoco_compile(xml, &error, files);
  REQUIRE(theirs);
  CHECK(ours.geom_rbound[1] == theirs->geom_rbound[1]);
  std::unique_ptr<mjData, void (*)(mjData*)> d(mj_makeData(theirs.get()), mj_deleteData);
  const int unsupported = static_cast<int>(lever::Warning::kContactUnsupported);
  int touching = 0;
  for (int k = 0; k <= 60; ++k) {
    const double lift = -0.6 + 0.01 * k;  // from through the rock to 0.1 m above it
    lever::Data data(ours);
    data.qpos[0] = lift;
    lever::forward(ours, data);
    d->qpos[0] = lift;
    mj_forward(theirs.get(), d.get());
    const bool warns = data.warning[static_cast<size_t>(unsupported)].number > 0;
    INFO("lift " << lift << ": MuJoCo " << d->ncon << " contacts, lever " << data.ncon);
    CHECK(data.ncon == d->ncon);
    CHECK_FALSE(warns);
    touching += d->ncon > 0;
  }
  CHECK(touching >= 5);
  // far above: no warning
  lever::Data far(ours);
  far.qpos[0] = 0.5;
  lever::forward(ours, far);
  CHECK(far.warning[static_cast<size_t>(unsupported)].number == 0);
}

TEST_CASE("a Menagerie-style arm without its <inertial>s takes its masses from its meshes",
          "[compile][mesh][menagerie]") {
  // every link's visual and collision meshes (stand-in tetrahedra, each scaled differently by
  // its file name's length) give it mass, as in MuJoCo
  const std::string path = lever::test::model_path("tests/menagerie/panda_style.xml");
  const std::string xml = lever::test::without_inertials(lever::test::read_text(path));
  const lever::Model with_inertials = lever::mjcf::load_file(path);
  std::map<std::string, std::string> files;
  for (const std::string& f : with_inertials.visual.mesh_file) {
    Shape s = tetrahedron();
    for (Vertex& p : s.v) {
      for (float& x : p) x *= 1.0f + 0.1f * static_cast<float>(f.size() % 7);
    }
    files[f] =
        f.size() >= 4 && f.compare(f.size() - 4, 4, ".obj") == 0 ? obj_triangles(s) : binary_stl(s);
  }
  check_against_mujoco("menagerie", xml, files, "assets/");
}
