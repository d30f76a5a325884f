// Mesh files and mesh mass properties; see mesh.hpp. Every expression keeps MuJoCo 2.2.2's
// operand order and precision (float where MuJoCo computes in float), so that the results agree
// to the last bits.
#include "mesh.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <sstream>

#include "orientation.hpp"

namespace lever::mjcf::detail {

namespace {

constexpr double kMinVal = 1e-15;  // mjMINVAL

// ---- STL -------------------------------------------------------------------------------------

float read_float(const char* p) {
  float x;
  std::memcpy(&x, p, sizeof x);  // little-endian, as the file and the machine
  return x;
}

// ---- OBJ -------------------------------------------------------------------------------------

// A number as tinyobjloader (MuJoCo 2.2.2's OBJ reader) computes it: the digits accumulate in a
// double, each decimal digit scaled by a table power of ten, an exponent applied as
// 5^e * 2^e; the caller rounds to float. Unlike tinyobjloader, anything but a whole number is
// refused (it would silently read "1.5x" as 1.5 and "abc" as 0).
std::optional<double> obj_number(std::string_view s) {
  size_t i = 0;
  const auto digit = [&](size_t k) { return k < s.size() && s[k] >= '0' && s[k] <= '9'; };
  bool negative = false;
  if (i < s.size() && (s[i] == '+' || s[i] == '-')) negative = s[i++] == '-';
  double mantissa = 0;
  int digits = 0;
  while (digit(i)) {
    mantissa = mantissa * 10 + static_cast<int>(s[i++] - '0');
    ++digits;
  }
  if (i < s.size() && s[i] == '.') {
    ++i;
    static const double kTenths[] = {1.0, 0.1, 0.01, 0.001, 0.0001, 0.00001, 0.000001, 0.0000001};
    for (int place = 1; digit(i); ++place, ++i, ++digits) {
      const double scale = place < 8 ? kTenths[place] : std::pow(10.0, -place);
      mantissa += static_cast<int>(s[i] - '0') * scale;
    }
  }
  if (digits == 0) return std::nullopt;
  int exponent = 0;
  if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
    ++i;
    bool exponent_negative = false;
    if (i < s.size() && (s[i] == '+' || s[i] == '-')) exponent_negative = s[i++] == '-';
    if (!digit(i)) return std::nullopt;
    while (digit(i)) {
      if (exponent > 100000) return std::nullopt;
      exponent = exponent * 10 + (s[i++] - '0');
    }
    if (exponent_negative) exponent = -exponent;
  }
  if (i != s.size()) return std::nullopt;
  const double magnitude =
      exponent != 0 ? std::ldexp(mantissa * std::pow(5.0, exponent), exponent) : mantissa;
  return (negative ? -1 : 1) * magnitude;
}

std::vector<std::string_view> obj_fields(std::string_view line) {
  std::vector<std::string_view> out;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    const size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
  return out;
}

std::optional<long> obj_integer(std::string_view s) {
  if (s.empty() || s.size() > 10) return std::nullopt;
  size_t i = s[0] == '-' || s[0] == '+' ? 1 : 0;
  if (i == s.size()) return std::nullopt;
  long v = 0;
  for (size_t k = i; k < s.size(); ++k) {
    if (s[k] < '0' || s[k] > '9') return std::nullopt;
    v = v * 10 + (s[k] - '0');
  }
  return s[0] == '-' ? -v : v;
}

// tinyobjloader's ear clipping of a quadrilateral starts with the ear (0, 1, 2); lever accepts a
// quadrilateral only when that ear is taken, so that the two triangles are (0, 1, 2), (0, 2, 3)
// as in MuJoCo (its test, in float, projected on the two axes the first corner selects)
bool first_ear_taken(const std::vector<float>& v, const std::array<int, 4>& q) {
  const auto at = [&](int corner, size_t axis) {
    return v[3 * static_cast<size_t>(q[static_cast<size_t>(corner) % 4]) + axis];
  };
  size_t axes[2] = {1, 2};
  const float epsilon = std::numeric_limits<float>::epsilon();
  for (int k = 0; k < 4; ++k) {
    const float e0x = at(k + 1, 0) - at(k, 0), e0y = at(k + 1, 1) - at(k, 1),
                e0z = at(k + 1, 2) - at(k, 2);
    const float e1x = at(k + 2, 0) - at(k + 1, 0), e1y = at(k + 2, 1) - at(k + 1, 1),
                e1z = at(k + 2, 2) - at(k + 1, 2);
    const float cx = std::fabs(e0y * e1z - e0z * e1y);
    const float cy = std::fabs(e0z * e1x - e0x * e1z);
    const float cz = std::fabs(e0x * e1y - e0y * e1x);
    if (cx > epsilon || cy > epsilon || cz > epsilon) {
      if (!(cx > cy && cx > cz)) {
        axes[0] = 0;
        if (cz > cx && cz > cy) axes[1] = 1;
      }
      break;
    }
  }
  float area = 0;
  for (int k = 0; k < 4; ++k) {
    area += (at(k, axes[0]) * at(k + 1, axes[1]) - at(k, axes[1]) * at(k + 1, axes[0])) *
            static_cast<float>(0.5);
  }
  float x[3], y[3];
  for (int k = 0; k < 3; ++k) {
    x[k] = at(k, axes[0]);
    y[k] = at(k, axes[1]);
  }
  const float cross = (x[1] - x[0]) * (y[2] - y[1]) - (y[1] - y[0]) * (x[2] - x[1]);
  if (cross * area < 0.0f) return false;
  // the fourth corner must not lie inside the ear (even-odd crossing test)
  const float tx = at(3, axes[0]), ty = at(3, axes[1]);
  bool inside = false;
  for (int i = 0, j = 2; i < 3; j = i++) {
    if (((y[i] > ty) != (y[j] > ty)) && (tx < (x[j] - x[i]) * (ty - y[i]) / (y[j] - y[i]) + x[i])) {
      inside = !inside;
    }
  }
  return !inside;
}

// ---- processing ------------------------------------------------------------------------------

// a triangle's area, unit normal and centre, as MuJoCo computes them: the centre and the edge
// vectors in float, the rest in double; a face with a tiny normal has area 0
double area_normal_centre(Vec3& normal, Vec3& centre, const float* a, const float* b,
                          const float* c) {
  for (size_t i = 0; i < 3; ++i) centre[i] = static_cast<double>((a[i] + b[i] + c[i]) / 3.0f);
  const auto d = [](float x) { return static_cast<double>(x); };
  const double e[3] = {d(b[0] - a[0]), d(b[1] - a[1]), d(b[2] - a[2])};
  const double f[3] = {d(c[0] - a[0]), d(c[1] - a[1]), d(c[2] - a[2])};
  normal = {e[1] * f[2] - e[2] * f[1], e[2] * f[0] - e[0] * f[2], e[0] * f[1] - e[1] * f[0]};
  const double length =
      std::sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]);
  if (length < kMinVal) return 0;
  for (double& n : normal) n /= length;
  return length / 2;
}

