// Internal error plumbing of mjcf_lite: every stage throws a Problem (where and what, without the
// file name); load_string() turns it into the public ParseError with the file name added.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace lever::mjcf::detail {

/// The element a problem is about: its tag, its name= (if any) and its source line.
struct Place {
  std::string tag;
  std::string name;
  int line = 0;
  /// the element's index in document order (the root element 0), for writing a model back
  /// (lever/mjcf/write.hpp); -1 where no element applies
  int element = -1;
  /// the file it was written in, for an element of an included file; "" for the model file
  std::string file{};
};

/// One bad input, located. `attribute` is "" when the element as a whole is at fault.
struct Problem {
  Place where;
  std::string attribute;
  std::string message;
};

/// Throw a Problem; the one way every stage reports bad input.
[[noreturn]] void fail(const Place& where, std::string_view attribute, std::string message);

/// " (did you mean 'range'?)" when one candidate is close to `typo`, else "".
std::string did_you_mean(std::string_view typo, const std::vector<std::string_view>& candidates);

/// "'a', 'b' or 'c'" for messages listing what was expected.
std::string quoted_list(const std::vector<std::string_view>& items, std::string_view last_joint);

/// A number as the user would write it back (shortest text that reads back exactly).
std::string show(double x);

}  // namespace lever::mjcf::detail
