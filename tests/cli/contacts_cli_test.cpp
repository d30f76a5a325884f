// `lever forward` and `lever simulate` on a model with contacts: the JSON holds ncon and
// each contact (mjContact's fields, the geoms' names, its force in its frame), equal to what the
// library computes for the same state, and the forces obey Newton's law for the box they hold; the
// text of `lever forward` lists them.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include <lever/contact_force.hpp>
#include <lever/lever.hpp>
#include <lever/mjcf.hpp>

#include <lever/harness/models.hpp>
#include "json_reader.hpp"
#include "run_lever.hpp"

namespace lever::test {

namespace {

std::string list(const Eigen::VectorXd& v) {
  std::string out;
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%s%.17g", i ? "," : "", v[i]);
    out += buf;
  }
  return out;
}

Eigen::VectorXd numbers(const json::Value& v) {
  Eigen::VectorXd out(static_cast<Eigen::Index>(v.size()));
  for (std::size_t i = 0; i < v.size(); ++i) out[static_cast<Eigen::Index>(i)] = v[i].number;
  return out;
}

// The box dropped onto the table, after it has come to rest (models/box_drop.xml). `qpos` is
// the state forward() was given: forward() normalizes the box's quaternion in place, and a
// quaternion normalized once may move by an ulp when normalized again, so the command is given
// the same numbers the library was.
struct Resting {
  Model model = mjcf::load_file(model_path("models/box_drop.xml"));
  Data data{model};
  Eigen::VectorXd qpos;
  Resting() {
    for (int i = 0; i < 600; ++i) step(model, data);
    qpos = data.qpos;
    forward(model, data);
  }
};

}  // namespace

TEST_CASE("lever forward --json: the contacts of a box on the table, as the library's",
          "[cli][contact]") {
  const Resting rest;
  const Model& model = rest.model;
  const Data& data = rest.data;
  REQUIRE(data.ncon > 0);
  const Run run = run_lever("forward " + quoted(model_path("models/box_drop.xml")) + " --qpos " +
                            list(rest.qpos) + " --qvel " + list(data.qvel) + " --json");
  REQUIRE(run.status == 0);
  const json::Value out = json::parse(run.out);
  REQUIRE(out["ncon"].number == data.ncon);
  REQUIRE(out["contact"].size() == static_cast<std::size_t>(data.ncon));
  REQUIRE(out["efc_J"].size() == static_cast<std::size_t>(data.nefc * model.nv));

  Eigen::Vector3d pushed = Eigen::Vector3d::Zero();  // the contacts' force on the box, world frame
  for (int i = 0; i < data.ncon; ++i) {
    INFO("contact " << i);
    const Contact& c = data.contact[static_cast<std::size_t>(i)];
    const json::Value& theirs = out["contact"][static_cast<std::size_t>(i)];
    CHECK(theirs["geom1"].number == c.geom1);
    CHECK(theirs["geom2"].number == c.geom2);
    CHECK(theirs["geom1_name"].string == "table");
    CHECK(theirs["geom2_name"].string == "box");
    CHECK(theirs["dim"].number == c.dim);
    CHECK(theirs["exclude"].number == c.exclude);
    CHECK(theirs["efc_address"].number == c.efc_address);
    CHECK(theirs["dist"].number == c.dist);
    CHECK(theirs["mu"].number == c.mu);
    CHECK(numbers(theirs["pos"]) == Eigen::VectorXd(c.pos));
    CHECK(numbers(theirs["frame"]) == Eigen::Map<const Eigen::VectorXd>(c.frame.data(), 9));
    const Eigen::VectorXd force = numbers(theirs["force"]);
    CHECK(force == Eigen::VectorXd(contact_force(model, data, i)));
    CHECK(force[0] > 0);  // the table pushes the box up
    // frame rows are the normal and the tangents: the world force is frame^T f
    pushed += c.frame.transpose() * force.head<3>();
  }
  // Newton for the free box (its frame origin is its centre of mass): m qacc = m g + contacts
  const double mass = model.body_mass[1];
  const Eigen::Vector3d qacc = numbers(out["qacc"]).head<3>();
  const Eigen::Vector3d newton = mass * qacc - mass * model.opt.gravity - pushed;
  INFO("m a - m g - F = " << newton.transpose());
  CHECK(newton.norm() <= 1e-12 * mass * model.opt.gravity.norm());
}

