// Every model file in the shared real robots (../shared/robots: MuJoCo 2.2.2's samples, Menagerie
// 2022, every one of which MuJoCo 2.2.2 loads), as a user would load it: it must either load in
// lever, with the compiled model agreeing with MuJoCo's, or be refused by a ParseError that names
// the feature lever does not have: never a crash, never another exception, never a generic error
// (unless MuJoCo refuses the file too). No file is skipped: the table of every file, what MuJoCo
// does, what lever does, is printed (Markdown, on stdout). With LEVER_ROBOT_FILES_EVERY_FEATURE
// set, it also lists every feature lever refuses in each file, not only the first
// (robot_files.hpp).
#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <lever/mjcf.hpp>
#include <sstream>

#include "mujoco_xml.hpp"
#include "robot_files.hpp"

namespace {

struct RobotRow {
  std::string file;     // relative to the robots folder
  std::string mujoco;   // "loads" or MuJoCo's message
  std::string lever;    // "loads", "refuses <feature>", or what went wrong
  std::string refused;  // every feature refused, when counting them (robot_files.hpp)
  bool ok = false;
};

std::string first_line(const std::string& text) {
  const std::string line = text.substr(0, text.find('\n'));
  return line.size() > 100 ? line.substr(0, 100) + "..." : line;
}

}  // namespace

TEST_CASE("every real robot file MuJoCo 2.2.2 loads loads in lever or is refused by name",
          "[compile][robots]") {
  const std::string root = lever::test::robots_dir();
  INFO("the real robot files are looked for in " << root
                                                 << " (../shared/robots beside the checkout, or "
                                                    "$LEVER_ROBOTS_DIR)");
  REQUIRE(std::filesystem::is_directory(root));
  const std::vector<std::string> files = lever::test::robot_files(root);
  REQUIRE(files.size() >= 30);

  // every refused feature, not only the first, costs a load per feature: on request
  const bool count_every_feature = std::getenv("LEVER_ROBOT_FILES_EVERY_FEATURE") != nullptr;
  std::vector<RobotRow> rows;
  for (const std::string& path : files) {
    RobotRow row;
    row.file = std::filesystem::relative(path, root).string();
    // MuJoCo's load (seconds for the large meshes) is asked for only where it decides the row:
    // a file lever loads is compared with it, a generic error is right only if MuJoCo refuses too
    const auto mujoco_load = [&]() {
      char error[1000] = "";
      lever::test::MjModelHandle m(mj_loadXML(path.c_str(), nullptr, error, sizeof error),
                                   mj_deleteModel);
      row.mujoco = m ? "loads" : "refuses: " + first_line(error);
      return m;
    };
    row.mujoco = "not asked";
    try {
      const lever::Model ours = lever::mjcf::load_file(path);
      row.lever = "loads";
      const lever::test::MjModelHandle theirs = mujoco_load();
      if (theirs) {
        std::vector<std::string> differences = lever::test::compare_parameters(ours, *theirs);
        for (const std::string& d : lever::test::compare_constants(ours, *theirs)) {
          differences.push_back(d);
        }
        row.ok = differences.empty();
        if (!row.ok) row.lever += ", differs: " + differences.front();
      }
    } catch (const lever::mjcf::ParseError& e) {
      const std::string feature = lever::test::refused_feature(e);
      row.lever = feature.empty() ? "error: " + first_line(e.what()) : "refuses " + feature;
      row.ok = !feature.empty() || !mujoco_load();
      if (!feature.empty() && count_every_feature) {
        row.refused = lever::test::every_refused_feature(path);
      }
    } catch (const std::exception& e) {
      row.lever = std::string("unexpected exception: ") + e.what();
    }
    rows.push_back(row);
  }

  std::ostringstream table;
  int loaded = 0;
  table << "| file | MuJoCo 2.2.2 | lever | every refused feature |\n|---|---|---|---|\n";
  for (const RobotRow& r : rows) {
    table << "| " << r.file << " | " << r.mujoco << " | " << r.lever << " | " << r.refused
          << " |\n";
    if (r.lever == "loads") ++loaded;
  }
  table << "\n" << loaded << " of " << rows.size() << " files load in lever.\n";
  std::cout << table.str();
  for (const RobotRow& r : rows) {
    INFO(r.file << ": MuJoCo " << r.mujoco << "; lever " << r.lever);
    CHECK(r.ok);
    // lever has <include>: every scene reaches its robot
    CHECK(r.lever.find("<include") == std::string::npos);
  }
  // the files that loaded before <include> (7), the scenes of those (ur5e, humanoid100) since
  CHECK(loaded >= 9);
}
