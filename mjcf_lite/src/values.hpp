// Attribute values: the lexical rules for numbers, integers and keywords, with one clear error
// per bad value. The rules follow MuJoCo 2.2.2 (C++ stream number syntax, exact keyword match),
// except where lever deliberately refuses a value that 2.2.2 silently accepts (see values.cpp).
#pragma once

#include <string>
#include <vector>

#include "reader.hpp"
#include "schema.hpp"

namespace lever::mjcf::detail {

/// One attribute value, checked against its rule.
struct Value {
  std::vector<double> numbers;  ///< reals and integers, as many as were written
  std::string text;             ///< keywords and text
  int line = 0;                 ///< where it was written
};

/// Parse the attribute `a` of element `e` by `rule`; throws Problem.
Value parse_value(const Element& e, const Attribute& a, const AttributeRule& rule);

/// The rule's built-in default as numbers (empty if unset or not numeric).
std::vector<double> default_numbers(const AttributeRule& rule);

}  // namespace lever::mjcf::detail
