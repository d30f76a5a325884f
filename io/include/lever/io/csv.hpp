// lever/io/csv.hpp: a CSV file with a header row, as `lever simulate --csv` writes it.
//
// Fields are split at commas, with "quoted, fields" and "" for a quote inside one (RFC 4180);
// a trailing carriage return is dropped and blank lines are skipped. Fields stay text until a
// caller asks for a number, so a file may carry columns its reader does not use. Every error
// names the file, the line and, for a field, its column.
#pragma once

#include <string>
#include <vector>

namespace lever::io {

class CsvTable {
 public:
  /// The file at `path`. Throws lever::Error if it cannot be opened, has no header row, or has a
  /// row whose number of fields is not the header's.
  static CsvTable read(const std::string& path);
  /// The same from text; `name` stands for the file in messages.
  static CsvTable parse(const std::string& text, const std::string& name);

  const std::string& name() const { return name_; }
  const std::vector<std::string>& header() const { return header_; }
  int rows() const { return static_cast<int>(fields_.size()); }

  /// The index of the column headed `heading`, or -1 if there is none.
  int column(const std::string& heading) const;
  /// The text of a row's field.
  const std::string& field(int row, int column) const;
  /// A row's field as a number. Throws lever::Error ("file:line: column 'c': 'x' is not a finite
  /// number.") unless the whole field reads as a finite number.
  double number(int row, int column) const;
  /// The line of the file a row is on (1-based: the header is line 1).
  int line(int row) const { return lines_[static_cast<std::size_t>(row)]; }

 private:
  std::string name_;
  std::vector<std::string> header_;
  std::vector<std::vector<std::string>> fields_;  // per row, as many as the header
  std::vector<int> lines_;                        // per row
};

}  // namespace lever::io
