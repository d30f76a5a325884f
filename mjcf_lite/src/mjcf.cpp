// The public entry points of mjcf_lite: read, validate, parse, compile, set_const. Every stage
// reports bad input by throwing a detail::Problem; it becomes a ParseError here, with the file.
#include <filesystem>
#include <fstream>
#include <lever/mjcf.hpp>
#include <sstream>
#include <utility>

#include "compiler.hpp"
#include "parse.hpp"
#include "problem.hpp"
#include "reader.hpp"
#include "schema.hpp"

namespace lever::mjcf {

namespace detail {

std::string read_model_file(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) {
    throw ParseError(path, 0, "", "", "cannot open the model: no such file");
  }
  if (std::filesystem::is_directory(path, ec)) {
    throw ParseError(path, 0, "", "", "cannot open the model: it is a directory, not a file");
  }
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw ParseError(path, 0, "", "", "cannot open the model: not a regular file");
  }
  // the size limit before reading, so that a huge file is never read into memory
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (!ec && size > Limits::kDocumentBytes) {
    throw ParseError(path, 0, "", "",
                     "the file is " + std::to_string(size) + " bytes long; lever accepts at most " +
                         std::to_string(Limits::kDocumentBytes) +
                         " (a limit, see docs/reliability.md)");
  }
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in) throw ParseError(path, 0, "", "", "cannot read the model file");
  return text.str();
}

Model load_located(const std::string& xml, const std::string& filename, const LoadOptions& options,
                   Locations* located) {
  // build everything into locals: the caller gets a complete model or an exception
  Model model;
  detail::Locations where;
  LengthRangeOptions lengthrange;  // <compiler><lengthrange>, used once the constants are set
  try {
    const detail::Element root = detail::read_document(xml, filename, &where.included_files);
    detail::ModelSpec spec = detail::parse_model(root, options.infer_inertia_from_geoms);
    // mesh files are found from the model's folder, as MuJoCo does (mjuu_getfiledir)
    const size_t slash = filename.find_last_of("/\\");
    spec.model_dir = slash == std::string::npos ? "" : filename.substr(0, slash + 1);
    model = detail::compile(spec, &where);
    lengthrange = spec.compiler.lengthrange;
  } catch (const detail::Problem& p) {
    // a problem in an included file is reported in that file
    const std::string& file = p.where.file.empty() ? filename : p.where.file;
    throw ParseError(file, p.where.line, p.where.tag, p.attribute, p.message, p.where.name);
  }
  try {
    set_const(model);
    set_length_ranges(model, lengthrange);
  } catch (const ModelError& e) {
    // located at the element the object came from, when set_const names one
    const std::vector<detail::Place>* places = nullptr;
    if (e.object() == "body") places = &where.body;
    if (e.object() == "joint") places = &where.joint;
    if (e.object() == "site") places = &where.site;
    if (e.object() == "actuator") places = &where.actuator;
    if (places && e.index() >= 0 && e.index() < static_cast<int>(places->size())) {
      const detail::Place& at = (*places)[static_cast<size_t>(e.index())];
      throw ParseError(at.file.empty() ? filename : at.file, at.line, at.tag, "", e.what(),
                       at.name);
    }
    throw ParseError(filename, 0, "", "",
                     std::string("the compiled model is invalid: ") + e.what());
  } catch (const Error& e) {
    throw ParseError(filename, 0, "", "",
                     std::string("the compiled model is invalid: ") + e.what());
  }
  if (located) *located = std::move(where);
  return model;
}

}  // namespace detail

Model load_string(const std::string& xml, const std::string& filename, const LoadOptions& options) {
  return detail::load_located(xml, filename, options, nullptr);
}

Model load_file(const std::string& path, const LoadOptions& options) {
  Model model = load_string(detail::read_model_file(path), path, options);
  model.source = path;
  return model;
}

std::string schema_markdown() { return detail::markdown(); }

}  // namespace lever::mjcf