double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// second moments of one triangle's vertices (float, in MuJoCo's order) for the pair (i, j)
float vertex_products(const float* d, const float* e, const float* f, size_t i, size_t j) {
  return 2 * (d[i] * d[j] + e[i] * e[j] + f[i] * f[j]) + d[i] * e[j] + d[j] * e[i] + d[i] * f[j] +
         d[j] * f[i] + e[i] * f[j] + e[j] * f[i];
}

// MuJoCo's mjCMesh::RemoveRepeated: the vertices sorted (stably, as glibc's qsort_r sorts) by the
// float key x + 0.01 y + 0.0001 z; a vertex equal to the one before it in that order is merged
// into it; the survivors keep their order and the faces are renumbered.
void remove_repeated(TriangleMesh& m) {
  std::vector<float>& vert = m.vert;
  const int nvert = static_cast<int>(vert.size() / 3);
  const auto key = [&vert](int i) {
    const size_t k = 3 * static_cast<size_t>(i);
    return static_cast<float>(static_cast<double>(vert[k]) + 1e-2 * static_cast<double>(vert[k + 1]) +
                              1e-4 * static_cast<double>(vert[k + 2]));
  };
  std::vector<int> order(static_cast<size_t>(nvert)), redirect(static_cast<size_t>(nvert));
  for (int i = 0; i < nvert; ++i) order[i] = redirect[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return key(a) < key(b); });
  int repeated = 0;
  const auto same = [&vert](int a, int b) {
    return vert[3 * a] == vert[3 * b] && vert[3 * a + 1] == vert[3 * b + 1] &&
           vert[3 * a + 2] == vert[3 * b + 2];
  };
  for (int i = 1; i < nvert; ++i) {
    if (same(order[i], order[i - 1])) {
      redirect[order[i]] = order[i - 1];
      ++repeated;
    }
  }
  if (repeated == 0) return;
  for (int i = 0; i < nvert; ++i) {
    int j = i;
    while (redirect[j] != j) j = redirect[j];
    redirect[i] = j;
  }
  std::vector<int> position(static_cast<size_t>(nvert), -1);
  int kept = 0;
  for (int i = 0; i < nvert; ++i) {
    if (redirect[i] != i) continue;
    position[i] = kept;
    for (int k = 0; k < 3; ++k) vert[3 * kept + k] = vert[3 * i + k];
    ++kept;
  }
  vert.resize(3 * static_cast<size_t>(kept));
  for (int& f : m.face) f = position[redirect[f]];
}

}  // namespace

