// See robot_files.hpp.
#include "robot_files.hpp"

#include <tinyxml2.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <lever/harness/models.hpp>

namespace lever::test {

namespace fs = std::filesystem;

std::vector<std::string> robot_files(const std::string& root) {
  std::vector<std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    if (entry.is_regular_file() && entry.path().extension() == ".xml") {
      files.push_back(entry.path().string());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::string refused_feature(const mjcf::ParseError& e) {
  const std::string& problem = e.problem();
  // lever's refusals of valid MJCF say what lever lacks; other errors are about the input
  const bool names_a_lack = problem.find("not supported by lever") != std::string::npos ||
                            problem.find("lever has no") != std::string::npos ||
                            problem.find("lever does not") != std::string::npos ||
                            problem.find("which lever follows") != std::string::npos ||
                            problem.find("lever reads") != std::string::npos ||
                            problem.find("lever cannot") != std::string::npos ||
                            problem.find("lever refuses") != std::string::npos;
  if (!names_a_lack || e.element().empty()) return "";
  std::string feature = "<" + e.element();
  if (!e.attribute().empty()) {
    feature += " " + e.attribute();
    // a refused keyword: "integrator 'implicitfast' ..."
    const std::string lead = e.attribute() + " '";
    if (problem.rfind(lead, 0) == 0) {
      const size_t end = problem.find('\'', lead.size());
      if (end != std::string::npos) {
        feature += "=\"" + problem.substr(lead.size(), end - lead.size()) + "\"";
      }
    }
  }
  return feature + ">";
}

namespace {

// the element `tag` written at `line` (or, for an attribute on a later line, the last one of that
// tag starting before it)
tinyxml2::XMLElement* element_at(tinyxml2::XMLElement* e, const std::string& tag, int line,
                                 tinyxml2::XMLElement* best) {
  if (e->Value() == tag && e->GetLineNum() <= line &&
      (!best || e->GetLineNum() >= best->GetLineNum())) {
    best = e;
  }
  for (tinyxml2::XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
    best = element_at(c, tag, line, best);
  }
  return best;
}

// an attribute without which the element means nothing: the element goes with it
bool is_transmission(const std::string& attribute) {
  for (const char* a : {"tendon", "site", "body", "jointinparent", "cranksite", "slidersite"}) {
    if (attribute == a) return true;
  }
  return false;
}

// remove what `e` refuses from its file; false if it cannot be found
bool remove_refused(const mjcf::ParseError& e) {
  tinyxml2::XMLDocument doc;
  if (doc.LoadFile(e.file().c_str()) != tinyxml2::XML_SUCCESS || !doc.RootElement()) return false;
  tinyxml2::XMLElement* at = element_at(doc.RootElement(), e.element(), e.line(), nullptr);
  if (!at) return false;
  if (!e.attribute().empty() && !is_transmission(e.attribute()) &&
      at->Attribute(e.attribute().c_str())) {
    at->DeleteAttribute(e.attribute().c_str());
  } else if (at->Parent()) {
    at->Parent()->DeleteChild(at);
  } else {
    return false;
  }
  return doc.SaveFile(e.file().c_str()) == tinyxml2::XML_SUCCESS;
}

}  // namespace

std::string every_refused_feature(const std::string& path) {
  // a copy of the file's folder: its model files copied, everything else linked
  const fs::path source(path);
  const fs::path copy =
      fs::temp_directory_path() / ("lever-robot-files-" + std::to_string(::getpid()));
  fs::remove_all(copy);
  fs::create_directories(copy);
  for (const auto& entry : fs::directory_iterator(source.parent_path())) {
    const fs::path to = copy / entry.path().filename();
    if (entry.is_regular_file() && entry.path().extension() == ".xml") {
      fs::copy_file(entry.path(), to);
    } else {
      fs::create_symlink(fs::absolute(entry.path()), to);
    }
  }
  std::vector<std::string> features;
  std::string ending;
  for (int attempt = 0; attempt < 200; ++attempt) {
    try {
      mjcf::load_file((copy / source.filename()).string());
      break;
    } catch (const mjcf::ParseError& e) {
      const std::string feature = refused_feature(e);
      if (feature.empty() || !remove_refused(e)) {
        ending = std::string("then: ") + e.problem().substr(0, 80);
        break;
      }
      if (std::find(features.begin(), features.end(), feature) == features.end()) {
        features.push_back(feature);
      }
    }
  }
  fs::remove_all(copy);
  std::string out;
  for (const std::string& f : features) out += (out.empty() ? "" : ", ") + f;
  if (!ending.empty()) out += (out.empty() ? "" : "; ") + ending;
  return out;
}

}  // namespace lever::test
