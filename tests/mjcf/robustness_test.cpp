// No input crashes the loader: it returns a complete model or throws one ParseError. Truncated
// and mutated copies of a real model, deep nesting, binary junk. Also: docs/mjcf-subset.md is
// what schema_markdown() generates.
#include <catch2/catch.hpp>
#include <fstream>
#include <lever/mjcf.hpp>
#include <random>
#include <sstream>

#include <lever/harness/models.hpp>

namespace {

std::string read(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// loads, or throws a located ParseError; anything else fails the test
void load_or_refuse(const std::string& xml) {
  try {
    const lever::Model m = lever::mjcf::load_string(xml, "fuzz.xml");
    CHECK(static_cast<int>(m.body_pos.size()) == m.nbody);
  } catch (const lever::mjcf::ParseError& e) {
    CHECK(e.file() == "fuzz.xml");
    CHECK(!e.problem().empty());
  }
}

std::string nested_bodies(int depth) {
  std::string xml = "<mujoco><worldbody>";
  for (int i = 0; i < depth; ++i) xml += "<body><joint/><geom size=\"0.1\"/>";
  for (int i = 0; i < depth; ++i) xml += "</body>";
  return xml + "</worldbody></mujoco>";
}

}  // namespace

TEST_CASE("every truncation of arm2.xml loads or is refused cleanly", "[mjcf][robustness]") {
  const std::string xml = read(lever::test::model_path("models/arm2.xml"));
  REQUIRE(xml.size() > 100);
  for (size_t n = 0; n < xml.size(); ++n) load_or_refuse(xml.substr(0, n));
}

TEST_CASE("single-character mutations of arm2.xml load or are refused cleanly",
          "[mjcf][robustness]") {
  const std::string xml = read(lever::test::model_path("models/arm2.xml"));
  std::mt19937_64 rng(lever::test::seed_for("arm2.xml"));
  const std::string alphabet = "<>/=\" -.0123456789eE+abcxyz\n\t\x01\xff";
  std::uniform_int_distribution<size_t> where(0, xml.size() - 1), what(0, alphabet.size() - 1);
  for (int trial = 0; trial < 3000; ++trial) {
    std::string mutated = xml;
    mutated[where(rng)] = alphabet[what(rng)];
    load_or_refuse(mutated);
  }
}

TEST_CASE("binary junk is refused", "[mjcf][robustness]") {
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<int> byte(0, 255);
  for (int trial = 0; trial < 200; ++trial) {
    std::string junk(static_cast<size_t>(1 + trial * 5), '\0');
    for (char& c : junk) c = static_cast<char>(byte(rng));
    CHECK_THROWS_AS(lever::mjcf::load_string(junk), lever::mjcf::ParseError);
  }
}

TEST_CASE("deep nesting loads up to the limit and is refused beyond it", "[mjcf][robustness]") {
  // 3 levels for mujoco, worldbody and the body's own children, then one per body
  const lever::Model deep = lever::mjcf::load_string(nested_bodies(90));
  CHECK(deep.nv == 90);
  CHECK(deep.dof_parentid[89] == 88);
  try {
    lever::mjcf::load_string(nested_bodies(5000), "deep.xml");
    FAIL("loaded");
  } catch (const lever::mjcf::ParseError& e) {
    CHECK_THAT(e.problem(), Catch::Contains("nested more than"));
  }
}

TEST_CASE("docs/mjcf-subset.md is generated from the schema table", "[mjcf][docs]") {
  const std::string doc = read(lever::test::model_path("docs/mjcf-subset.md"));
  INFO("regenerate it: lever model --schema > docs/mjcf-subset.md");
  CHECK(doc == lever::mjcf::schema_markdown());
}
