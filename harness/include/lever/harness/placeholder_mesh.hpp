// Stand-in mesh files for models written with meshes that are not in the repository (as the
// Menagerie's are): lever never reads them when the bodies have <inertial>, MuJoCo always does.
// A small tetrahedron, outward-facing, in the format the file's extension names (binary STL or
// OBJ), so that MuJoCo 2.2.2 compiles the model; the tests compare nothing that depends on it.
#pragma once

#include <array>
#include <cstdint>
#include <cstring>
#include <string>

namespace lever::test {

inline std::string placeholder_mesh(const std::string& file_name) {
  constexpr float s = 0.05f;
  const std::array<std::array<float, 3>, 4> v{{{0, 0, 0}, {s, 0, 0}, {0, s, 0}, {0, 0, s}}};
  // each face counter-clockwise seen from outside
  const std::array<std::array<int, 3>, 4> faces{{{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}};
  const bool obj = file_name.size() >= 4 && file_name.compare(file_name.size() - 4, 4, ".obj") == 0;
  if (obj) {
    std::string text;
    for (const auto& p : v) {
      text += "v " + std::to_string(p[0]) + " " + std::to_string(p[1]) + " " +
              std::to_string(p[2]) + "\n";
    }
    for (const auto& f : faces) {
      text += "f " + std::to_string(f[0] + 1) + " " + std::to_string(f[1] + 1) + " " +
              std::to_string(f[2] + 1) + "\n";
    }
    return text;
  }
  // binary STL: an 80-byte header, the triangle count, then per triangle a normal, three
  // vertices (little-endian floats) and a 2-byte attribute count
  std::string bytes(80, ' ');
  const auto put = [&bytes](const void* p, std::size_t n) {
    bytes.append(static_cast<const char*>(p), n);
  };
  const std::uint32_t count = faces.size();
  put(&count, sizeof count);
  for (const auto& f : faces) {
    const float normal[3] = {0, 0, 0};  // readers recompute it from the vertices
    put(normal, sizeof normal);
    for (const int i : f) put(v[static_cast<std::size_t>(i)].data(), 3 * sizeof(float));
    const std::uint16_t attribute = 0;
    put(&attribute, sizeof attribute);
  }
  return bytes;
}

}  // namespace lever::test
