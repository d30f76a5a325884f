// Attribute values; see values.hpp.
//
// Deliberate differences from MuJoCo 2.2.2's reader (xml_util.cc, ReadAttr/ReadAttrInt), each an
// input that 2.2.2 accepts silently although it is almost certainly a mistake:
//   - `nan` and `inf` are refused (2.2.2 stores them, warning only for nan);
//   - a list ending in a blank with fewer numbers than the maximum is refused: 2.2.2 parses the
//     last number a second time, so pos="1 2 " loads as (1, 2, 2);
//   - an integer must be a whole integer: 2.2.2 reads group="1.7" as 1 and "2abc" as 2;
//   - eulerseq letters are checked where written, not only when an euler angle uses them.
#include "values.hpp"

#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdlib>

namespace lever::mjcf::detail {

namespace {

std::vector<std::string> tokens(const std::string& s) {
  std::vector<std::string> out;
  size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && is_space(s[i])) ++i;
    size_t j = i;
    while (j < s.size() && !is_space(s[j])) ++j;
    if (j > i) out.push_back(s.substr(i, j - i));
    i = j;
  }
  return out;
}

// digits [. digits] or . digits, then an optional exponent: what a C++ stream reads as a double
bool is_decimal(const std::string& t) {
  size_t i = (!t.empty() && (t[0] == '+' || t[0] == '-')) ? 1 : 0;
  size_t mantissa_digits = 0;
  while (i < t.size() && is_digit(t[i])) ++i, ++mantissa_digits;
  if (i < t.size() && t[i] == '.') {
    ++i;
    while (i < t.size() && is_digit(t[i])) ++i, ++mantissa_digits;
  }
  if (mantissa_digits == 0) return false;
  if (i < t.size() && (t[i] == 'e' || t[i] == 'E')) {
    ++i;
    if (i < t.size() && (t[i] == '+' || t[i] == '-')) ++i;
    size_t exponent_digits = 0;
    while (i < t.size() && is_digit(t[i])) ++i, ++exponent_digits;
    if (exponent_digits == 0) return false;
  }
  return i == t.size();
}

bool is_integer(const std::string& t) {
  size_t i = (!t.empty() && (t[0] == '+' || t[0] == '-')) ? 1 : 0;
  if (i == t.size()) return false;
  for (; i < t.size(); ++i) {
    if (!is_digit(t[i])) return false;
  }
  return true;
}

bool names_non_finite(std::string t) {
  for (char& c : t) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (!t.empty() && (t[0] == '+' || t[0] == '-')) t.erase(0, 1);
  return t == "nan" || t == "inf" || t == "infinity";
}

std::string expected(const AttributeRule& rule) {
  const bool whole = rule.kind == ValueKind::kInteger;
  const std::string noun = whole ? "integer" : "number";
  if (rule.count == 1) return whole ? "an integer" : "a number";
  if (rule.partial || rule.list) return "1 to " + std::to_string(rule.count) + " " + noun + "s";
  return std::to_string(rule.count) + " " + noun + "s";
}

double read_real(const Element& e, const Attribute& a, const std::string& t) {
  const Place at = e.place(a);
  if (names_non_finite(t)) {
    fail(at, a.name, "attribute '" + a.name + "': '" + t + "' is not a finite number");
  }
  if (!is_decimal(t)) fail(at, a.name, "attribute '" + a.name + "': '" + t + "' is not a number");
  errno = 0;
  const double x = std::strtod(t.c_str(), nullptr);
  if (errno == ERANGE && std::isinf(x)) {
    fail(at, a.name, "attribute '" + a.name + "': '" + t + "' is too large for a double");
  }
  return x;  // an underflow to 0 or a denormal is kept, as MuJoCo does
}

double read_integer(const Element& e, const Attribute& a, const std::string& t) {
  if (!is_integer(t)) {
    fail(e.place(a), a.name, "attribute '" + a.name + "': '" + t + "' is not an integer");
  }
  errno = 0;
  const long v = std::strtol(t.c_str(), nullptr, 10);
  if (errno == ERANGE || v < INT_MIN || v > INT_MAX) {
    fail(e.place(a), a.name, "attribute '" + a.name + "': '" + t + "' is out of range");
  }
  return static_cast<double>(v);
}

