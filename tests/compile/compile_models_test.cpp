// Every model of the repository (models/ and tests/models/), compiled by mjcf_lite and by
// MuJoCo 2.2.2, must agree field by field to |a - b| <= 1e-12 max(1, |b|) (quaternions up to sign).
#include <catch2/catch.hpp>
#include <filesystem>
#include <lever/mjcf.hpp>

#include "mujoco_xml.hpp"
#include <lever/harness/models.hpp>

namespace {

using lever::test::all_model_files;

std::string file_name(const std::string& path) {
  return std::filesystem::path(path).filename().string();
}

// one failed check per difference, at most `limit` of them, so a broken model stays readable
void report(const std::string& model, const std::vector<std::string>& differences) {
  constexpr size_t limit = 40;
  for (size_t i = 0; i < differences.size() && i < limit; ++i) {
    FAIL_CHECK(model << ": " << differences[i]);
  }
  if (differences.size() > limit) {
    FAIL_CHECK(model << ": ... and " << differences.size() - limit << " more differences");
  }
}

// lever's model and mujoco's of the same text, or the message of whichever refused it
struct Pair {
  lever::Model ours;
  lever::test::MjModelHandle theirs{nullptr, mj_deleteModel};
  std::string our_error, their_error;
  bool ours_loaded = false;
};

Pair compile_both(const std::string& name, const std::string& xml, bool infer_inertia) {
  Pair p;
  lever::mjcf::LoadOptions options;
  options.infer_inertia_from_geoms = infer_inertia;
  try {
    p.ours = lever::mjcf::load_string(xml, name, options);
    p.ours_loaded = true;
  } catch (const lever::mjcf::ParseError& e) {
    p.our_error = e.what();
  }
  p.theirs = lever::test::mujoco_compile(xml, &p.their_error);
  return p;
}

// both must load (a model of the repository is meant to be valid)
Pair load_both(const std::string& path, const std::string& xml, bool infer_inertia) {
  Pair p = compile_both(file_name(path), xml, infer_inertia);
  if (!p.ours_loaded) FAIL(file_name(path) << ": lever cannot load it: " << p.our_error);
  if (!p.theirs) FAIL(file_name(path) << ": MuJoCo cannot load it: " << p.their_error);
  return p;
}

}  // namespace

TEST_CASE("every model compiles to MuJoCo 2.2.2's parameters", "[compile]") {
  const std::vector<std::string> files = all_model_files();
  REQUIRE(!files.empty());
  for (const std::string& path : files) {
    DYNAMIC_SECTION(file_name(path)) {
      const Pair p = load_both(path, lever::test::read_text(path), false);
      report(file_name(path), lever::test::compare_parameters(p.ours, *p.theirs));
    }
  }
}

TEST_CASE("every model without its <inertial> elements infers inertia as MuJoCo does",
          "[compile]") {
  // lever's LoadOptions::infer_inertia_from_geoms against MuJoCo on the text without them; a
  // model may then be refused (inertiafromgeom="false" leaves its moving bodies massless), and
  // then both must refuse it
  for (const std::string& path : all_model_files()) {
    DYNAMIC_SECTION(file_name(path)) {
      const std::string xml = lever::test::read_text(path);
      const Pair removed =
          compile_both(file_name(path), lever::test::without_inertials(xml), false);
      const Pair ignored = compile_both(file_name(path), xml, true);
      INFO("lever: " << removed.our_error << "\nmujoco: " << removed.their_error);
      REQUIRE(removed.ours_loaded == static_cast<bool>(removed.theirs));
      REQUIRE(ignored.ours_loaded == removed.ours_loaded);
      if (!removed.theirs) continue;
      report(file_name(path) + " (no <inertial>)",
             lever::test::compare_parameters(removed.ours, *removed.theirs));
      report(file_name(path) + " (infer_inertia_from_geoms)",
             lever::test::compare_parameters(ignored.ours, *removed.theirs));
    }
  }
}

TEST_CASE("every model's set_const constants agree with mj_setConst", "[compile][set_const]") {
  // dof_invweight0, dof_M0, body_subtreemass, body_invweight0: computed by the engine's
  // set_const() from the compiled parameters, so they agree once both the compiler and
  // set_const do
  for (const std::string& path : all_model_files()) {
    DYNAMIC_SECTION(file_name(path)) {
      const Pair p = load_both(path, lever::test::read_text(path), false);
      report(file_name(path), lever::test::compare_constants(p.ours, *p.theirs));
    }
  }
}