TriangleMesh read_stl(const std::string& bytes, bool righthand) {
  if (bytes.empty()) throw MeshError("the file is empty");
  const bool ascii = bytes.compare(0, 5, "solid") == 0;
  const std::string ascii_hint =
      ascii ? " (it looks like an ASCII STL file; MuJoCo 2.2.2 reads only binary STL: convert it)"
            : "";
  if (bytes.size() < 84) throw MeshError("the STL header is incomplete" + ascii_hint);
  std::uint32_t count;
  std::memcpy(&count, bytes.data() + 80, sizeof count);
  if (count < 1 || count > 200000) {
    throw MeshError("a binary STL file must have 1 to 200000 triangles; this one says " +
                    std::to_string(count) + ascii_hint);
  }
  if (static_cast<std::size_t>(count) * 50 != bytes.size() - 84) {
    throw MeshError("the file has " + std::to_string(bytes.size()) +
                    " bytes, but a binary STL of " + std::to_string(count) + " triangles has " +
                    std::to_string(84 + static_cast<std::size_t>(count) * 50) + ascii_hint);
  }
  TriangleMesh m;
  m.vert.reserve(9 * static_cast<size_t>(count));
  m.face.resize(3 * static_cast<size_t>(count));
  for (size_t i = 0; i < count; ++i) {
    for (size_t j = 0; j < 3; ++j) {
      const char* p = bytes.data() + 84 + 50 * i + 12 * (j + 1);
      for (size_t k = 0; k < 3; ++k) {
        const float x = read_float(p + 4 * k);
        if (!std::isfinite(x)) {
          throw MeshError("triangle " + std::to_string(i + 1) +
                          " has a coordinate that is not finite");
        }
        if (static_cast<double>(std::fabs(x)) > 1073741824.0) {  // 2^30
          throw MeshError("triangle " + std::to_string(i + 1) +
                          " has a coordinate beyond 2^30 (MuJoCo's bound)");
        }
        m.vert.push_back(x);
      }
      // a mirroring scale reverses the triangle, as in MuJoCo
      const int vertex = static_cast<int>(3 * i + j);
      m.face[righthand || j == 0 ? 3 * i + j : 3 * i + 3 - j] = vertex;
    }
  }
  remove_repeated(m);
  return m;
}