TEST_CASE("lever forward lists the contacts in its text", "[cli][contact]") {
  const Resting rest;
  const Run run = run_lever("forward " + quoted(model_path("models/box_drop.xml")) + " --qpos " +
                            list(rest.qpos) + " --qvel " + list(rest.data.qvel));
  REQUIRE(run.status == 0);
  CHECK_THAT(run.out, Catch::Contains("contacts: ncon " + std::to_string(rest.data.ncon)));
  std::istringstream lines(run.out.substr(run.out.find("contacts: ncon")));
  std::string line;
  std::getline(lines, line);  // the title
  std::getline(lines, line);  // the header
  CHECK_THAT(line, Catch::Contains("geom1") && Catch::Contains("normal N"));
  for (int i = 0; i < rest.data.ncon; ++i) {
    std::getline(lines, line);
    INFO(line);
    CHECK_THAT(line, Catch::Contains("table") && Catch::Contains("box"));
  }
  // a model that cannot make contacts has no such section
  const Run arm = run_lever("forward " + quoted(model_path("models/arm2.xml")));
  REQUIRE(arm.status == 0);
  CHECK_THAT(arm.out, !Catch::Contains("contacts:"));
}

TEST_CASE("lever simulate --json: each line's contacts, from falling to resting",
          "[cli][contact]") {
  const Run run =
      run_lever("simulate " + quoted(model_path("models/box_drop.xml")) + " --steps 600 --json");
  REQUIRE(run.status == 0);
  std::istringstream lines(run.out);
  int count = 0, first_ncon = -1, last_ncon = -1;
  for (std::string line; std::getline(lines, line); ++count) {
    const json::Value row = json::parse(line);
    const int ncon = static_cast<int>(row["ncon"].number);
    REQUIRE(row["contact"].size() == static_cast<std::size_t>(ncon));
    for (std::size_t i = 0; i < row["contact"].size(); ++i) {
      CHECK(row["contact"][i]["force"][0].number >= 0);  // contacts only push
    }
    if (first_ncon < 0) first_ncon = ncon;
    last_ncon = ncon;
  }
  CHECK(count == 601);
  CHECK(first_ncon == 0);  // dropped from above the table
  const Resting rest;      // the same run in the library
  CHECK(last_ncon == rest.data.ncon);
}

// With elliptic cones a contact has dim rows (a pyramid 2 (dim - 1)): the box resting on its four
// corners, condim 3, has 12 rows, and each contact's force is read from its own three.
TEST_CASE("lever forward and simulate with elliptic cones: every contact's force",
          "[cli][contact][elliptic]") {
  std::string xml;
  {
    std::ifstream in(model_path("models/box_drop.xml"));
    xml.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  const std::string option = "<option timestep=\"0.002\"/>";
  REQUIRE(xml.find(option) != std::string::npos);
  xml.replace(xml.find(option), option.size(),
              "<option timestep=\"0.002\" cone=\"elliptic\"/>");
  const std::string file = temporary_file("box_drop_elliptic.xml", xml);
  const Model model = mjcf::load_file(file);
  REQUIRE(model.opt.cone == Cone::kElliptic);
  Data data(model);
  for (int i = 0; i < 600; ++i) step(model, data);
  const Eigen::VectorXd qpos = data.qpos;
  forward(model, data);
  REQUIRE(data.ncon == 4);
  REQUIRE(data.nefc == 12);

  const std::string state = " --qpos " + list(qpos) + " --qvel " + list(data.qvel);
  const Run json_run = run_lever("forward " + quoted(file) + state + " --json");
  INFO(json_run.out);
  REQUIRE(json_run.status == 0);
  const json::Value out = json::parse(json_run.out);
  REQUIRE(out["contact"].size() == 4);
  double normal = 0;
  for (int i = 0; i < data.ncon; ++i) {
    const Eigen::VectorXd force = numbers(out["contact"][static_cast<std::size_t>(i)]["force"]);
    CHECK(force == Eigen::VectorXd(contact_force(model, data, i)));
    // elliptic rows are the force's components: the normal one is the contact's first row
    CHECK(force[0] == data.efc_force[data.contact[static_cast<std::size_t>(i)].efc_address]);
    normal += force[0];
  }
  // at rest the table carries the box's weight
  CHECK(std::abs(normal - model.body_mass[1] * model.opt.gravity.norm()) <= 1e-6 * normal);

  const Run text = run_lever("forward " + quoted(file) + state, true);
  CHECK(text.status == 0);
  CHECK_THAT(text.out, Catch::Contains("contacts: ncon 4") && !Catch::Contains("rows run past"));

  const Run sim = run_lever("simulate " + quoted(file) + " --steps 600 --json");
  CHECK(sim.status == 0);
  CHECK_THAT(sim.out, !Catch::Contains("rows run past"));
  std::istringstream lines(sim.out);
  std::string line, last;
  while (std::getline(lines, line)) last = line;
  CHECK(json::parse(last)["ncon"].number == 4);
}

}  // namespace lever::test

