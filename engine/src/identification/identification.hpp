// The identification room: the inertial-parameter regressor (regressor.cpp, on the smooth room's
// recursions), the base parameters, its column space (base_parameters.cpp), and a model's
// parameter vector: layout, names, reading and writing it (parameters.cpp). Its public faces are
// lever/regressor.hpp and lever/parameters.hpp; nothing here is shared with another room.
#pragma once

#include <lever/parameters.hpp>
#include <lever/regressor.hpp>

namespace lever::detail {

/// The inertial parameters of one body (m, mx, my, mz, Ixx, Iyy, Izz, Ixy, Ixz, Iyz): the
/// regressor's columns and the parameter vector's entries per body.
inline constexpr int kPerBody = 10;

}  // namespace lever::detail