TriangleMesh read_obj(const std::string& text, bool righthand) {
  std::vector<float> v;
  std::vector<std::vector<long>> faces;  // as written (1-based, or negative = relative)
  std::vector<int> face_line;
  bool split = false;  // a group/object/material line after faces: MuJoCo keeps only the first
  std::istringstream in(text);
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    const std::vector<std::string_view> t = obj_fields(line);
    const std::string where = "line " + std::to_string(number) + ": ";
    if (t.empty() || t[0][0] == '#') continue;
    const std::string_view key = t[0];
    if (key == "v") {
      if (t.size() < 4) throw MeshError(where + "a vertex needs three coordinates");
      for (size_t k = 1; k <= 3; ++k) {
        const std::optional<double> x = obj_number(t[k]);
        if (!x || !std::isfinite(static_cast<float>(*x))) {
          throw MeshError(where + "'" + std::string(t[k]) + "' is not a finite number");
        }
        v.push_back(static_cast<float>(*x));
      }
    } else if (key == "f") {
      if (split) {
        throw MeshError(where +
                        "faces after a new group, object or material: MuJoCo 2.2.2 "
                        "would use only the first group; lever refuses such a file");
      }
      if (t.size() != 4 && t.size() != 5) {
        throw MeshError(where + "lever reads faces of 3 or 4 vertices; this one has " +
                        std::to_string(t.size() - 1) + " (split it into triangles)");
      }
      std::vector<long> f;
      for (size_t k = 1; k < t.size(); ++k) {
        const std::string_view index = t[k].substr(0, t[k].find('/'));
        const std::optional<long> i = obj_integer(index);
        if (!i || *i == 0) {
          throw MeshError(where + "'" + std::string(t[k]) + "' is not a vertex index");
        }
        // a negative index counts back from the vertices read so far
        f.push_back(*i > 0 ? *i - 1 : static_cast<long>(v.size() / 3) + *i);
      }
      faces.push_back(std::move(f));
      face_line.push_back(number);
    } else if (key == "o" || key == "g" || key == "usemtl") {
      split = split || !faces.empty();
    } else if (key == "vn" || key == "vt" || key == "vp" || key == "s" || key == "mtllib") {
      // normals, texture coordinates, smoothing and materials: no effect on mass
    } else {
      throw MeshError(where + "lever does not read OBJ '" + std::string(key) +
                      "' lines (it reads v, f, vn, vt, vp, s, o, g, usemtl, mtllib)");
    }
  }
  if (faces.empty()) {
    throw MeshError(
        "the file has no faces (MuJoCo would build the convex hull of its vertices, "
        "which lever does not)");
  }
  const long nvert = static_cast<long>(v.size() / 3);
  TriangleMesh m;
  std::map<std::pair<long, long>, int> edges;
  for (size_t i = 0; i < faces.size(); ++i) {
    const std::vector<long>& f = faces[i];
    for (const long index : f) {
      if (index < 0 || index >= nvert) {
        throw MeshError("line " + std::to_string(face_line[i]) + ": vertex index out of range (" +
                        std::to_string(nvert) + " vertices)");
      }
    }
    std::vector<std::array<long, 3>> triangles{{f[0], f[1], f[2]}};
    if (f.size() == 4) {
      const std::array<int, 4> quad{static_cast<int>(f[0]), static_cast<int>(f[1]),
                                    static_cast<int>(f[2]), static_cast<int>(f[3])};
      if (!first_ear_taken(v, quad)) {
        throw MeshError("line " + std::to_string(face_line[i]) +
                        ": a non-convex or folded quadrilateral; split it into triangles");
      }
      triangles.push_back({f[0], f[2], f[3]});
    }
    for (const auto& tri : triangles) {
      // MuJoCo notes each directed edge; one used twice means inconsistent orientation
      for (size_t k = 0; k < 3; ++k) {
        if (++edges[{tri[k], tri[(k + 1) % 3]}] > 1) m.consistent = false;
      }
      // every triangle gets its own three vertices, as in MuJoCo
      const int first = static_cast<int>(m.vert.size() / 3);
      for (const long index : tri) {
        for (size_t k = 0; k < 3; ++k) m.vert.push_back(v[3 * static_cast<size_t>(index) + k]);
      }
      m.face.push_back(first);
      m.face.push_back(righthand ? first + 1 : first + 2);
      m.face.push_back(righthand ? first + 2 : first + 1);
    }
  }
  return m;
}

