// lever's own XML reader (used where tinyxml2 is not available: the WebAssembly build) against the
// tinyxml2 path on the same texts: every model, the bad-input corpus, the saved fuzz inputs, XML
// corner cases, and random mutations of all of them. For each text both give the same Element tree
// (tags, attributes, values, lines) or both refuse it with the same message (up to the bracketed
// detail, which is each reader's own) at the same line.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "bad_inputs.hpp"
#include "problem.hpp"
#include "xml.hpp"

namespace {

using lever::mjcf::detail::Element;
using lever::mjcf::detail::Problem;

std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// One reader's answer as text: the tree, or the refusal.
void describe_tree(const Element& e, int indent, std::string& out) {
  out += std::string(static_cast<size_t>(indent), ' ') + "<" + e.tag + "> line " +
         std::to_string(e.line) + "\n";
  for (const auto& a : e.attributes) {
    out += std::string(static_cast<size_t>(indent) + 2, ' ') + a.name + "=[" + a.value + "] line " +
           std::to_string(a.line) + "\n";
  }
  for (const Element& c : e.children) describe_tree(c, indent + 2, out);
}

template <typename Reader>
std::string answer(Reader read, const std::string& xml) {
  try {
    std::string out;
    describe_tree(read(xml), 0, out);
    return out;
  } catch (const Problem& p) {
    const std::string message = p.message.substr(0, p.message.find(" ["));
    return "refused at line " + std::to_string(p.where.line) + " <" + p.where.tag + "> '" +
           p.attribute + "': " + message;
  }
}

void same_answer(const std::string& what, const std::string& xml) {
  INFO(what << "\n--- text ---\n" << xml.substr(0, 2000));
  const std::string ours = answer(lever::mjcf::detail::read_xml_lever, xml);
  const std::string theirs = answer(lever::mjcf::detail::read_xml_tinyxml2, xml);
  CHECK(ours == theirs);
}

std::vector<std::filesystem::path> model_files() {
  std::vector<std::filesystem::path> files;
  for (const char* dir : {"models", "tests/models"}) {
    for (const auto& entry :
         std::filesystem::directory_iterator(std::filesystem::path(LEVER_SOURCE_DIR) / dir)) {
      if (entry.path().extension() == ".xml") files.push_back(entry.path());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::vector<std::string> corpus() {
  std::vector<std::string> texts;
  for (const auto& path : model_files()) texts.push_back(read_text(path));
  for (const auto& bad : lever::test::kBadInputs) texts.emplace_back(bad.xml);
  const std::filesystem::path fuzz = std::filesystem::path(LEVER_SOURCE_DIR) / "tests/hostile/fuzz";
  if (std::filesystem::exists(fuzz)) {
    for (const auto& entry : std::filesystem::recursive_directory_iterator(fuzz)) {
      if (entry.is_regular_file() && entry.path().filename() != "README.md") {
        texts.push_back(read_text(entry.path()));
      }
    }
  }
  return texts;
}

// XML corner cases, each written to hit one rule of tinyxml2's (xml_reader.cpp lists them).
const char* const kCorners[] = {
    "",
    "   \n\t ",
    "\xEF\xBB\xBF<mujoco/>",
    "  \n\xEF\xBB\xBF<mujoco/>",
    "<mujoco/>\0<more/>",
    "<?xml version=\"1.0\"?>\n<mujoco/>",
    "<?xml version=\"1.0\"?><?second?>\n<mujoco/>",
    "<!-- c -->\n<?xml version=\"1.0\"?>\n<mujoco/>",
    "<mujoco><?pi?></mujoco>",
    "<?xml never closed",
    "<!DOCTYPE mujoco>\n<mujoco/>",
    "<!DOCTYPE mujoco [ <!ENTITY e \"x\"> ]>\n<mujoco/>",
    "<!DOCTYPE never closed",
    "<mujoco><!-- a comment --></mujoco>",
    "<mujoco><!-- never closed </mujoco>",
    "<mujoco>\n<![CDATA[   ]]>\n</mujoco>",
    "<mujoco>\n<![CDATA[ text ]]>\n</mujoco>",
    "<mujoco><![CDATA[ never closed </mujoco>",
    "<![CDATA[x]]><mujoco/>",
    "<mujoco>\n  text\n</mujoco>",
    "<mujoco>&#32;&#x9;\n</mujoco>",
    "<mujoco>&#0;abc</mujoco>",
    "<mujoco>&amp;</mujoco>",
    "<mujoco>&nbsp;</mujoco>",
    "<mujoco model=\"a&amp;b&lt;c&gt;d&quot;e&apos;f\"/>",
    "<mujoco model=\"&unknown; &amp &#65;&#x42;&#x;&#;&#12a;&#xZZ; &#\"/>",
    "<mujoco model=\"&#x263A; &#128512; &#1114112; &#99999999999;\"/>",
    "<mujoco model='single \"quoted\"'/>",
    "<mujoco model=\"a\r\nb\rc\n\rd\"/>",
    "<mujoco model=\"line\nbreaks\n\"\n  other=\"x\"/>",
    "<mujoco model=\"<>\"/>",
    "<mujoco model=unquoted/>",
    "<mujoco model = \"spaced\" />",
    "<mujoco model=\"x\" model=\"y\"/>",
    "<mujoco model=\"never closed/>",
    "<mujoco model/>",
    "<mujoco 1model=\"x\"/>",
    "<mujoco :a=\"1\" _b=\"2\" c.d-e=\"3\" \xC3\xA9=\"4\"/>",
    "< mujoco/>",
    "<mujoco></ mujoco>",
    "<mujoco></mujoco extra=\"1\">",
    "<mujoco></mujoco/>",
    "<mujoco><a></a/></mujoco>",
    "<mujoco></mujocoo>",
    "<mujoco>",
    "<mujoco>  ",
    "<mujoco><worldbody>",
    "<mujoco><worldbody></mujoco>",
    "<>",
    "< >",
    "<1a/>",
    "<mujoco/><second/>",
    "<mujoco/></closing> trailing",
    "<mujoco/>trailing text",
    "<mujoco/>trailing text<!-- -->",
    "leading text<mujoco/>",
    "text<",
    "<mujoco>text<",
    "<mujoco x=\"1\"",
    "<mujoco x=\"1\" /",
    "<mujoco/ >",
    "<!-- only a comment -->",
    "<?xml?>",
    "\r\n\r\n<mujoco>\r\n<bad\r\n</mujoco>",
    "<mujoco>\n\n<a\n  b=\"1\"\n  c=\"2\"/>\n</mujoco>",
};

std::string nested(int depth, bool self_close_last) {
  std::string xml;
  for (int i = 0; i < depth; ++i) {
    xml += (i + 1 == depth && self_close_last) ? "<e/>\n" : "<e>\n";
  }
  for (int i = self_close_last ? 1 : 0; i < depth; ++i) xml += "</e>\n";
  return xml;
}

}  // namespace

TEST_CASE("lever's XML reader and tinyxml2 agree on every model and bad input", "[mjcf][xml]") {
  const std::vector<std::string> texts = corpus();
  REQUIRE(texts.size() > 40);
  for (size_t i = 0; i < texts.size(); ++i)
    same_answer("corpus text " + std::to_string(i), texts[i]);
}

TEST_CASE("lever's XML reader and tinyxml2 agree on XML corner cases", "[mjcf][xml]") {
  for (const char* corner : kCorners) same_answer("corner case", corner);
  same_answer("NUL inside", std::string("<mujoco/>\0<second/>", 19));
  same_answer("NUL first", std::string("\0<mujoco/>", 10));
  same_answer("long attribute", "<mujoco model=\"" + std::string(5000, 'x') + "\"/>");
  same_answer("long attribute with entities",
              "<mujoco model=\"" + std::string(4090, 'x') + "&amp;&amp;&amp;&amp;\"/>");
  for (int depth : {97, 98, 99, 100, 101, 150}) {
    same_answer("nested " + std::to_string(depth), nested(depth, false));
    same_answer("nested, last closed " + std::to_string(depth), nested(depth, true));
  }
}

TEST_CASE("lever's XML reader and tinyxml2 agree on mutated texts", "[mjcf][xml]") {
  // each mutation deletes, inserts or replaces a few bytes, drawn from XML's significant characters
  const std::string alphabet = "<>/=\"'!?-[]&;#x \n\rab0";
  std::mt19937 rng(12);
  const std::vector<std::string> texts = corpus();
  int compared = 0;
  for (const std::string& original : texts) {
    for (int round = 0; round < 40; ++round) {
      std::string text = original;
      const int edits = 1 + static_cast<int>(rng() % 3);
      for (int k = 0; k < edits; ++k) {
        const size_t at = text.empty() ? 0 : rng() % (text.size() + 1);
        const char c = alphabet[rng() % alphabet.size()];
        switch (rng() % 3) {
          case 0:
            if (at < text.size()) text.erase(at, 1);
            break;
          case 1: text.insert(at, 1, c); break;
          default:
            if (at < text.size()) text[at] = c;
        }
      }
      same_answer("mutation " + std::to_string(round), text);
      ++compared;
    }
  }
  CHECK(compared > 1000);
}
