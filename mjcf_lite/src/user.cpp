// User data; see user.hpp. MuJoCo 2.2.2 sizes each kind by <size nuser_*> when it is written
// (>= 0), else by the longest list of the kind (mjCModel's -1), refuses a list longer than a
// written width, and pads every list with zeros.
#include "user.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace lever::mjcf::detail {

const char* user_size_attribute(UserKind kind) {
  static constexpr std::array<const char*, kUserKinds> names = {
      "nuser_body",   "nuser_jnt",      "nuser_geom",  "nuser_site",
      "nuser_tendon", "nuser_actuator", "nuser_sensor"};
  return names[static_cast<size_t>(kind)];
}

int user_width(UserKind kind, const UserSizes& sizes, const std::vector<const UserData*>& lists) {
  const int written = sizes.width[static_cast<size_t>(kind)];
  int longest = 0;
  for (const UserData* u : lists) {
    const int n = static_cast<int>(u->numbers.size());
    longest = std::max(longest, n);
    if (written >= 0 && n > written) {
      const Place& size_at = sizes.at[static_cast<size_t>(kind)];
      fail(u->at, "user",
           "user has " + std::to_string(n) + " numbers, more than <size " +
               user_size_attribute(kind) + "=\"" + std::to_string(written) + "\">" +
               (size_at.line > 0 ? " (line " + std::to_string(size_at.line) + ")" : "") +
               " allows");
    }
  }
  return written >= 0 ? written : longest;
}

void fill_user_rows(const std::vector<const UserData*>& lists, int width, ArenaRowMatrix& out) {
  // sized by size_model: one row per object, `width` columns
  if (out.rows() != static_cast<Eigen::Index>(lists.size()) || out.cols() != width) {
    throw std::logic_error("lever::mjcf: user data sized " + std::to_string(out.rows()) + " x " +
                           std::to_string(out.cols()) + " for " + std::to_string(lists.size()) +
                           " x " + std::to_string(width));
  }
  out.setZero();
  for (size_t r = 0; r < lists.size(); ++r) {
    const std::vector<double>& x = lists[r]->numbers;
    for (size_t c = 0; c < x.size(); ++c) out(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) = x[c];
  }
}

}  // namespace lever::mjcf::detail