TEST_CASE("lever forward lists the sensors, and --time sets what a clock reads", "[cli][sensors]") {
  using lever::test::run_lever;
  const std::string model = lever::test::quoted(lever::test::model_path("tests/models/sensors.xml"));
  const lever::test::Run json_run = run_lever("forward " + model + " --key bent --time 2.5 --json");
  REQUIRE(json_run.status == 0);
  const lever::test::json::Value out = lever::test::json::parse(json_run.out);
  const lever::Model m = lever::mjcf::load_file(lever::test::model_path("tests/models/sensors.xml"));
  REQUIRE(out["sensordata"].size() == static_cast<std::size_t>(m.nsensordata));
  const int clock = m.sensor_adr[static_cast<std::size_t>(m.sensor("clock"))];
  CHECK(out["sensordata"][static_cast<std::size_t>(clock)].number == 2.5);
  CHECK(out["cfrc_int"].size() == static_cast<std::size_t>(6 * m.nbody));
  const lever::test::Run text = run_lever("forward " + model + " --time 2.5");
  CHECK_THAT(text.out, Catch::Contains("sensors: " + std::to_string(m.nsensor)));
  CHECK_THAT(text.out, Catch::Contains("clock"));
}

TEST_CASE("lever simulate writes each sensor's numbers as columns name[i], and lever model lists "
          "the sensors", "[cli][sensors]") {
  using lever::test::run_lever;
  const std::string path = lever::test::model_path("tests/models/sensors.xml");
  const lever::Model m = lever::mjcf::load_file(path);
  const lever::test::Run csv = run_lever("simulate " + lever::test::quoted(path) +
                                         " --key bent --steps 3 --csv -");
  REQUIRE(csv.status == 0);
  std::istringstream lines(csv.out);
  std::string header;
  std::getline(lines, header);
  std::vector<std::string> columns;
  {
    std::istringstream fields(header);
    for (std::string f; std::getline(fields, f, ',');) columns.push_back(f);
  }
  const auto column = [&columns](const std::string& name) {
    const auto it = std::find(columns.begin(), columns.end(), name);
    return it == columns.end() ? -1 : static_cast<int>(it - columns.begin());
  };
  int sensor_columns = 0;
  for (int s = 0; s < m.nsensor; ++s) {
    for (int k = 0; k < m.sensor_dim[s]; ++k) {
      const std::string name = m.sensor_name[s].empty()
                                   ? "sensordata[" + std::to_string(m.sensor_adr[s] + k) + "]"
                                   : m.sensor_name[s] + "[" + std::to_string(k) + "]";
      CHECK(column(name) >= 0);
      sensor_columns += column(name) >= 0;
    }
  }
  CHECK(sensor_columns == m.nsensordata);
  // the clock reads the row's time and the encoder its joint's qpos, on every row
  const int time = column("time"), clock = column("clock[0]"), yaw = column("yaw_pos[0]");
  const int qpos_yaw = column("qpos[yaw]");
  REQUIRE((time >= 0 && clock >= 0 && yaw >= 0 && qpos_yaw >= 0));
  int rows = 0;
  for (std::string line; std::getline(lines, line); ++rows) {
    std::vector<std::string> fields;
    std::istringstream in(line);
    for (std::string f; std::getline(in, f, ',');) fields.push_back(f);
    REQUIRE(fields.size() == columns.size());
    CHECK(fields[clock] == fields[time]);
    CHECK(fields[yaw] == fields[qpos_yaw]);
  }
  CHECK(rows == 4);

  const lever::test::Run json =
      run_lever("simulate " + lever::test::quoted(path) + " --steps 2 --json");
  REQUIRE(json.status == 0);
  std::istringstream json_lines(json.out);
  std::string first;
  std::getline(json_lines, first);
  CHECK(lever::test::json::parse(first)["sensordata"].size() ==
        static_cast<std::size_t>(m.nsensordata));
  const lever::test::Run arm2 = run_lever(
      "simulate " + lever::test::quoted(lever::test::model_path("models/arm2.xml")) +
      " --steps 1 --json");
  CHECK(arm2.out.find("sensordata") == std::string::npos);  // no sensors: the rows as before

  const lever::test::Run text = run_lever("model " + lever::test::quoted(path));
  REQUIRE(text.status == 0);
  CHECK_THAT(text.out, Catch::Contains("sensors (" + std::to_string(m.nsensor) + ", " +
                                       std::to_string(m.nsensordata) + " numbers"));
  CHECK_THAT(text.out, Catch::Matches("(.|\n)*hand_in_base +framepos +geom hand in xbody base "
                                      "+sensordata\\[\\d+\\.\\.\\d+\\](.|\n)*"));
  CHECK_THAT(text.out, Catch::Contains("cutoff 0.5"));
  const lever::test::Run model_json = run_lever("model " + lever::test::quoted(path) + " --json");
  REQUIRE(model_json.status == 0);
  const lever::test::json::Value compiled = lever::test::json::parse(model_json.out);
  CHECK(compiled["nsensordata"].number == m.nsensordata);
  REQUIRE(compiled["sensor_name"].size() == static_cast<std::size_t>(m.nsensor));
  for (int s = 0; s < m.nsensor; ++s) {
    CHECK(compiled["sensor_name"][static_cast<std::size_t>(s)].string == m.sensor_name[s]);
  }
}