MeshMass process_mesh(TriangleMesh mesh, const Vec3& refpos, const Quat& refquat, const Vec3& scale,
                      double density, bool exact, bool hull) {
  // MuJoCo builds the hull from the vertices as read; its vertex numbers hold after processing
  std::vector<int> graph;
  if (hull) graph = convex_hull_graph(mesh.vert);
  std::vector<float>& vert = mesh.vert;
  const std::vector<int>& face = mesh.face;
  const size_t nvert = vert.size() / 3, nface = face.size() / 3;
  const auto corner = [&](size_t f, size_t k) {
    return vert.data() + 3 * static_cast<size_t>(face[3 * f + k]);
  };
  // MuJoCo reports a bad face orientation before any other fault it found while processing
  const auto fault = [&](const std::string& reason) -> MeshError {
    if (!mesh.consistent) {
      return MeshError(
          "its faces have inconsistent orientation (two faces share an edge "
          "in the same direction)");
    }
    return MeshError(reason);
  };

  // the reference frame, then the scale, in float as MuJoCo keeps the vertices
  if (refpos[0] != 0 || refpos[1] != 0 || refpos[2] != 0) {
    const float rp[3] = {static_cast<float>(refpos[0]), static_cast<float>(refpos[1]),
                         static_cast<float>(refpos[2])};
    for (size_t i = 0; i < nvert; ++i) {
      for (size_t k = 0; k < 3; ++k) vert[3 * i + k] -= rp[k];
    }
  }
  if (refquat[0] != 1 || refquat[1] != 0 || refquat[2] != 0 || refquat[3] != 0) {
    Quat q = refquat;
    engine_normalize(q);
    const Mat3 r = engine_rotation(q);
    for (size_t i = 0; i < nvert; ++i) {
      const double p[3] = {static_cast<double>(vert[3 * i]), static_cast<double>(vert[3 * i + 1]),
                           static_cast<double>(vert[3 * i + 2])};
      for (size_t k = 0; k < 3; ++k) {
        vert[3 * i + k] = static_cast<float>(r[k] * p[0] + r[3 + k] * p[1] + r[6 + k] * p[2]);
      }
    }
  }
  if (scale[0] != 1 || scale[1] != 1 || scale[2] != 1) {
    for (size_t i = 0; i < nvert; ++i) {
      for (size_t k = 0; k < 3; ++k) {
        vert[3 * i + k] = static_cast<float>(static_cast<double>(vert[3 * i + k]) * scale[k]);
      }
    }
  }

  MeshMass out;
  Vec3 normal{}, centre{};
  // the two passes of mjCMesh::Process: the solid (whose results lever uses), then the shell
  // (whose results only MuJoCo's checks use: a mesh MuJoCo refuses is refused here too)
  for (const bool shell : {false, true}) {
    Vec3 facecen{};
    if (!shell) {
      double area = 0;
      for (size_t f = 0; f < nface; ++f) {
        const double a =
            area_normal_centre(normal, centre, corner(f, 0), corner(f, 1), corner(f, 2));
        for (size_t k = 0; k < 3; ++k) facecen[k] += a * centre[k];
        area += a;
      }
      if (area < kMinVal) throw fault("its surface area is too small (below 1e-15)");
      for (double& c : facecen) c /= area;
    }

    // volume and centre of mass from the pyramids of the faces on the face centroid
    double volume = 0;
    Vec3 com{};
    for (size_t f = 0; f < nface; ++f) {
      const double a = area_normal_centre(normal, centre, corner(f, 0), corner(f, 1), corner(f, 2));
      const Vec3 arm{centre[0] - facecen[0], centre[1] - facecen[1], centre[2] - facecen[2]};
      double vol = shell ? a : dot(arm, normal) * a / 3;
      if (!exact) vol = std::fabs(vol);  // MuJoCo's legacy mesh inertia
      volume += vol;
      for (size_t k = 0; k < 3; ++k) com[k] += vol * (centre[k] * 3.0 / 4.0 + facecen[k] / 4.0);
    }
    if (volume < kMinVal) {
      throw fault(shell ? "its surface area is too small (below 1e-15)"
                        : "its volume is too small (below 1e-15): is the mesh closed, its "
                          "faces pointing outwards?");
    }
    for (double& c : com) c /= volume;
    if (!shell) {
      out.pos = com;
      for (size_t i = 0; i < nvert; ++i) {
        for (size_t k = 0; k < 3; ++k) {
          vert[3 * i + k] = static_cast<float>(static_cast<double>(vert[3 * i + k]) - com[k]);
        }
      }
    }

    // products of inertia about the centre of mass (the float sums as MuJoCo forms them)
    static const size_t kPair[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}};
    double products[6] = {0, 0, 0, 0, 0, 0};
    volume = 0;
    for (size_t f = 0; f < nface; ++f) {
      const float* d = corner(f, 0);
      const float* e = corner(f, 1);
      const float* g = corner(f, 2);
      const double a = area_normal_centre(normal, centre, d, e, g);
      double vol = shell ? a : dot(centre, normal) * a / 3;
      if (!exact) vol = std::fabs(vol);
      volume += vol;
      for (size_t j = 0; j < 6; ++j) {
        products[j] += density * vol / (shell ? 12 : 20) *
                       static_cast<double>(vertex_products(d, e, g, kPair[j][0], kPair[j][1]));
      }
    }
    const Sym6 inertia{products[1] + products[2],
                       products[0] + products[2],
                       products[0] + products[1],
                       -products[3],
                       -products[4],
                       -products[5]};
    const Principal p = principal_axes(inertia);
    const Vec3& e = p.moments;
    if (e[2] <= 0) {
      throw fault(
          "a principal moment of its inertia is not positive (a flat or degenerate mesh, "
          "or a mesh class with geom density 0)");
    }
    if (e[0] + e[1] < e[2] || e[0] + e[2] < e[1] || e[1] + e[2] < e[0]) {
      throw fault("the principal moments of its inertia violate A + B >= C");
    }
    const double mass = volume * density;
    if (shell) {
      // MuJoCo's shell pass: its centre (the face centroids weighted by area, times 3/4: the
      // pyramid formula with no apex) and axes in the vertices' frame after the solid pass
      out.shell_pos = com;
      out.shell_quat = p.quat;
      out.surface = volume;
      out.shell_box = {std::sqrt(6 * (e[1] + e[2] - e[0]) / mass) / 2,
                       std::sqrt(6 * (e[0] + e[2] - e[1]) / mass) / 2,
                       std::sqrt(6 * (e[0] + e[1] - e[2]) / mass) / 2};
      break;
    }
    out.volume = volume;
    out.box = {std::sqrt(6 * (e[1] + e[2] - e[0]) / mass) / 2,
               std::sqrt(6 * (e[0] + e[2] - e[1]) / mass) / 2,
               std::sqrt(6 * (e[0] + e[1] - e[2]) / mass) / 2};
    out.quat = p.quat;

    // the vertices in the principal frame, and their bounding box
    const Mat3 r = rotation({p.quat[0], -p.quat[1], -p.quat[2], -p.quat[3]});
    for (size_t i = 0; i < nvert; ++i) {
      const double x[3] = {static_cast<double>(vert[3 * i]), static_cast<double>(vert[3 * i + 1]),
                           static_cast<double>(vert[3 * i + 2])};
      for (size_t k = 0; k < 3; ++k) {
        vert[3 * i + k] =
            static_cast<float>(r[3 * k] * x[0] + r[3 * k + 1] * x[1] + r[3 * k + 2] * x[2]);
      }
    }
    for (size_t i = 0; i < nvert; ++i) {
      for (size_t k = 0; k < 3; ++k) {
        out.aabb[k] = std::max(out.aabb[k], static_cast<double>(std::fabs(vert[3 * i + k])));
      }
    }
  }
  if (!mesh.consistent) throw fault("");
  out.vert = std::move(vert);
  out.graph = std::move(graph);
  out.face = std::move(mesh.face);
  return out;
}

std::string mesh_path(const std::string& model_dir, std::string meshdir, const std::string& file) {
  const auto absolute = [](const std::string& p) {
    return (!p.empty() && (p[0] == '/' || p[0] == '\\')) ||
           (p.size() > 2 && p[1] == ':' && (p[2] == '/' || p[2] == '\\'));
  };
  if (!meshdir.empty() && meshdir.back() != '/' && meshdir.back() != '\\') meshdir += '/';
  if (absolute(file)) return file;
  if (absolute(meshdir)) return meshdir + file;
  return model_dir + meshdir + file;
}

std::string read_mesh_file(const std::string& path, std::size_t max_bytes) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw MeshError("no such file");
  if (!std::filesystem::is_regular_file(path, ec)) throw MeshError("not a regular file");
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (!ec && size > max_bytes) {
    throw MeshError("the file has " + std::to_string(size) + " bytes; lever reads at most " +
                    std::to_string(max_bytes));
  }
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  if (!in) throw MeshError("the file cannot be read");
  return bytes.str();
}

}  // namespace lever::mjcf::detail
