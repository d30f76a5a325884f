// stub: being written
#include <lever/mjcf.hpp>
namespace lever::mjcf {
ParseError::ParseError(std::string file, int line, std::string element, std::string attribute, std::string problem)
    : Error(file + ":" + std::to_string(line) + ": error: " + problem), file_(std::move(file)), element_(std::move(element)),
      attribute_(std::move(attribute)), problem_(std::move(problem)), line_(line) {}
Model load_file(const std::string& path, const LoadOptions&) { throw ParseError(path, 0, "", "", "not implemented"); }
Model load_string(const std::string&, const std::string& filename, const LoadOptions&) { throw ParseError(filename, 0, "", "", "not implemented"); }
std::string schema_markdown() { return ""; }
}
