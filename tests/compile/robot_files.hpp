// The shared real robot files (../shared/robots beside the checkout, or $LEVER_ROBOTS_DIR): where
// they are, and what lever refuses in each (robot_files_test.cpp).
#pragma once

#include <lever/harness/models.hpp>
#include <lever/mjcf.hpp>
#include <string>
#include <vector>

namespace lever::test {

/// Every *.xml file under `root`, sorted, as paths.
std::vector<std::string> robot_files(const std::string& root);

/// The feature a ParseError refuses, as "<element attribute>" (with the value, when the refusal is
/// of a keyword: <option integrator="implicitfast">), or "" if the error does not name a feature
/// lever lacks (malformed input, a generic error).
std::string refused_feature(const mjcf::ParseError& e);

/// Every feature lever refuses in the model file `path`, not only the first: each refused
/// attribute (or element) is removed, from a copy of the file and of the files it includes, and
/// the copy loaded again, until it loads or an error names no feature. Distinct features in the
/// order met, ", "-separated; "then: <error>" at the end if the copy stops at another error.
std::string every_refused_feature(const std::string& path);

}  // namespace lever::test
