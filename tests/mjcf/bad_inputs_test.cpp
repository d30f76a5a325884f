// Every bad input is refused with one ParseError that names its line, element, attribute and
// problem (see bad_inputs.hpp).
#include "bad_inputs.hpp"

#include <catch2/catch.hpp>
#include <lever/mjcf.hpp>

using lever::mjcf::ParseError;
using lever::test::kBadInputs;

TEST_CASE("every bad input gets one located ParseError", "[mjcf][errors]") {
  STATIC_REQUIRE(sizeof(kBadInputs) / sizeof(kBadInputs[0]) >= 30);
  for (const lever::test::BadInput& bad : kBadInputs) {
    DYNAMIC_SECTION(bad.id) {
      try {
        lever::mjcf::load_string(bad.xml, "bad.xml");
        FAIL(bad.id << ": loaded without an error");
      } catch (const ParseError& e) {
        INFO(bad.id << ": " << e.what());
        CHECK(e.file() == "bad.xml");
        CHECK(e.line() == bad.line);
        CHECK(e.element() == bad.element);
        CHECK(e.attribute() == bad.attribute);
        CHECK_THAT(e.problem(), Catch::Contains(bad.phrase));
        // what() is a compiler-style diagnostic that carries the same facts
        CHECK_THAT(e.what(), Catch::StartsWith("bad.xml"));
        CHECK_THAT(e.what(), Catch::Contains(e.problem()));
      }
    }
  }
}

TEST_CASE("the diagnostic reads like a compiler's", "[mjcf][errors]") {
  const char* xml = R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="elbow" rnage="-1 1"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
</mujoco>)";
  try {
    lever::mjcf::load_string(xml, "arm2.xml");
    FAIL("loaded");
  } catch (const ParseError& e) {
    CHECK(std::string(e.what()) ==
          "arm2.xml:4: error: <joint name=\"elbow\">: unknown attribute 'rnage' (did you mean "
          "'range'?)");
    CHECK(e.element_name() == "elbow");
  }
}

TEST_CASE("a missing file is a ParseError without a line", "[mjcf][errors]") {
  try {
    lever::mjcf::load_file("does/not/exist.xml");
    FAIL("loaded");
  } catch (const ParseError& e) {
    CHECK(e.file() == "does/not/exist.xml");
    CHECK(e.line() == 0);
    CHECK_THAT(e.problem(), Catch::Contains("no such file"));
  }
}

TEST_CASE("an attribute's own line is reported when an element spans lines", "[mjcf][errors]") {
  const char* xml = R"(<mujoco>
  <worldbody>
    <body name="b">
      <joint name="elbow"
             range="-1 1"
             damping="fast"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
</mujoco>)";
  try {
    lever::mjcf::load_string(xml, "multi.xml");
    FAIL("loaded");
  } catch (const ParseError& e) {
    CHECK(e.line() == 6);
    CHECK(e.attribute() == "damping");
    CHECK(e.element_name() == "elbow");
  }
}
