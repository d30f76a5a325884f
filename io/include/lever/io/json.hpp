// lever/io/json.hpp: a minimal streaming JSON writer, shared by the command line, the Python
// package and the browser build. Numbers are written in full double precision (%.17g), non-finite
// numbers as null, keys in the order written.
#pragma once

#include <Eigen/Core>

#include <cstdio>
#include <string>
#include <vector>

namespace lever::json {

class Writer {
 public:
  explicit Writer(std::FILE* out) : file_(out) {}    ///< writes as it goes
  explicit Writer(std::string* out) : text_(out) {}  ///< appends to *out
  Writer& begin_object();
  Writer& end_object();
  Writer& begin_array();
  Writer& end_array();
  Writer& key(const std::string& k);
  Writer& value(double x);
  Writer& value(int x);
  Writer& value(long x);
  Writer& value(bool x);
  Writer& value(const std::string& s);
  Writer& value(const char* s) { return value(std::string(s)); }
  Writer& values(const Eigen::Ref<const Eigen::VectorXd>& v);  ///< as one flat array
  void newline();

 private:
  void put(const char* s);
  void put(char c);
  void separator();
  std::FILE* file_ = nullptr;
  std::string* text_ = nullptr;
  std::vector<bool> first_;  // one per open container: nothing written in it yet
  bool after_key_ = false;
};

/// JSON string escaping.
std::string escape(const std::string& s);

}  // namespace lever::json
