// The public entry points of mjcf_lite: read, validate, parse, compile, set_const. Every stage
// reports bad input by throwing a detail::Problem; it becomes a ParseError here, with the file.
#include <filesystem>
#include <fstream>
#include <lever/mjcf.hpp>
#include <sstream>

#include "compiler.hpp"
#include "parse.hpp"
#include "problem.hpp"
#include "reader.hpp"
#include "schema.hpp"

namespace lever::mjcf {

namespace {

std::string read_file(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) {
    throw ParseError(path, 0, "", "", "cannot open the model: no such file");
  }
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw ParseError(path, 0, "", "", "cannot open the model: not a regular file");
  }
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in) throw ParseError(path, 0, "", "", "cannot read the model file");
  return text.str();
}

}  // namespace

Model load_string(const std::string& xml, const std::string& filename, const LoadOptions& options) {
  // build everything into locals: the caller gets a complete model or an exception
  Model model;
  try {
    const detail::Element root = detail::read_document(xml);
    const detail::ModelSpec spec = detail::parse_model(root, options.infer_inertia_from_geoms);
    model = detail::compile(spec);
  } catch (const detail::Problem& p) {
    throw ParseError(filename, p.where.line, p.where.tag, p.attribute, p.message, p.where.name);
  }
  try {
    set_const(model);
  } catch (const Error& e) {
    throw ParseError(filename, 0, "", "",
                     std::string("the compiled model is inconsistent: ") + e.what());
  }
  return model;
}

Model load_file(const std::string& path, const LoadOptions& options) {
  Model model = load_string(read_file(path), path, options);
  model.source = path;
  return model;
}

std::string schema_markdown() { return detail::markdown(); }

}  // namespace lever::mjcf
