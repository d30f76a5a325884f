// How identification names a joint, actuator or body of the prior: its name, or #index as
// `lever simulate` writes it (internal to lever::identify).
#pragma once

#include <string>

namespace lever::identify::detail {

inline std::string label_of(const std::string& name, int index) {
  return name.empty() ? std::string("#").append(std::to_string(index)) : name;
}

}  // namespace lever::identify::detail
