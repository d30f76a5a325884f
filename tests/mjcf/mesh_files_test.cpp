// Mesh files on their own (no MuJoCo): a cube whose mass properties are known by hand, and every
// kind of bad mesh file, each refused with one ParseError located at the geom that needed it,
// naming the file and saying how to do without it.
#include <array>
#include <catch2/catch.hpp>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <lever/mjcf.hpp>
#include <limits>
#include <string>
#include <vector>

namespace {

using Vertex = std::array<float, 3>;

// an axis-aligned box of half sizes h centred at c, outward triangles (corner = x + 2 y + 4 z)
std::vector<std::array<Vertex, 3>> cube(const Vertex& c, const Vertex& h) {
  std::vector<Vertex> v;
  for (int k = 0; k < 8; ++k) {
    v.push_back({c[0] + ((k & 1) ? h[0] : -h[0]), c[1] + ((k & 2) ? h[1] : -h[1]),
                 c[2] + ((k & 4) ? h[2] : -h[2])});
  }
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  std::vector<std::array<Vertex, 3>> t;
  for (const auto& q : quads) {
    t.push_back(
        {v[static_cast<size_t>(q[0])], v[static_cast<size_t>(q[1])], v[static_cast<size_t>(q[2])]});
    t.push_back(
        {v[static_cast<size_t>(q[0])], v[static_cast<size_t>(q[2])], v[static_cast<size_t>(q[3])]});
  }
  return t;
}

std::string stl(const std::vector<std::array<Vertex, 3>>& triangles) {
  std::string bytes(80, ' ');
  const auto put = [&bytes](const void* p, std::size_t n) {
    bytes.append(static_cast<const char*>(p), n);
  };
  const std::uint32_t count = static_cast<std::uint32_t>(triangles.size());
  put(&count, sizeof count);
  for (const auto& t : triangles) {
    const float normal[3] = {0, 0, 0};
    put(normal, sizeof normal);
    for (const Vertex& p : t) put(p.data(), sizeof p);
    const std::uint16_t attribute = 0;
    put(&attribute, sizeof attribute);
  }
  return bytes;
}

struct Folder {
  std::filesystem::path path;
  explicit Folder(const std::string& name) {
    path =
        std::filesystem::temp_directory_path() /
        ("lever_meshfile_" + name + "_" + std::to_string(reinterpret_cast<std::uintptr_t>(this)));
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~Folder() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  std::string write(const std::string& name, const std::string& bytes) const {
    std::ofstream(path / name, std::ios::binary) << bytes;
    return (path / name).string();
  }
};

// a moving body whose mass comes from one mesh geom (line 6)
std::string model(const std::string& file, const std::string& compiler = "") {
  return R"(<mujoco>
  <compiler )" +
         compiler + R"(/>
  <asset><mesh name="part" file=")" +
         file + R"("/></asset>
  <worldbody>
    <body name="link">
      <joint/><geom name="shell" type="mesh" mesh="part" pos="1 0 0"/>
    </body>
  </worldbody>
</mujoco>)";
}

}  // namespace

TEST_CASE("a box's mesh mass properties match the formulas", "[mjcf][mesh]") {
  // MuJoCo computes face centres and edges in float, so its numbers (and lever's, which agree
  // with them to 1e-12: tests/compile/mesh_test.cpp) are the formulas' to float precision only
  const Folder folder("box");
  folder.write("box.stl", stl(cube({0.25f, 0.5f, -0.125f}, {0.125f, 0.25f, 0.0625f})));
  for (const char* exact : {"false", "true"}) {
    folder.write("model.xml", model("box.stl", std::string("exactmeshinertia=\"") + exact + "\""));
    const lever::Model m = lever::mjcf::load_file((folder.path / "model.xml").string());
    const double mass = 1000 * 0.25 * 0.5 * 0.125;
    constexpr double kFloat = 1e-6;
    CHECK(m.geom_mass[0] == Approx(mass).epsilon(kFloat));
    CHECK(m.body_mass[1] == Approx(mass).epsilon(kFloat));
    // the geom frame moved to the box's centre (the geom's pos="1 0 0" added)
    CHECK(m.geom_pos[0].x() == Approx(1.25).epsilon(kFloat));
    CHECK(m.geom_pos[0].y() == Approx(0.5).epsilon(kFloat));
    CHECK(m.geom_pos[0].z() == Approx(-0.125).epsilon(kFloat));
    // principal axes in decreasing moment order: z, x, y; the size is the box in that frame
    const double x = 0.125, y = 0.25, z = 0.0625;
    const double moments[3] = {mass * (x * x + y * y) / 3, mass * (y * y + z * z) / 3,
                               mass * (x * x + z * z) / 3};
    const double sizes[3] = {z, x, y};
    for (int k = 0; k < 3; ++k) {
      CHECK(m.geom_size[0][k] == Approx(sizes[k]).epsilon(kFloat));
      CHECK(m.body_inertia[1][k] == Approx(moments[k]).epsilon(kFloat));
    }
  }
}

