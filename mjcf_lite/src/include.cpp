// <include> expansion; see include.hpp.
#include "include.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "xml.hpp"

namespace lever::mjcf::detail {

namespace {

namespace fs = std::filesystem;

// MuJoCo 2.2.2 compares included file names ignoring case (strcasecmp)
bool same_file_name(const std::string& a, const std::string& b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) ==
                  std::tolower(static_cast<unsigned char>(y));
         });
}

// the folder of a path, with its trailing separator, or "" (MuJoCo's mjuu_getfiledir)
std::string folder_of(const std::string& path) {
  const size_t slash = path.find_last_of("/\\");
  return slash == std::string::npos ? "" : path.substr(0, slash + 1);
}

// levels of elements from `e` down to its deepest descendant (1 for an element without children)
int height(const Element& e) {
  int below = 0;
  for (const Element& child : e.children) below = std::max(below, height(child));
  return below + 1;
}

void mark_file(Element& e, const std::string& file) {
  e.file = file;
  for (Element& child : e.children) mark_file(child, file);
}

class Expander {
 public:
  Expander(const std::string& filename, std::size_t bytes)
      : main_(filename), folder_(folder_of(filename)), bytes_(bytes) {
    read_.push_back({filename, Place{}});
  }

  // replace the <include>s among the children of `e` (at nesting level `depth`), recursively
  void expand(Element& e, int depth) {
    std::vector<Element> children;
    children.reserve(e.children.size());
    for (Element& child : e.children) {
      if (child.tag == "include") {
        for (Element& included : include(child, depth + 1)) children.push_back(std::move(included));
      } else {
        expand(child, depth + 1);
        children.push_back(std::move(child));
      }
    }
    e.children = std::move(children);
  }

  std::vector<std::string> included() const {
    std::vector<std::string> paths;
    for (size_t i = 1; i < read_.size(); ++i) paths.push_back(read_[i].path);
    return paths;
  }

 private:
  struct ReadFile {
    std::string path;
    Place by;  ///< the <include> that read it (the main file: none)
  };

  // "scene.xml:3", where an element is
  std::string shown(const Place& at) const {
    return (at.file.empty() ? main_ : at.file) + ":" + std::to_string(at.line);
  }

  // the elements of the file an <include> at nesting level `depth` names, expanded
  std::vector<Element> include(const Element& inc, int depth) {
    for (const Attribute& a : inc.attributes) {
      if (a.name != "file") {
        fail(inc.place(a), a.name,
             "unknown attribute '" + a.name + "'; <include> takes only 'file'" +
                 did_you_mean(a.name, {"file"}));
      }
    }
    const Attribute* file = inc.find("file");
    if (!file) fail(inc.place(), "file", "missing required attribute 'file'");
    if (file->value.empty()) fail(inc.place(*file), "file", "the file name is empty");
    if (!inc.children.empty()) {
      fail(inc.children.front().place(), "",
           "an <include> cannot have children: it is replaced by the elements of its file");
    }
    const Place at = inc.place(*file);
    // always from the main file's folder, an absolute path too (as 2.2.2 joins them)
    const std::string path = folder_ + file->value;
    for (const ReadFile& r : read_) {
      if (!same_file_name(r.path, path)) continue;
      if (r.by.line == 0) {
        fail(at, "file",
             "'" + file->value + "' is the model file itself (" + main_ +
                 "): a file cannot include itself or a file that includes it");
      }
      fail(at, "file",
           "'" + path + "' is already included, at " + shown(r.by) +
               ": MuJoCo includes a file once (is there a cycle of includes?)");
    }
    const std::string text = read_text(at, file->value, path);
    bytes_ += text.size();
    if (bytes_ > Limits::kDocumentBytes) {
      fail(at, "file",
           "the model file and the files it includes are " + std::to_string(bytes_) +
               " bytes long together; lever accepts at most " +
               std::to_string(Limits::kDocumentBytes) + " (a limit, see docs/reliability.md)");
    }
    Element root;
    try {
      check_size(text);
      root = read_xml(text);
    } catch (Problem& p) {
      // a problem in the included text is located in that file
      if (p.where.file.empty()) p.where.file = path;
      throw;
    }
    mark_file(root, path);
    read_.push_back({path, at});
    if (root.children.empty()) {
      fail(at, "file",
           "'" + path + "' has no elements inside its root element <" + root.tag +
               ">: nothing to include");
    }
    // its root's children take the <include>'s level
    for (const Element& child : root.children) {
      if (depth - 1 + height(child) > kMaxDepth) {
        fail(at, "file",
             "with the elements of '" + path + "', elements are nested more than " +
                 std::to_string(kMaxDepth) + " levels deep");
      }
    }
    expand(root, depth - 1);
    return std::move(root.children);
  }

  // the text of an included file, or a Problem at its <include>
  std::string read_text(const Place& at, const std::string& written, const std::string& path) {
    std::error_code ec;
    if (!fs::exists(path, ec)) {
      std::string message = "cannot include '" + written + "': there is no file '" + path +
                            "' (include paths are relative to the folder of the main model "
                            "file, " +
                            (main_.empty() ? std::string("<string>") : main_) +
                            ", in nested includes too, as MuJoCo reads them)";
      // the path a user may have meant: beside the file that includes it
      const std::string beside = folder_of(at.file) + written;
      if (!at.file.empty() && beside != path && fs::exists(beside, ec)) {
        message += "; '" + beside + "' exists beside " + at.file +
                   ": write its path from the main model file's folder";
      }
      fail(at, "file", message);
    }
    if (!fs::is_regular_file(path, ec)) {
      fail(at, "file", "cannot include '" + path + "': it is not a regular file");
    }
    const std::uintmax_t size = fs::file_size(path, ec);
    if (!ec && size > Limits::kDocumentBytes) {
      fail(at, "file",
           "cannot include '" + path + "': it is " + std::to_string(size) +
               " bytes long; lever accepts at most " + std::to_string(Limits::kDocumentBytes) +
               " (a limit, see docs/reliability.md)");
    }
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    if (!in) fail(at, "file", "cannot read the included file '" + path + "'");
    return text.str();
  }

  std::string main_, folder_;
  std::size_t bytes_;
  std::vector<ReadFile> read_;  ///< the model file first, then every included file
};

}  // namespace

std::vector<std::string> expand_includes(Element& root, const std::string& filename,
                                         std::size_t bytes) {
  Expander expander(filename, bytes);
  expander.expand(root, 1);
  return expander.included();
}

}  // namespace lever::mjcf::detail
