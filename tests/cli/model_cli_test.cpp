// `lever model`'s text: each joint named by its kind (free, ball, slide, hinge) with the units of
// that kind, on tests/models/floating.xml, which has all four.
#include <catch2/catch.hpp>

#include <sstream>
#include <string>

#include <lever/harness/models.hpp>
#include "run_lever.hpp"

namespace lever::test {

namespace {

// the line of joint `name` in the "joints" section
std::string joint_line(const std::string& out, const std::string& name) {
  std::istringstream lines(out.substr(out.find("joints (")));
  std::string line;
  while (std::getline(lines, line)) {
    if (line.rfind("  " + name + " ", 0) == 0) return line;
  }
  return "";
}

}  // namespace

TEST_CASE("lever model names free, ball, slide and hinge joints by their kind", "[cli][model]") {
  const Run run = run_lever("model " + quoted(model_path("tests/models/floating.xml")));
  REQUIRE(run.status == 0);
  struct Expected {
    const char* joint;
    const char* kind;
    const char* damping_unit;
    bool axis;
  };
  const Expected joints[] = {
      {"float", "free", "N s/m, N m s/rad", false},  // a free joint and a freejoint alike
      {"spin", "free", "N s/m, N m s/rad", false},
      {"shoulder", "ball", "N m s/rad", false},
      {"hinge", "hinge", "N m s/rad", true},
      {"slide", "slide", "N s/m", true},
  };
  for (const Expected& e : joints) {
    const std::string line = joint_line(run.out, e.joint);
    INFO(run.out);
    INFO(e.joint << ": " << line);
    REQUIRE(!line.empty());
    std::istringstream words(line);
    std::string name, kind;
    words >> name >> kind;
    CHECK(kind == e.kind);
    CHECK_THAT(line, Catch::Contains(std::string("damping 0.05 ") + e.damping_unit) ||
                         Catch::Contains(std::string("damping 0 ") + e.damping_unit));
    CHECK((line.find("axis (") != std::string::npos) == e.axis);
  }
  // a free joint has no range; a ball joint's is an angle
  CHECK_THAT(joint_line(run.out, "float"), !Catch::Contains("range"));
  CHECK_THAT(joint_line(run.out, "shoulder"), Catch::Contains("rad  limited no"));
}

}  // namespace lever::test