TEST_CASE("bad mesh files are refused at the geom that needs them", "[mjcf][mesh][errors]") {
  const Folder folder("bad");
  std::string stl_bytes = stl(cube({0, 0, 0}, {0.1f, 0.1f, 0.1f}));
  std::string nan_bytes = stl_bytes;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(&nan_bytes[84 + 12], &nan, sizeof nan);
  std::vector<std::array<Vertex, 3>> flat = cube({0, 0, 0}, {0.1f, 0.1f, 0.1f});
  for (auto& t : flat) {
    for (Vertex& p : t) p[2] = 0;
  }
  std::vector<std::array<Vertex, 3>> inward = cube({0, 0, 0}, {0.1f, 0.1f, 0.1f});
  for (auto& t : inward) std::swap(t[1], t[2]);
  struct Bad {
    const char* file;
    std::string bytes;
    const char* compiler;
    const char* phrase;
  };
  const Bad bad[] = {
      {"empty.stl", "", "", "the file is empty"},
      {"short.stl", stl_bytes.substr(0, stl_bytes.size() - 7), "", "a binary STL of 12 triangles"},
      {"ascii.stl",
       "solid cube\n  facet normal 0 0 1\n    outer loop\n      vertex 0 0 0\n"
       "      vertex 1 0 0\n      vertex 0 1 0\n    endloop\n  endfacet\nendsolid\n",
       "", "ASCII STL"},
      {"nan.stl", nan_bytes, "", "not finite"},
      // a mesh that can collide gets its convex hull first, as in MuJoCo: qhull refuses it
      {"flat.stl", stl(flat), "", "qhull could not build the convex hull"},
      {"inward.stl", stl(inward), "exactmeshinertia=\"true\"", "volume is too small"},
      {"word.obj", "v 0 0 0\nv 1 0 x\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n", "",
       "line 2: 'x' is not a finite number"},
      {"penta.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nf 1 2 3 4 5\n", "",
       "faces of 3 or 4 vertices"},
      {"concave.obj", "v 0 0 0\nv 0.5 0.5 0\nv 2 0 0\nv 0 2 0\nf 1 2 3 4\n", "",
       "non-convex or folded quadrilateral"},
      {"range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", "", "vertex index out of range"},
      {"noface.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n", "", "no faces"},
      {"twice.obj",
       "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n", "",
       "inconsistent orientation"},
      {"line.obj", "v 0 0 0\nv 1 0 0\nl 1 2\n", "", "does not read OBJ 'l' lines"},
      {"part.msh", "x", "", "not binary STL or OBJ"},
  };
  for (const Bad& b : bad) {
    DYNAMIC_SECTION(b.file) {
      const std::string path = folder.write(b.file, b.bytes);
      const std::string xml = folder.write("model.xml", model(b.file, b.compiler));
      try {
        lever::mjcf::load_file(xml);
        FAIL(b.file << ": loaded");
      } catch (const lever::mjcf::ParseError& e) {
        INFO(e.what());
        CHECK(e.line() == 6);
        CHECK(e.element() == "geom");
        CHECK(e.attribute() == "mesh");
        CHECK_THAT(e.problem(), Catch::Contains(b.phrase) && Catch::Contains(path) &&
                                    Catch::Contains("mesh geom 'shell'") &&
                                    Catch::Contains("add an <inertial> to body 'link'"));
      }
    }
  }
  SECTION("a missing file and a folder in its place") {
    std::filesystem::create_directories(folder.path / "dir.stl");
    for (const char* file : {"missing.stl", "dir.stl"}) {
      const std::string xml = folder.write("model.xml", model(file));
      CHECK_THROWS_WITH(lever::mjcf::load_file(xml),
                        Catch::Contains("cannot read mesh file '" + (folder.path / file).string()));
    }
  }
}
