// User data (MJCF's `user` on bodies, joints, geoms, sites, tendons, actuators and sensors, and <size
// nuser_*>): numbers the engine never reads, compiled as MuJoCo 2.2.2 compiles them into its
// *_user arrays (user_model.cc, user_objects.cc). user.cpp.
#pragma once

#include <array>
#include <vector>

#include <lever/model.hpp>

#include "problem.hpp"

namespace lever::mjcf::detail {

/// One object's `user` list as written or inherited from its class (empty: none), and where.
struct UserData {
  std::vector<double> numbers;
  Place at;  ///< the `user` attribute's element (its line), for errors
};

/// The kinds of object that carry user data, in <size>'s order.
enum class UserKind { kBody, kJoint, kGeom, kSite, kTendon, kActuator, kSensor };
inline constexpr int kUserKinds = 7;

/// <size nuser_*>: each kind's width as written (-1: the longest list of the kind), and where.
struct UserSizes {
  std::array<int, kUserKinds> width{-1, -1, -1, -1, -1, -1, -1};
  std::array<Place, kUserKinds> at{};
};

/// <size>'s attribute for a kind ("nuser_body", ...).
const char* user_size_attribute(UserKind kind);

/// A kind's width: as <size> gives it, else the longest of `lists`. A list longer than a written
/// width is an error at its `user` attribute (MuJoCo's "user has more values than nuser_...").
int user_width(UserKind kind, const UserSizes& sizes, const std::vector<const UserData*>& lists);

/// The lists as rows of `out` (lists.size() x width), each padded with zeros.
void fill_user_rows(const std::vector<const UserData*>& lists, int width, ArenaRowMatrix& out);

}  // namespace lever::mjcf::detail
