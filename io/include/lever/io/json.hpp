// lever/io/json.hpp: the JSON writer shared by the command line, the Python package and the
// browser build. It places values; nlohmann-json (Debian's nlohmann-json3-dev, a private
// dependency of lever::io) holds the document and writes it: numbers in the shortest form that
// reads back as the same double, non-finite numbers as null, strings escaped (bytes that are not
// UTF-8 replaced by U+FFFD), keys in the order written.
//
// A document is written whole when its outermost object or array closes (or at once, for a value
// outside any container): a writer that stops half-way, by an exception, writes nothing.
#pragma once

#include <Eigen/Core>

#include <cstdio>
#include <memory>
#include <string>

namespace lever::json {

class Writer {
 public:
  explicit Writer(std::FILE* out);    ///< writes each finished document to out
  explicit Writer(std::string* out);  ///< appends each finished document to *out
  ~Writer();
  Writer(const Writer&) = delete;
  Writer& operator=(const Writer&) = delete;

  Writer& begin_object();
  Writer& end_object();
  Writer& begin_array();
  Writer& end_array();
  /// The key of the next value in the open object.
  Writer& key(const std::string& k);
  Writer& value(double x);
  Writer& value(int x);
  Writer& value(long x);
  Writer& value(bool x);
  Writer& value(const std::string& s);
  Writer& value(const char* s) { return value(std::string(s)); }
  Writer& values(const Eigen::Ref<const Eigen::VectorXd>& v);  ///< as one flat array
  /// A newline after the last finished document (one document per line).
  void newline();

 private:
  struct Document;  // nlohmann's, kept out of this installed header
  std::unique_ptr<Document> doc_;
};

}  // namespace lever::json
