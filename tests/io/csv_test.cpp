// lever/io/csv.hpp: the CSV reader, on what the CSV writer writes (every number read back
// exactly) and on text written by hand: quoting, blank lines, carriage returns, and each error
// located by file, line and column.
#include <catch2/catch.hpp>

#include <lever/error.hpp>
#include <lever/io/csv.hpp>
#include <lever/io/serialize.hpp>
#include <lever/lever.hpp>
#include <lever/mjcf.hpp>

#include <random>
#include <string>

#include <lever/harness/models.hpp>

using lever::io::CsvTable;

TEST_CASE("csv: what CsvWriter writes reads back number for number", "[io][csv]") {
  const lever::Model model = lever::mjcf::load_file(lever::test::model_path("models/panda7.xml"));
  lever::Data data(model);
  const lever::CsvWriter writer(model, lever::simulate_csv_arrays());
  std::string text = writer.header();
  std::mt19937_64 rng(lever::test::seed_for("csv_test"));
  std::uniform_real_distribution<double> uniform(-1, 1);
  std::vector<lever::Data> states;
  for (int k = 0; k < 5; ++k) {
    for (int i = 0; i < model.nq; ++i) data.qpos[i] = uniform(rng);
    for (int i = 0; i < model.nv; ++i) data.qvel[i] = uniform(rng);
    data.time = 0.01 * k;
    lever::forward(model, data);
    text += writer.row(data);
    states.push_back(data);
  }
  const CsvTable table = CsvTable::parse(text, "written.csv");
  REQUIRE(table.rows() == 5);
  for (int k = 0; k < 5; ++k) {
    CHECK(table.line(k) == k + 2);
    CHECK(table.number(k, table.column("time")) == states[k].time);
    for (int j = 0; j < model.njnt; ++j) {
      const std::string joint = model.jnt_name[j];
      CHECK(table.number(k, table.column("qpos[" + joint + "]")) == states[k].qpos[j]);
      CHECK(table.number(k, table.column("qacc[" + joint + "]")) == states[k].qacc[j]);
    }
  }
  CHECK(table.column("no such column") == -1);
}

TEST_CASE("csv: quoted fields, blank lines and carriage returns", "[io][csv]") {
  const CsvTable table =
      CsvTable::parse("time,\"a, b\",\"say \"\"hi\"\"\"\r\n\n0.5,\"1,5\",x\r\n\r\n2,3,\"\"\n", "t");
  REQUIRE(table.header() == std::vector<std::string>{"time", "a, b", "say \"hi\""});
  REQUIRE(table.rows() == 2);
  CHECK(table.line(0) == 3);
  CHECK(table.line(1) == 5);
  CHECK(table.field(0, 1) == "1,5");
  CHECK(table.number(1, table.column("a, b")) == 3);
  CHECK(table.field(1, 2).empty());
}

TEST_CASE("csv: errors name the file, the line and the column", "[io][csv]") {
  const auto message = [](const std::string& text) {
    try {
      (void)CsvTable::parse(text, "bad.csv");
    } catch (const lever::Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK(message("") == "bad.csv:1: empty file: expected a header row.");
  CHECK(message("a,b\n1,2\n\n1,2,3\n") == "bad.csv:4: 3 fields, the header has 2.");
  const CsvTable table = CsvTable::parse("a,b\n1,2\n\n1,x\n3,nan\n4,1e999\n5,\n", "bad.csv");
  CHECK(table.number(0, 1) == 2);
  const auto number_error = [&](int row) {
    try {
      (void)table.number(row, 1);
    } catch (const lever::Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK(number_error(1) == "bad.csv:4: column 'b': 'x' is not a finite number.");
  CHECK(number_error(2) == "bad.csv:5: column 'b': 'nan' is not a finite number.");
  CHECK(number_error(3) == "bad.csv:6: column 'b': '1e999' is not a finite number.");
  CHECK(number_error(4) == "bad.csv:7: column 'b': '' is not a finite number.");
  CHECK_THROWS_WITH(CsvTable::read("no such folder/lever.csv"),
                    Catch::Contains("cannot open the CSV file"));
}
