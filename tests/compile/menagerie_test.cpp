// A Menagerie-style arm (tests/menagerie/panda_style.xml): mesh geoms whose files are not in the
// repository, materials, a light and a camera, slash-named classes, <general> servos, a keyframe.
// lever loads the file as it is; MuJoCo 2.2.2 compiles it with placeholder meshes, and the two
// compiled models must agree on everything but what MuJoCo fits to the mesh files.
#include <catch2/catch.hpp>
#include <filesystem>
#include <lever/mjcf.hpp>

#include <lever/harness/models.hpp>
#include <lever/harness/placeholder_mesh.hpp>
#include "mujoco_xml.hpp"

namespace {

const std::string kFile = "tests/menagerie/panda_style.xml";

}  // namespace

TEST_CASE("a Menagerie-style arm loads without its mesh files", "[compile][menagerie]") {
  const std::string path = lever::test::model_path(kFile);
  const std::filesystem::path meshdir = std::filesystem::path(path).parent_path() / "assets";
  REQUIRE_FALSE(std::filesystem::exists(meshdir));  // the point: the files are not there
  const lever::Model model = lever::mjcf::load_file(path);
  CHECK(model.nv == 7);
  CHECK(model.nu == 7);
  REQUIRE(model.nkey == 1);
  CHECK(model.key_name[0] == "home");
  CHECK(model.opt.integrator == lever::Integrator::kImplicit);
  CHECK(model.visual.meshdir == "assets");
  CHECK(model.visual.light_name == std::vector<std::string>{"top"});
  CHECK(model.visual.camera_name == std::vector<std::string>{"side"});
  // a mesh without a name is named after its file, as in MuJoCo
  const auto& meshes = model.visual.mesh_name;
  CHECK(std::find(meshes.begin(), meshes.end(), "base_0") != meshes.end());
  for (int g = 0; g < model.ngeom; ++g) {
    CHECK(model.geom_type[static_cast<size_t>(g)] == lever::GeomType::kMesh);
    CHECK(model.geom_mass[static_cast<size_t>(g)] == 0.0);
  }
  // the collision meshes are read to collide, and their files are missing: one warning per mesh
  // (7); then the pairs they would make, the first ten named, each with what to use instead, the
  // rest counted
  REQUIRE(model.warnings.size() == 7 + 11);
  for (size_t k = 0; k < 7; ++k) {
    CHECK_THAT(model.warnings[k], Catch::Contains("mesh geom can collide") &&
                                      Catch::Contains("no such file"));
  }
  for (size_t k = 7; k < 17; ++k) {
    CHECK_THAT(model.warnings[k], Catch::Contains("(mesh, mesh; lines ") &&
                                      Catch::Contains("can collide and lever did not read the mesh") &&
                                      Catch::Contains("primitive collision geoms"));
  }
  CHECK_THAT(model.warnings[17], Catch::StartsWith("and ") && Catch::Contains("more geom pairs"));
}

TEST_CASE("a Menagerie-style arm compiles to MuJoCo 2.2.2's parameters", "[compile][menagerie]") {
  const std::string path = lever::test::model_path(kFile);
  const lever::Model ours = lever::mjcf::load_file(path);
  std::map<std::string, std::string> files;
  for (const std::string& f : ours.visual.mesh_file) files[f] = lever::test::placeholder_mesh(f);
  std::string error;
  const auto theirs = lever::test::mujoco_compile(lever::test::read_text(path), &error, files);
  INFO("MuJoCo: " << error);
  REQUIRE(theirs);
  CHECK(theirs->nmesh == static_cast<int>(ours.visual.mesh_name.size()));
  CHECK(theirs->nmat == static_cast<int>(ours.visual.material_name.size()));
  CHECK(theirs->nlight == static_cast<int>(ours.visual.light_name.size()));
  CHECK(theirs->ncam == static_cast<int>(ours.visual.camera_name.size()));
  for (const std::string& difference : lever::test::compare_parameters(ours, *theirs)) {
    FAIL_CHECK(difference);
  }
  for (const std::string& difference : lever::test::compare_constants(ours, *theirs)) {
    FAIL_CHECK(difference);
  }
}
