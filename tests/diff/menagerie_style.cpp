// The Menagerie-style arm (tests/menagerie/panda_style.xml) against MuJoCo 2.2.2, as the other
// models are (MuJoCo's contacts off: lever has none, and says so at load): random states, and 10 s
// lockstep runs from its `home` keyframe under Euler, RK4 and
// implicit. MuJoCo needs the mesh files the model names, so the test copies the model into a
// fresh folder with placeholder meshes (lever ignores them: every body has an <inertial>).
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <lever/diff/runs.hpp>
#include <lever/mjcf.hpp>
#include <unistd.h>

#include "diff_checks.hpp"
#include <lever/harness/models.hpp>
#include <lever/harness/placeholder_mesh.hpp>
#include "sampling.hpp"

namespace lever::test {

namespace {

// the model beside placeholder mesh files, in a folder removed when the object goes
class ModelWithMeshes {
 public:
  explicit ModelWithMeshes(const std::string& source) {
    dir_ = std::filesystem::temp_directory_path() /
           ("lever-menagerie-" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir_);
    const Model model = mjcf::load_file(source);
    std::filesystem::create_directories(dir_ / model.visual.meshdir);
    for (const std::string& f : model.visual.mesh_file) {
      std::ofstream(dir_ / model.visual.meshdir / f, std::ios::binary) << placeholder_mesh(f);
    }
    file_ = (dir_ / std::filesystem::path(source).filename()).string();
    std::filesystem::copy_file(source, file_);
  }
  ~ModelWithMeshes() {
    std::error_code ignored;
    std::filesystem::remove_all(dir_, ignored);
  }
  ModelWithMeshes(const ModelWithMeshes&) = delete;
  ModelWithMeshes& operator=(const ModelWithMeshes&) = delete;
  const std::string& file() const { return file_; }

 private:
  std::filesystem::path dir_;
  std::string file_;
};

}  // namespace

TEST_CASE("diff: a Menagerie-style arm agrees with MuJoCo on random states and from `home`",
          "[diff][menagerie]") {
  REQUIRE(mj_version() == 222);
  const ModelWithMeshes copy(model_path("tests/menagerie/panda_style.xml"));
  for (const diff::Path path : paths_to_compare()) {
    const std::uint64_t seed = diff::default_seed(copy.file());
    INFO(context(copy.file(), path, seed));
    diff::Twin twin(copy.file(), path);
    REQUIRE(twin.start_name() == "keyframe 'home'");
    // its collision meshes (the placeholder tetrahedra) are read and collided by both
    if (path == diff::Path::kLoader) REQUIRE(twin.model.warnings.empty());
    check_within_bound(diff::random_states(twin, samples(200), seed));
    for (const Integrator integrator : kEveryIntegrator) {
      INFO("lockstep from home, " << integrator_name(integrator));
      check_within_bound(
          diff::lockstep(twin, integrator, run_seconds(10.0), diff::Control::kSmooth));
    }
  }
}

}  // namespace lever::test