Value read_numbers(const Element& e, const Attribute& a, const AttributeRule& rule) {
  Value v;
  v.line = a.line;
  const std::vector<std::string> list = tokens(a.value);
  if (list.empty()) {
    fail(e.place(a), a.name, "attribute '" + a.name + "' is empty; expected " + expected(rule));
  }
  for (const std::string& t : list) {
    v.numbers.push_back(rule.kind == ValueKind::kInteger ? read_integer(e, a, t)
                                                         : read_real(e, a, t));
  }
  const int n = static_cast<int>(v.numbers.size());
  const std::string found = "attribute '" + a.name + "' has " + std::to_string(n) + " number" +
                            (n == 1 ? "" : "s") + "; expected " + expected(rule);
  if (n > rule.count) fail(e.place(a), a.name, found);
  // mujoco 2.2.2 reads the last number once more when the list ends in a blank (see top)
  const bool trailing_blank = is_space(a.value.back());
  const bool variable = rule.partial || rule.list;
  const bool quirk = trailing_blank && (variable ? n < rule.count : n + 1 == rule.count);
  const std::string note = quirk ? " (the list ends in a blank, which MuJoCo 2.2.2 would fill by "
                                   "repeating the last number; remove the blank)"
                                 : "";
  if (!variable && n < rule.count) fail(e.place(a), a.name, found + note);
  if (quirk) {
    fail(e.place(a), a.name,
         "attribute '" + a.name + "' ends in a blank after " + std::to_string(n) + " of up to " +
             std::to_string(rule.count) +
             " numbers; MuJoCo 2.2.2 would repeat the last number. Remove "
             "the blank");
  }
  return v;
}

Value read_keyword(const Element& e, const Attribute& a, const AttributeRule& rule) {
  if (has_word(rule.keywords, a.value)) return Value{{}, a.value, a.line};
  if (has_word(rule.unsupported_keywords, a.value)) {
    fail(e.place(a), a.name,
         std::string(a.name) + " '" + a.value +
             "' is valid MJCF but not supported by lever, which has " +
             quoted_list(words(rule.keywords), "and") + " (see docs/mjcf-subset.md)");
  }
  std::vector<std::string_view> all = words(rule.keywords);
  for (const std::string_view w : words(rule.unsupported_keywords)) all.push_back(w);
  fail(e.place(a), a.name,
       "invalid value '" + a.value + "' for attribute '" + a.name + "'; expected " +
           quoted_list(words(rule.keywords), "or") + did_you_mean(a.value, all));
}

Value read_euler_sequence(const Element& e, const Attribute& a) {
  bool ok = a.value.size() == 3;
  for (const char c : a.value) ok = ok && std::string_view("xyzXYZ").find(c) != std::string::npos;
  if (!ok) {
    fail(e.place(a), a.name,
         "attribute '" + a.name +
             "' must be 3 letters from x, y, z (rotating "
             "axes) and X, Y, Z (fixed axes); found '" +
             a.value + "'");
  }
  return Value{{}, a.value, a.line};
}

}  // namespace

Value parse_value(const Element& e, const Attribute& a, const AttributeRule& rule) {
  switch (rule.kind) {
    case ValueKind::kReal:
    case ValueKind::kInteger: return read_numbers(e, a, rule);
    case ValueKind::kKeyword: return read_keyword(e, a, rule);
    case ValueKind::kEulerSeq: return read_euler_sequence(e, a);
    case ValueKind::kText: break;
  }
  return Value{{}, a.value, a.line};
}

std::vector<double> default_numbers(const AttributeRule& rule) {
  std::vector<double> out;
  if (rule.kind != ValueKind::kReal && rule.kind != ValueKind::kInteger) return out;
  for (const std::string& t : tokens(std::string(rule.default_value))) {
    out.push_back(std::strtod(t.c_str(), nullptr));
  }
  return out;
}

}  // namespace lever::mjcf::detail
