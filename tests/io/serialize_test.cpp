// lever/io/serialize.hpp: the JSON and CSV writers walk the field table.
#include <catch2/catch.hpp>

#include <lever/fields.hpp>
#include <lever/io/serialize.hpp>
#include <lever/lever.hpp>
#include <lever/mjcf.hpp>

#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <lever/harness/models.hpp>

namespace {

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream in(line);
  std::string field;
  while (std::getline(in, field, ',')) fields.push_back(field);
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

// "name":[ as the JSON writer prints a key and its array
std::string key_of(const lever::FieldInfo& info) {
  return std::string(1, '"').append(info.name).append("\":[");
}

}  // namespace

TEST_CASE("the CSV of lever simulate: header names and one number per column", "[serialize]") {
  const lever::Model model = lever::mjcf::load_file(lever::test::model_path("models/arm2.xml"));
  lever::Data data(model);
  data.qpos << 0.6, -1.2;
  data.ctrl << 30, -2;
  lever::forward(model, data);
  const lever::CsvWriter csv(model, lever::simulate_csv_arrays());
  const std::string header = csv.header();
  CHECK(header ==
        "time,qpos[shoulder],qpos[elbow],qvel[shoulder],qvel[elbow],qacc[shoulder],qacc[elbow],"
        "qfrc_bias[shoulder],qfrc_bias[elbow],ctrl[shoulder],ctrl[elbow],actuator_force[shoulder],"
        "actuator_force[elbow],qfrc_constraint[shoulder],qfrc_constraint[elbow]\n");
  const std::string row = csv.row(data);
  REQUIRE(row.back() == '\n');
  const std::vector<std::string> fields = split(row.substr(0, row.size() - 1));
  REQUIRE(fields.size() == 15);
  CHECK(std::stod(fields[0]) == data.time);
  CHECK(std::stod(fields[1]) == data.qpos[0]);  // 17 digits: the same double back
  CHECK(std::stod(fields[5]) == data.qacc[0]);
  CHECK(std::stod(fields[12]) == data.actuator_force[1]);
  CHECK(std::stod(fields[14]) == data.qfrc_constraint[1]);

  // a number that is not finite is an empty field
  data.qvel[1] = std::numeric_limits<double>::quiet_NaN();
  const std::vector<std::string> bad = split(csv.row(data));
  CHECK(bad[4].empty());
}

TEST_CASE("CsvWriter: arrays of several columns, unknown names, limit rows", "[serialize]") {
  const lever::Model model = lever::mjcf::load_file(lever::test::model_path("models/arm2.xml"));
  const lever::CsvWriter csv(model, {"site_xpos", "xquat"});
  CHECK(csv.header().rfind("time,site_xpos[ee][0],site_xpos[ee][1],site_xpos[ee][2],xquat[world]",
                           0) == 0);
  CHECK_THROWS_AS(lever::CsvWriter(model, {"qpos", "no_such_array"}), lever::StateError);
  CHECK_THROWS_WITH(lever::CsvWriter(model, {"efc_force"}), Catch::Contains("efc_force"));
  // a Data of another model is refused, not read out of bounds
  const lever::Model arm3 = lever::mjcf::load_file(lever::test::model_path("models/arm3.xml"));
  const lever::Data other(arm3);
  CHECK_THROWS_AS(csv.row(other), lever::StateError);
}

TEST_CASE("the JSON of a Data holds every array of the table", "[serialize]") {
  const lever::Model model = lever::mjcf::load_file(lever::test::model_path("models/arm3.xml"));
  lever::Data data(model);
  lever::forward(model, data);
  const std::string json = lever::data_to_json(model, data);
  for (const lever::FieldInfo& info : lever::data_field_table()) {
    INFO(info.name);
    CHECK(json.find(key_of(info)) != std::string::npos);
  }
  const std::string model_json = lever::model_to_json(model);
  for (const lever::FieldInfo& info : lever::model_field_table()) {
    INFO(info.name);
    CHECK(model_json.find(key_of(info)) != std::string::npos);
  }
}

TEST_CASE("the JSON of a Data holds its contacts, each with its force", "[serialize]") {
  const lever::Model model = lever::mjcf::load_file(lever::test::model_path("models/box_drop.xml"));
  lever::Data data(model);
  {
    const std::string json = lever::data_to_json(model, data);
    CHECK(json.find("\"ncon\":0,\"contact\":[]") != std::string::npos);
  }
  // the box lying on the table: let it fall and settle
  for (int i = 0; i < 600; ++i) lever::step(model, data);
  lever::forward(model, data);
  REQUIRE(data.ncon > 0);
  const std::string json = lever::data_to_json(model, data);
  CHECK(json.find("\"ncon\":" + std::to_string(data.ncon) + ",") != std::string::npos);
  // one object per contact, each with the mjContact fields, the geoms' names and the force
  for (const char* key :
       {"\"geom1\":", "\"geom2\":", "\"geom1_name\":\"table\"", "\"geom2_name\":\"box\"",
        "\"dist\":", "\"pos\":[", "\"frame\":[", "\"dim\":3", "\"friction\":[", "\"solref\":[",
        "\"solimp\":[", "\"includemargin\":", "\"exclude\":0",
        "\"efc_address\":", "\"mu\":", "\"force\":["}) {
    INFO(key);
    size_t count = 0;
    for (size_t at = json.find(key); at != std::string::npos; at = json.find(key, at + 1)) {
      ++count;
    }
    CHECK(count == static_cast<size_t>(data.ncon));
  }
  // the normal forces hold the box up. The table is level and the box's centre of mass is its
  // body's origin, so Newton's law along z for the box alone reads sum(normal) = m (a_z - g_z),
  // with a_z the free joint's vertical acceleration (what is left of the settling): the forces
  // written are the ones the dynamics used, to rounding.
  double normal = 0;
  for (int i = 0; i < data.ncon; ++i) normal += lever::contact_force(model, data, i)[0];
  const double mass = model.body_mass[1];
  const double weight = mass * -model.opt.gravity.z();
  CHECK(std::abs(normal - mass * (data.qacc[2] - model.opt.gravity.z())) <= 1e-12 * weight);
  CHECK(json.find("\"efc_J\":[") != std::string::npos);
}
