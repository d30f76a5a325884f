// A CSV file with a header row (lever/io/csv.hpp).
#include <lever/error.hpp>
#include <lever/io/csv.hpp>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace lever::io {

namespace {

// One line split at commas, with "quoted, fields" as `lever simulate` writes them.
std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char ch = line[i];
    if (quoted) {
      if (ch == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        fields.back() += '"';
        ++i;
      } else if (ch == '"') {
        quoted = false;
      } else {
        fields.back() += ch;
      }
    } else if (ch == '"') {
      quoted = true;
    } else if (ch == ',') {
      fields.emplace_back();
    } else if (ch != '\r') {
      fields.back() += ch;
    }
  }
  return fields;
}

}  // namespace

CsvTable CsvTable::read(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path + ": cannot open the CSV file.");
  std::ostringstream text;
  text << in.rdbuf();
  return parse(text.str(), path);
}

CsvTable CsvTable::parse(const std::string& text, const std::string& name) {
  CsvTable table;
  table.name_ = name;
  std::istringstream in(text);
  std::string line;
  if (!std::getline(in, line)) throw Error(name + ":1: empty file: expected a header row.");
  table.header_ = split(line);
  int line_number = 1;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.empty() || line == "\r") continue;
    std::vector<std::string> fields = split(line);
    if (fields.size() != table.header_.size()) {
      throw Error(name + ":" + std::to_string(line_number) + ": " + std::to_string(fields.size()) +
                  " fields, the header has " + std::to_string(table.header_.size()) + ".");
    }
    table.fields_.push_back(std::move(fields));
    table.lines_.push_back(line_number);
  }
  return table;
}

int CsvTable::column(const std::string& heading) const {
  for (std::size_t c = 0; c < header_.size(); ++c) {
    if (header_[c] == heading) return static_cast<int>(c);
  }
  return -1;
}

const std::string& CsvTable::field(int row, int column) const {
  return fields_[static_cast<std::size_t>(row)][static_cast<std::size_t>(column)];
}

double CsvTable::number(int row, int column) const {
  const std::string& f = field(row, column);
  char* end = nullptr;
  const double x = std::strtod(f.c_str(), &end);
  if (f.empty() || end != f.c_str() + f.size() || !std::isfinite(x)) {
    throw Error(name_ + ":" + std::to_string(line(row)) + ": column '" +
                header_[static_cast<std::size_t>(column)] + "': '" + f +
                "' is not a finite number.");
  }
  return x;
}

}  // namespace lever::io
