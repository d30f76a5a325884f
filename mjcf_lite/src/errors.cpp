// Error messages of mjcf_lite: the public ParseError, "did you mean" suggestions, number display.
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <lever/mjcf.hpp>
#include <utility>

#include "problem.hpp"

namespace lever::mjcf {

namespace {

// "file:line: error: <joint name="elbow">: problem", leaving out the parts that are unknown
std::string diagnostic(const std::string& file, int line, const std::string& element,
                       const std::string& element_name, const std::string& problem) {
  std::string s = file;
  if (line > 0) s.append(":").append(std::to_string(line));
  s.append(": error: ");
  if (!element.empty()) {
    s.append("<").append(element);
    if (!element_name.empty()) s.append(" name=\"").append(element_name).append("\"");
    s.append(">: ");
  }
  return s.append(problem);
}

}  // namespace

ParseError::ParseError(std::string file, int line, std::string element, std::string attribute,
                       std::string problem, std::string element_name)
    : Error(diagnostic(file, line, element, element_name, problem)),
      file_(std::move(file)),
      element_(std::move(element)),
      element_name_(std::move(element_name)),
      attribute_(std::move(attribute)),
      problem_(std::move(problem)),
      line_(line) {}

}  // namespace lever::mjcf

namespace lever::mjcf::detail {

void fail(const Place& where, std::string_view attribute, std::string message) {
  throw Problem{where, std::string(attribute), std::move(message)};
}

namespace {

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

// edit distance counting an adjacent transposition as one edit ("rnage" -> "range")
int edit_distance(const std::string& a, const std::string& b) {
  const size_t n = a.size(), m = b.size();
  std::vector<std::vector<int>> d(n + 1, std::vector<int>(m + 1, 0));
  for (size_t i = 0; i <= n; ++i) d[i][0] = static_cast<int>(i);
  for (size_t j = 0; j <= m; ++j) d[0][j] = static_cast<int>(j);
  for (size_t i = 1; i <= n; ++i) {
    for (size_t j = 1; j <= m; ++j) {
      const int cost = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) {
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
      }
    }
  }
  return d[n][m];
}

// how many edits still count as a typo of a word this long
int typo_budget(size_t length) { return length <= 3 ? 1 : (length <= 6 ? 2 : 3); }

}  // namespace

std::string did_you_mean(std::string_view typo, const std::vector<std::string_view>& candidates) {
  // a typo is a short word: no suggestion for long ones, so that the O(n m) edit distance stays
  // cheap whatever the input (a 4 KiB name against 1000 others)
  constexpr size_t kLongest = 64;
  if (typo.size() > kLongest) return "";
  const std::string t = lower(typo);
  int best = typo_budget(t.size()) + 1;
  std::string_view choice;
  for (const std::string_view c : candidates) {
    // the edit distance is at least the difference in length
    const size_t gap = c.size() > t.size() ? c.size() - t.size() : t.size() - c.size();
    if (gap >= static_cast<size_t>(best)) continue;
    const int d = edit_distance(t, lower(c));
    if (d < best) {
      best = d;
      choice = c;
    }
  }
  // an abbreviation ("deg" for "degree") is close too, if it abbreviates only one candidate
  if (choice.empty() && t.size() >= 3) {
    int matches = 0;
    for (const std::string_view c : candidates) {
      if (lower(c).rfind(t, 0) == 0) {
        choice = c;
        ++matches;
      }
    }
    if (matches != 1) choice = {};
  }
  if (choice.empty() || choice == typo) return "";
  return " (did you mean '" + std::string(choice) + "'?)";
}

std::string quoted_list(const std::vector<std::string_view>& items, std::string_view last_joint) {
  std::string s;
  for (size_t i = 0; i < items.size(); ++i) {
    if (i > 0 && i + 1 == items.size()) {
      s.append(" ").append(last_joint).append(" ");
    } else if (i > 0) {
      s.append(", ");
    }
    s.append("'").append(items[i]).append("'");
  }
  return s;
}

std::string show(double x) {
  char buffer[32];
#ifdef __EMSCRIPTEN__
  // Emscripten 3.1.6's libc++ has no floating-point to_chars: the fewest %g digits that read back
  for (int digits = 1; digits <= 17; ++digits) {
    std::snprintf(buffer, sizeof buffer, "%.*g", digits, x);
    if (std::strtod(buffer, nullptr) == x) break;
  }
  return buffer;
#else
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, x);
  return std::string(buffer, result.ptr);
#endif
}

}  // namespace lever::mjcf::detail
