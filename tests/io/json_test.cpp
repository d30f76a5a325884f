// lever/io/json.hpp: the writer on nlohmann-json. Every finite double reads back as the same
// double, a number that is not finite is null, strings are escaped, keys keep their order, and a
// document left half-written writes nothing.
#include <catch2/catch.hpp>

#include <lever/io/json.hpp>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "json_reader.hpp"

namespace {

namespace reader = lever::test::json;

std::uint64_t bits(double x) {
  std::uint64_t b = 0;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

// Finite doubles of every kind: random bit patterns (every exponent, denormals included), random
// values near 1 and near the timestep, the extremes, and the numbers that print awkwardly.
std::vector<double> hard_doubles() {
  std::vector<double> xs = {0.0,
                            -0.0,
                            0.1,
                            1.0 / 3.0,
                            0.002,
                            2.0 / 3.0 * 1e-12,
                            1e21,
                            1e22,
                            123456789012345678.0,
                            std::numeric_limits<double>::max(),
                            std::numeric_limits<double>::lowest(),
                            std::numeric_limits<double>::min(),
                            std::numeric_limits<double>::denorm_min(),
                            -std::numeric_limits<double>::denorm_min(),
                            std::nextafter(1.0, 2.0),
                            std::nextafter(1.0, 0.0)};
  std::mt19937_64 rng(20);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int i = 0; i < 20000; ++i) {
    std::uint64_t b = rng();
    double x = 0;
    std::memcpy(&x, &b, sizeof x);
    if (std::isfinite(x)) xs.push_back(x);
    xs.push_back(unit(rng));
    xs.push_back(1e-3 * unit(rng));
  }
  return xs;
}

}  // namespace

TEST_CASE("json: every finite double reads back bit for bit", "[json]") {
  const std::vector<double> xs = hard_doubles();
  std::string text;
  lever::json::Writer json(&text);
  json.begin_array();
  for (const double x : xs) json.value(x);
  json.end_array();

  const reader::Value parsed = reader::parse(text);  // the tests' own reader: strtod per number
  REQUIRE(parsed.size() == xs.size());
  int differ = 0;
  for (std::size_t i = 0; i < xs.size(); ++i) {
    if (bits(parsed[i].number) != bits(xs[i])) {
      if (++differ <= 5)
        FAIL_CHECK("element " << i << " written " << xs[i] << " read back differs");
    }
  }
  CHECK(differ == 0);
  // a shortest round-trip form, never longer than printf's %.17g
  CHECK(text.find("0.1,") != std::string::npos);
}

TEST_CASE("json: NaN and infinities are null, integers stay integers", "[json]") {
  std::string text;
  lever::json::Writer json(&text);
  json.begin_object();
  json.key("x").begin_array();
  json.value(std::numeric_limits<double>::quiet_NaN());
  json.value(std::numeric_limits<double>::infinity());
  json.value(-std::numeric_limits<double>::infinity());
  json.end_array();
  json.key("n").value(7).key("big").value(9007199254740993L).key("yes").value(true);
  json.end_object();
  CHECK(text == R"({"x":[null,null,null],"n":7,"big":9007199254740993,"yes":true})");
}

TEST_CASE("json: strings are escaped, bytes that are not UTF-8 replaced", "[json]") {
  const std::string awkward =
      std::string("a \"quote\", a \\ and\ta\nnewline, \x01, ") + "\xE9t\xE9";
  std::string text;
  lever::json::Writer json(&text);
  json.begin_object().key(awkward).value(awkward).end_object();
  const reader::Value parsed = reader::parse(text);
  REQUIRE(parsed.keys.size() == 1);
  const std::string expected =
      std::string("a \"quote\", a \\ and\ta\nnewline, \x01, ") + "\xEF\xBF\xBDt\xEF\xBF\xBD";
  CHECK(parsed.keys[0] == expected);
  CHECK(parsed.members[0].string == expected);
  CHECK(text.find('\n') == std::string::npos);  // one document, one line
}

TEST_CASE("json: keys in the order written, nested, one document per line", "[json]") {
  std::string text;
  {
    lever::json::Writer json(&text);
    for (int row = 0; row < 2; ++row) {
      json.begin_object();
      json.key("zeta").value(row);
      json.key("alpha").begin_array().begin_object().key("m").values(Eigen::Vector2d(1, 2));
      json.end_object().begin_array().end_array().end_array();
      json.key("s").value("x");
      json.end_object();
      json.newline();
    }
  }
  CHECK(text ==
        "{\"zeta\":0,\"alpha\":[{\"m\":[1.0,2.0]},[]],\"s\":\"x\"}\n"
        "{\"zeta\":1,\"alpha\":[{\"m\":[1.0,2.0]},[]],\"s\":\"x\"}\n");
}

TEST_CASE("json: a document left half-written writes nothing", "[json]") {
  std::string text;
  {
    lever::json::Writer json(&text);
    json.begin_object().key("a").begin_array().value(1.5);
    // an exception here (a bad state found while writing) leaves the document open
  }
  CHECK(text.empty());
  lever::json::Writer json(&text);
  CHECK_THROWS_AS(json.end_object(), std::logic_error);
  json.begin_object();
  CHECK_THROWS_AS(json.value(1.0), std::logic_error);  // a member needs its key
}
