// The compiler: ModelSpec -> Model; see compiler.hpp. The steps and their order follow MuJoCo
// 2.2.2's mjCModel::TryCompile and mjCBody/mjCGeom/mjCJoint/mjCSite/mjCActuator::Compile
// (user_model.cc, user_objects.cc), so that the same input gives the same numbers, and checks
// run in MuJoCo's order.
#include "compiler.hpp"

#include <lever/collision.hpp>
#include <lever/fields.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <optional>
#include <set>

#include "equality.hpp"
#include "tendon.hpp"
#include "inertia.hpp"
#include "mesh.hpp"
#include "orientation.hpp"

namespace lever::mjcf::detail {

namespace {

// ---- compiled pieces, before they are copied into the Model ------------------------------------

struct BodyNode {
  const BodySpec* spec;
  int parent;
  std::vector<int> children;
};

struct CompiledBody {
  Vec3 pos{};
  Quat quat{1, 0, 0, 0};
  BodyInertia inertial;
  bool explicit_inertial = false;
  int first_joint = -1, first_geom = -1;
};

struct CompiledGeom {
  const GeomSpec* spec;
  int body;
  Vec3 size{}, pos{};
  Quat quat{1, 0, 0, 0};
  double mass = 0;
  Vec3 inertia{};
};

struct CompiledJoint {
  const JointSpec* spec;
  int body;
  Vec3 axis{};
  std::array<double, 2> range{};
  bool limited = false;
  double ref = 0, springref = 0;
  Vec3 pos{};  ///< anchor (a free joint's is the origin)
};

struct CompiledSite {
  const SiteSpec* spec;
  int body;
  Quat quat{1, 0, 0, 0};
};

// where an element is written, for messages that name several: its line, with its file when it
// comes from an included one
std::string line_text(const Place& at) {
  return at.file.empty() ? std::to_string(at.line) : at.file + ":" + std::to_string(at.line);
}

struct CompiledMotor {
  const MotorSpec* spec;
  TransmissionType trntype = TransmissionType::kJoint;
  std::array<int, 2> trnid{-1, -1};  ///< Model::actuator_trnid
  bool ctrllimited = false, forcelimited = false, actlimited = false;
  std::array<double, 2> ctrlrange{};  ///< as written, or from the joint's range (inheritrange)
};

// a <contact><pair>, its geoms ordered by body as MuJoCo orders them
struct CompiledPair {
  const PairSpec* spec;
  int geom1 = -1, geom2 = -1;
  int signature = 0;
};

struct CompiledExclude {
  int signature = 0;
};

// MuJoCo's signature of a body pair (mjCPair, mjCBodyPair): the lower body id first, both + 1
int body_pair_signature(int body1, int body2) {
  return ((std::min(body1, body2) + 1) << 16) + std::max(body1, body2) + 1;
}

std::string show3(const Vec3& v) { return show(v[0]) + " " + show(v[1]) + " " + show(v[2]); }

// finite input can still overflow (a huge density, fromto or settotalmass): refuse the result
template <class... Arrays>
void require_finite(const Place& at, const char* what, const Arrays&... arrays) {
  const auto finite = [](const auto& a) {
    return std::all_of(a.begin(), a.end(), [](double x) { return std::isfinite(x); });
  };
  if (!(finite(arrays) && ...)) {
    fail(at, "", std::string("the numbers are too large: the compiled ") + what + " is not finite");
  }
}

// which attribute a degenerate orientation came from, and a message a student can act on
[[noreturn]] void fail_orientation(const Place& at, const std::string& reason) {
  struct Known {
    const char* reason;
    const char* attribute;
    const char* message;
  };
  static const Known known[] = {
      {"axisangle too small", "axisangle", "the axis of 'axisangle' has zero length"},
      {"xaxis too small", "xyaxes", "the x axis of 'xyaxes' has zero length"},
      {"yaxis too small", "xyaxes", "the y axis of 'xyaxes' is zero or parallel to the x axis"},
      {"cross(xaxis, yaxis) too small", "xyaxes", "the axes of 'xyaxes' are parallel"},
      {"zaxis too small", "zaxis", "'zaxis' has zero length"},
      {"inertia must have positive eigenvalues", "fullinertia",
       "'fullinertia' is not positive definite (a principal moment is below 1e-14)"},
  };
  for (const Known& k : known) {
    if (reason == k.reason) fail(at, k.attribute, k.message);
  }
  fail(at, "", reason);
}

// how many sizes each geom type uses, and what they mean
int sizes_used(GeomType type) {
  switch (type) {
    case GeomType::kSphere: return 1;
    case GeomType::kCapsule:
    case GeomType::kCylinder: return 2;
    case GeomType::kEllipsoid:
    case GeomType::kBox: return 3;
    case GeomType::kMesh: return 0;    // its size comes from the mesh
    case GeomType::kPlane:             // only its grid spacing must be positive (compile_geom)
    case GeomType::kHfield: return 0;  // refused by the parser
  }
  return 3;
}

const char* type_name(GeomType type) {
  switch (type) {
    case GeomType::kSphere: return "sphere";
    case GeomType::kCapsule: return "capsule";
    case GeomType::kCylinder: return "cylinder";
    case GeomType::kEllipsoid: return "ellipsoid";
    case GeomType::kBox: return "box";
    case GeomType::kMesh: return "mesh";
    case GeomType::kPlane: return "plane";
    case GeomType::kHfield: return "hfield";
  }
  return "geom";
}

const char* size_meaning(GeomType type) {
  switch (type) {
    case GeomType::kSphere: return "a positive radius: size=\"r\"";
    case GeomType::kCapsule:
    case GeomType::kCylinder:
      return "a positive radius and half-length: size=\"r h\" (or size=\"r\" with fromto)";
    case GeomType::kEllipsoid: return "three positive semi-axes: size=\"a b c\"";
    case GeomType::kBox: return "three positive half-sizes: size=\"x y z\"";
    case GeomType::kMesh: return "nothing (the mesh gives its size)";
    case GeomType::kPlane:
      return "a positive third size, the grid spacing it is drawn with: size=\"x y spacing\" (x, "
             "y: half-sizes drawn, 0 for infinite)";
    case GeomType::kHfield: return "an hfield asset";
  }
  return "";
}

// radius of the sphere around the geom's centre that holds it (mjCGeom::GetRBound); 0 for a
// plane, which is infinite; a mesh geom's from the half-sizes of its bounding box (zero for a mesh
// lever did not read, see apply_mesh)
double bounding_radius(GeomType type, const Vec3& size) {
  switch (type) {
    case GeomType::kSphere: return size[0];
    case GeomType::kCapsule: return size[0] + size[1];
    case GeomType::kCylinder: return std::sqrt(size[0] * size[0] + size[1] * size[1]);
    case GeomType::kEllipsoid: return std::max(std::max(size[0], size[1]), size[2]);
    case GeomType::kBox:
    case GeomType::kMesh:
      return std::sqrt(size[0] * size[0] + size[1] * size[1] + size[2] * size[2]);
    case GeomType::kPlane:
    case GeomType::kHfield: return 0;
  }
  return 0;
}

// resolve limited="auto" (mujoco: checklimited); the attribute names are for the message
bool resolve_limited(Limited limited, const std::array<double, 2>& range, bool autolimits,
                     const Place& at, const std::string& range_attribute,
                     const std::string& limited_attribute) {
  if (limited != Limited::kAuto) return limited == Limited::kTrue;
  const bool has_range = !(range[0] == 0 && range[1] == 0);
  if (has_range && !autolimits) {
    fail(at, range_attribute,
         "'" + range_attribute + "' is given but '" + limited_attribute +
             "' is not, and compiler/autolimits is false: set " + limited_attribute +
             "=\"true\" or \"false\", or remove "
             "autolimits=\"false\"");
  }
  return has_range;
}

// ---- the compiler ------------------------------------------------------------------------------

class Compiler {
 public:
  explicit Compiler(const ModelSpec& spec) : spec_(spec), c_(spec.compiler) {}

  Model run(Locations* where) {
    flatten(spec_.world, 0);
    check_names();
    for (size_t id = 0; id < bodies_.size(); ++id) compile_body(static_cast<int>(id));
    compile_contact();
    for (const TendonSpec& t : spec_.tendons) {
      tendon_limited_.push_back(
          resolve_limited(t.limited, t.range, c_.autolimits, t.at, "range", "limited"));
    }
    for (const MotorSpec& m : spec_.motors) motors_.push_back(compile_motor(m));
    check_stateless_first();
    check_moving_bodies();
    for (const KeySpec& k : spec_.keys) check_key(k);
    warn_unsupported_pairs();
    scale_total_mass();
    if (where) {
      for (const BodyNode& n : nodes_) where->body.push_back(n.spec->at);
      for (const BodyNode& n : nodes_) {
        where->inertial.push_back(n.spec->inertial ? n.spec->inertial->at : Place{});
      }
      for (const CompiledJoint& j : joints_) where->joint.push_back(j.spec->at);
      for (const CompiledSite& s : sites_) where->site.push_back(s.spec->at);
      for (const CompiledMotor& m : motors_) where->actuator.push_back(m.spec->at);
    }
    return assemble();
  }

 private:
  // ---- structure ----------------------------------------------------------------------------

  // bodies depth-first, pre-order (world = 0); joints, geoms and sites in body order
  void flatten(const BodySpec& b, int parent) {
    const int id = static_cast<int>(nodes_.size());
    nodes_.push_back({&b, parent, {}});
    if (id > 0) nodes_[static_cast<size_t>(parent)].children.push_back(id);
    if (b.mocap && (id == 0 || parent != 0 || !b.joints.empty())) {
      // as MuJoCo 2.2.2's compiler: a mocap body hangs from the world and has no joints
      fail(b.at, "mocap",
           "mocap body '" + b.at.name + "' is not a fixed child of the world: a mocap body must "
           "be a child of <worldbody> without joints");
    }
    if (b.mocap) ++nmocap_;
    // the body it moves with: itself if it has joints, else its parent's (mujoco's weldid)
    weld_.push_back(id == 0 || !b.joints.empty() ? id : weld_[static_cast<size_t>(parent)]);
    bodies_.emplace_back();
    for (const BodySpec& child : b.children) flatten(child, id);
  }

  static void check_unique(const std::vector<std::pair<const Place*, std::string>>& items,
                           const std::string& kind) {
    std::map<std::string, int> first_line;
    for (const auto& [place, name] : items) {
      if (name.empty()) continue;  // empty names may repeat, as in mujoco
      const auto [it, inserted] = first_line.emplace(name, place->line);
      if (!inserted) {
        const std::string where = it->second > 0
                                      ? " (also at line " + std::to_string(it->second) + ")"
                                      : " (it names the world body)";
        fail(*place, "name", "duplicate " + kind + " name '" + name + "'" + where);
      }
    }
  }

  void check_names() {
    std::vector<std::pair<const Place*, std::string>> bodies, joints, geoms, sites, motors;
    const Place world{"worldbody", "world", 0};
    bodies.push_back({&world, "world"});
    for (size_t i = 1; i < nodes_.size(); ++i) {
      bodies.push_back({&nodes_[i].spec->at, nodes_[i].spec->at.name});
    }
    for (const BodyNode& n : nodes_) {
      for (const JointSpec& j : n.spec->joints) joints.push_back({&j.at, j.at.name});
      for (const GeomSpec& g : n.spec->geoms) geoms.push_back({&g.at, g.at.name});
      for (const SiteSpec& s : n.spec->sites) sites.push_back({&s.at, s.at.name});
    }
    for (const MotorSpec& m : spec_.motors) motors.push_back({&m.at, m.at.name});
    std::vector<std::pair<const Place*, std::string>> keys, meshes, materials;
    for (const KeySpec& k : spec_.keys) keys.push_back({&k.at, k.at.name});
    for (const Place& p : spec_.assets.meshes) meshes.push_back({&p, p.name});
    for (const Place& p : spec_.assets.materials) materials.push_back({&p, p.name});
    check_unique(keys, "keyframe");
    check_unique(meshes, "mesh");
    check_unique(materials, "material");
    check_unique(bodies, "body");
    check_unique(joints, "joint");
    check_unique(geoms, "geom");
    check_unique(sites, "site");
    check_unique(motors, "motor");
    std::vector<std::pair<const Place*, std::string>> tendons;
    for (const TendonSpec& t : spec_.tendons) tendons.push_back({&t.at, t.at.name});
    check_unique(tendons, "tendon");
    std::vector<std::pair<const Place*, std::string>> pairs, excludes;
    for (const PairSpec& p : spec_.pairs) pairs.push_back({&p.at, p.at.name});
    for (const ExcludeSpec& x : spec_.excludes) excludes.push_back({&x.at, x.at.name});
    check_unique(pairs, "pair");
    check_unique(excludes, "exclude");
  }

  // ---- bodies ---------------------------------------------------------------------------------

  void compile_body(int id) {
    const BodySpec& b = *nodes_[static_cast<size_t>(id)].spec;
    CompiledBody& out = bodies_[static_cast<size_t>(id)];
    out.pos = b.pos;
    out.quat = b.orientation.quat;
    normalize(out.quat.data(), 4);
    if (const char* reason =
            apply_alternatives(b.orientation, c_.degree, c_.eulerseq, out.quat, nullptr)) {
      fail_orientation(b.at, reason);
    }
    const bool has_inertial = id > 0 && b.inertial.has_value();
    if (has_inertial) read_inertial(*b.inertial, out);

    out.first_geom = static_cast<int>(geoms_.size());
    for (const GeomSpec& g : b.geoms) {
      geoms_.push_back(compile_geom(g, id, id > 0 && gives_mass(has_inertial, g)));
    }
    if (id > 0) infer_inertia(id, has_inertial, out);
    if (id > 0) check_inertia(b, out);
    require_finite(b.at, "body", out.quat, out.inertial.ipos, out.inertial.iquat,
                   std::array<double, 1>{out.inertial.mass}, out.inertial.inertia);

    out.first_joint = static_cast<int>(joints_.size());
    for (const JointSpec& j : b.joints) joints_.push_back(compile_joint(j, id));
    for (const SiteSpec& s : b.sites) sites_.push_back(compile_site(s, id));
  }

  void read_inertial(const InertialSpec& in, CompiledBody& out) {
    out.explicit_inertial = true;
    out.inertial.ipos = in.pos;
    out.inertial.mass = in.mass;
    out.inertial.inertia = in.diaginertia;
    out.inertial.iquat = in.orientation.quat;
    normalize(out.inertial.iquat.data(), 4);
    if (const char* reason = apply_alternatives(in.orientation, c_.degree, c_.eulerseq,
                                                out.inertial.iquat, &out.inertial.inertia)) {
      fail_orientation(in.at, reason);
    }
  }

  bool from_geoms(bool has_inertial) const {
    return c_.inertiafromgeom == InertiaFromGeom::kTrue ||
           (c_.inertiafromgeom == InertiaFromGeom::kAuto && !has_inertial);
  }

  // whether a geom of a body (not the world) enters the body's mass and inertia
  bool gives_mass(bool has_inertial, const GeomSpec& g) const {
    return from_geoms(has_inertial) && g.group >= c_.inertiagrouprange[0] &&
           g.group <= c_.inertiagrouprange[1];
  }

  // mass from geoms when inertiafromgeom says so (mjCBody::GeomFrame); a body with no mass
  // source takes its own frame as inertial frame, with zero mass (mujoco copies pos and quat)
  void infer_inertia(int id, bool has_inertial, CompiledBody& out) {
    const bool from_geoms = this->from_geoms(has_inertial);
    std::vector<MassElement> parts;
    for (size_t g = static_cast<size_t>(out.first_geom); from_geoms && g < geoms_.size(); ++g) {
      const CompiledGeom& geom = geoms_[g];
      const int group = geom.spec->group;
      if (group >= c_.inertiagrouprange[0] && group <= c_.inertiagrouprange[1]) {
        parts.push_back({geom.pos, geom.quat, geom.mass, geom.inertia});
      }
    }
    if (parts.size() == 1) {
      // one geom: its frame and its unsorted moments become the body's
      out.inertial = BodyInertia{parts[0].pos, parts[0].quat, parts[0].mass, parts[0].inertia};
      out.explicit_inertial = false;
    } else if (parts.size() > 1) {
      if (auto reason = combine(parts, out.inertial)) {
        fail(nodes_[static_cast<size_t>(id)].spec->at, "", *reason + " (inferred from its geoms)");
      }
      out.explicit_inertial = false;
    } else if (!has_inertial) {
      out.inertial = BodyInertia{out.pos, out.quat, 0, {0, 0, 0}};
    }
  }

  // ---- meshes ---------------------------------------------------------------------------------

  // whether a ray is cast at the geoms (then every mesh is read, as MuJoCo reads them all)
  bool has_rangefinder() const {
    for (const SensorSpec& s : spec_.sensors) {
      if (s.type == SensorType::kRangefinder) return true;
    }
    return false;
  }

  // A mesh geom that gives its body mass or can collide: read and process its mesh (once per
  // mesh), then move the geom's frame to the mesh's centre and principal axes, size it by the
  // mesh's bounding box and, if it gives mass, give it the mass and inertia MuJoCo 2.2.2 gives it
  // (mjCGeom::Compile, GetVolume, SetInertia).
  void apply_mesh(const GeomSpec& g, int body, CompiledGeom& out, bool gives_mass) {
    const size_t m = mesh_index(g);
    const MeshMass& mesh = mesh_mass(m, g, body, gives_mass);
    // the solid's frame, or with shellinertia the shell's (MuJoCo 2.2.2's typeinertia)
    const Vec3& frame_pos = g.shellinertia ? mesh.shell_pos : mesh.pos;
    const Quat& frame_quat = g.shellinertia ? mesh.shell_quat : mesh.quat;
    const Mat3 r = rotation(out.quat);
    for (size_t k = 0; k < 3; ++k) {
      out.pos[k] += r[3 * k] * frame_pos[0] + r[3 * k + 1] * frame_pos[1] +
                    r[3 * k + 2] * frame_pos[2];
    }
    out.quat = compiler_product(out.quat, frame_quat);
    out.size = mesh.aabb;
    if (!gives_mass) return;  // read for collision only: its frame and size
    // the volume: the shell's area when exact, else (MuJoCo 2.2.2) the solid's inertia box even
    // for a shell; the inertia from the chosen inertia box
    const Vec3& b = g.shellinertia ? mesh.shell_box : mesh.box;
    const Vec3& solid = mesh.box;
    const double volume = c_.exactmeshinertia ? (g.shellinertia ? mesh.surface : mesh.volume)
                                              : solid[0] * solid[1] * solid[2] * 8;
    if (g.mass) {
      // a given mass goes only to a geom with a volume; mass 0 keeps zero inertia (mujoco)
      if (*g.mass == 0 || !(volume > 1e-15)) return;
      out.mass = *g.mass;
    } else {
      out.mass = g.density * volume;
    }
    out.inertia = {out.mass * (b[1] * b[1] + b[2] * b[2]) / 3,
                   out.mass * (b[0] * b[0] + b[2] * b[2]) / 3,
                   out.mass * (b[0] * b[0] + b[1] * b[1]) / 3};
  }

  size_t mesh_index(const GeomSpec& g) const {
    size_t m = 0;
    while (spec_.assets.meshes[m].name != g.mesh) ++m;  // check_mesh found it
    return m;
  }

  static bool can_collide(const GeomSpec& g) { return g.contype != 0 || g.conaffinity != 0; }

  // whether MuJoCo builds mesh m's convex hull: a mesh geom using it can collide and the compiler's
  // convexhull is on (mjCModel::Compile's needhull)
  bool needs_hull(size_t m) const {
    if (!c_.convexhull) return false;
    for (const BodyNode& node : nodes_) {
      for (const GeomSpec& g : node.spec->geoms) {
        if (g.type == GeomType::kMesh && can_collide(g) && g.mesh == spec_.assets.meshes[m].name) {
          return true;
        }
      }
    }
    return false;
  }

  const MeshMass& mesh_mass(size_t m, const GeomSpec& g, int body, bool gives_mass) {
    if (mesh_cache_.size() <= m) mesh_cache_.resize(spec_.assets.meshes.size());
    if (mesh_cache_[m]) return *mesh_cache_[m];
    const Place& at = spec_.assets.meshes[m];
    const std::string& file = spec_.assets.mesh_files[m];
    const std::string& body_name = nodes_[static_cast<size_t>(body)].spec->at.name;
    const std::string geom =
        "mesh geom" + (g.at.name.empty() ? std::string() : " '" + g.at.name + "'");
    const std::string why =
        gives_mass ? geom + " must give body '" + body_name + "' its mass and inertia"
                   : geom + " can collide (contype or conaffinity is not 0)";
    const std::string advice =
        gives_mass ? ". Fix that, or add an <inertial> to body '" + body_name +
                         "' and set the geom's contype and conaffinity to 0 (then lever does not "
                         "read the mesh)"
                   : ". Fix that, or set the geom's contype and conaffinity to 0 (then lever "
                     "does not read the mesh)";
    const std::string mesh = "mesh '" + at.name + "' (line " + line_text(at) + ")";
    if (file.empty()) {
      fail(g.at, "mesh",
           why + ", but " + mesh +
               " gives its vertices inline, which lever does not read: put them in an STL or OBJ "
               "file" +
               advice);
    }
    const std::string path = mesh_path(spec_.model_dir, c_.meshdir, file);
    const std::string ext = file.size() >= 4 ? file.substr(file.size() - 4) : file;
    const auto is = [&ext](const char* e) {
      return ext.size() == 4 && std::equal(ext.begin(), ext.end(), e, [](char a, char c) {
               return std::tolower(static_cast<unsigned char>(a)) == c;
             });
    };
    if (!is(".stl") && !is(".obj")) {
      fail(g.at, "mesh",
           why + ", but the file '" + path + "' of " + mesh +
               " is not binary STL or OBJ, the formats lever reads (MuJoCo 2.2.2 also reads MSH)" +
               advice);
    }
    const MeshSource& source = spec_.assets.mesh_sources[m];
    const Vec3& scale = source.scale;
    const bool righthand = scale[0] * scale[1] * scale[2] > 0;
    constexpr std::size_t kMaxBytes = std::size_t{64} << 20;
    std::string bytes;
    try {
      bytes = read_mesh_file(path, kMaxBytes);
    } catch (const MeshError& e) {
      fail(g.at, "mesh",
           why + ", but lever cannot read mesh file '" + path + "' of " + mesh + ": " + e.what() +
               advice);
    }
    try {
      TriangleMesh triangles = is(".stl") ? read_stl(bytes, righthand) : read_obj(bytes, righthand);
      mesh_cache_[m] = process_mesh(std::move(triangles), source.refpos, source.refquat, scale,
                                    source.density, c_.exactmeshinertia, needs_hull(m));
    } catch (const MeshError& e) {
      fail(g.at, "mesh",
           why + ", but mesh file '" + path + "' of " + mesh + " cannot be used: " + e.what() +
               advice);
    }
    return *mesh_cache_[m];
  }

  // bounds and the triangle inequality, for every body but the world
  void check_inertia(const BodySpec& b, CompiledBody& out) {
    BodyInertia& in = out.inertial;
    in.mass = std::max(in.mass, c_.boundmass);
    for (double& moment : in.inertia) moment = std::max(moment, c_.boundinertia);
    const Place& at = out.explicit_inertial ? b.inertial->at : b.at;
    if (in.mass < 0 || in.inertia[0] < 0 || in.inertia[1] < 0 || in.inertia[2] < 0) {
      fail(at, "",
           "mass and inertia must not be negative (mass " + show(in.mass) + ", principal moments " +
               show3(in.inertia) + ")");
    }
    const Vec3& i = in.inertia;
    if (i[0] + i[1] < i[2] || i[0] + i[2] < i[1] || i[1] + i[2] < i[0]) {
      if (c_.balanceinertia) {
        const double mean = (i[0] + i[1] + i[2]) / 3.0;
        in.inertia = {mean, mean, mean};
        return;
      }
      const std::string attribute =
          !out.explicit_inertial
              ? ""
              : (b.inertial->orientation.fullinertia ? "fullinertia" : "diaginertia");
      fail(at, attribute,
           "principal moments " + show3(i) +
               (out.explicit_inertial ? "" : " (inferred from its geoms)") +
               " violate the triangle inequality "
               "A + B >= C; fix them or set <compiler balanceinertia=\"true\">");
    }
  }

  // ---- geoms, joints, sites ---------------------------------------------------------------------

  // a mesh geom: its asset must exist (its file is read only if it gives its body mass)
  void check_mesh(const GeomSpec& g) const {
    if (g.shellinertia && g.type != GeomType::kMesh) {
      fail(g.at, "shellinertia",
           std::string("shellinertia applies to mesh geoms only (MuJoCo 2.2.2 refuses it for a ") +
               type_name(g.type) + " that gives mass): remove it");
    }
    if (g.type != GeomType::kMesh && !g.mesh.empty()) {
      fail(g.at, "mesh",
           std::string("a ") + type_name(g.type) + " geom with mesh=\"" + g.mesh +
               "\" is fitted to the mesh by MuJoCo, which needs the mesh file; lever reads no "
               "mesh file: give the geom its size, or make it type=\"mesh\"");
    }
    if (g.type != GeomType::kMesh) return;
    if (g.mesh.empty()) fail(g.at, "mesh", "a mesh geom needs mesh=\"NAME\" naming a <mesh> asset");
    if (g.fromto) fail(g.at, "fromto", "fromto cannot be used with a mesh geom");
    require_asset(g.at, "mesh", g.mesh, spec_.assets.meshes);
  }

  static void require_asset(const Place& at, const char* attribute, const std::string& name,
                            const std::vector<Place>& assets) {
    std::vector<std::string_view> names;
    for (const Place& a : assets) {
      if (a.name == name) return;
      names.push_back(a.name);
    }
    fail(at, attribute,
         std::string("unknown ") + attribute + " '" + name + "'" + did_you_mean(name, names));
  }

  CompiledGeom compile_geom(const GeomSpec& g, int body, bool gives_mass) {
    check_mesh(g);
    if (!g.material.empty()) require_asset(g.at, "material", g.material, spec_.assets.materials);
    check_condim(g.at, g.condim);
    if (g.type == GeomType::kPlane && weld_[static_cast<size_t>(body)] != 0) {
      const std::string& name = nodes_[static_cast<size_t>(body)].spec->at.name;
      fail(g.at, "type",
           "a plane is infinite, so it may only be in a body fixed to the world, and body '" +
               name + "' moves (it or a parent has a joint): use a box for a moving floor or wall");
    }
    CompiledGeom out{&g, body, g.size, g.pos, g.orientation.quat, 0, {}};
    normalize(out.quat.data(), 4);
    if (g.fromto) {
      apply_fromto(g, out);
    } else if (const char* reason =
                   apply_alternatives(g.orientation, c_.degree, c_.eulerseq, out.quat, nullptr)) {
      fail_orientation(g.at, reason);
    }
    if (g.type == GeomType::kPlane && !(out.size[2] > 0)) {
      fail(g.at, "size",
           std::string("a plane needs ") + size_meaning(g.type) + "; it has size \"" +
               show3(out.size) + "\"");
    }
    for (int k = 0; k < sizes_used(g.type); ++k) {
      if (!(out.size[static_cast<size_t>(k)] > 0)) {
        fail(g.at, "size",
             std::string("a ") + type_name(g.type) + " needs " + size_meaning(g.type) +
                 "; it has size \"" + show3(out.size) + "\"");
      }
    }
    if (g.type == GeomType::kMesh) {
      // a mesh geom that neither gives mass nor can collide keeps its frame as written, size zero
      // and no mass: lever reads its file only when the body, the collision stage or a
      // rangefinder's ray needs it
      out.size = {0, 0, 0};
      if (gives_mass) {
        apply_mesh(g, body, out, true);
      } else if (can_collide(g) || has_rangefinder()) {
        // MuJoCo reads mesh files lever does not (inline vertices, MSH): such a geom keeps its
        // frame as written and cannot collide in lever, which says so (the unsupported pairs'
        // warning names its pairs)
        try {
          apply_mesh(g, body, out, false);
        } catch (const Problem& p) {
          // once per mesh: the unsupported pairs' warnings name the other geoms
          if (unreadable_meshes_.insert(g.mesh).second) {
            warnings_.push_back("line " + line_text(p.where) + ": " + p.message);
          }
        }
      }
      require_finite(g.at, "geom", out.size, out.pos, out.quat, std::array<double, 1>{out.mass},
                     out.inertia);
      return out;
    }
    out.mass = geom_mass(g.type, out.size, g.density, g.mass);
    out.inertia = geom_inertia(g.type, out.size, out.mass);
    require_finite(g.at, "geom", out.size, out.pos, out.quat, std::array<double, 1>{out.mass},
                   out.inertia);
    return out;
  }

  // a segment geom: centre, length and orientation (+z points from `to` back to `from`)
  void apply_fromto(const GeomSpec& g, CompiledGeom& out) {
    if (g.type == GeomType::kSphere || g.type == GeomType::kPlane) {
      fail(g.at, "fromto",
           std::string("fromto needs a capsule, cylinder, ellipsoid or box, not a ") +
               type_name(g.type));
    }
    if (g.pos[0] != 0 || g.pos[1] != 0 || g.pos[2] != 0) {
      fail(g.at, "pos", "a geom with fromto takes its position from fromto; remove pos");
    }
    const Vec6& f = *g.fromto;
    Vec3 v{f[0] - f[3], f[1] - f[4], f[2] - f[5]};
    out.size[1] = normalize(v.data(), 3) / 2;
    if (out.size[1] < kCompilerEps) fail(g.at, "fromto", "the two points of fromto coincide");
    if (g.type == GeomType::kEllipsoid || g.type == GeomType::kBox) {
      out.size[2] = out.size[1];
      out.size[1] = out.size[0];
    }
    out.pos = {(f[0] + f[3]) / 2, (f[1] + f[4]) / 2, (f[2] + f[5]) / 2};
    out.quat = z_to_quat(v);
  }

  CompiledJoint compile_joint(const JointSpec& j, int body) {
    CompiledJoint out{&j, body, j.axis, j.range, false, j.ref, j.springref, j.pos};
    const bool hinge = j.type == JointType::kHinge;
    const bool rotates_freely = j.type == JointType::kBall || j.type == JointType::kFree;
    if (j.type == JointType::kFree) {
      // MuJoCo's rules: a free joint gives its body's pose outright
      const BodySpec& b = *nodes_[static_cast<size_t>(body)].spec;
      const char* attribute = j.at.tag == "freejoint" ? "" : "type";  // the element says it
      if (nodes_[static_cast<size_t>(body)].parent != 0) {
        fail(j.at, attribute, "a free joint can only move a body directly inside <worldbody>");
      }
      if (b.joints.size() != 1) fail(j.at, attribute, "a free joint must be its body's only joint");
      out.pos = {0, 0, 0};  // its anchor is the body's origin, whatever pos says
    } else {
      out.limited = resolve_limited(j.limited, j.range, c_.autolimits, j.at, "range", "limited");
    }
    if (out.limited && j.type == JointType::kBall) {
      fail(j.at, "limited",
           "lever does not limit ball joints yet (MuJoCo bounds the rotation angle); remove the "
           "range, or build the joint from hinges");
    }
    // a ball or free joint turns about the body's own axes: its axis is z by convention
    if (rotates_freely) out.axis = {0, 0, 1};
    if (out.limited) {
      if (j.range[0] >= j.range[1]) {
        fail(j.at, "range",
             "a limited joint needs range lower < upper; it has range \"" + show(j.range[0]) + " " +
                 show(j.range[1]) + "\"");
      }
      // only a limited hinge's range is in degrees, and a zero bound stays exactly zero
      for (double& bound : out.range) {
        if (c_.degree && hinge && bound != 0) bound = joint_radians(bound);
      }
    }
    if (normalize(out.axis.data(), 3) < kCompilerEps) {
      fail(j.at, "axis", "axis \"" + show3(j.axis) + "\" is too short to give a direction");
    }
    if (c_.degree && hinge) {
      out.ref = joint_radians(j.ref);
      out.springref = joint_radians(j.springref);
    }
    require_finite(j.at, "joint", out.axis, out.range,
                   std::array<double, 2>{out.ref, out.springref});
    return out;
  }

  CompiledSite compile_site(const SiteSpec& s, int body) {
    // a site applies its alternative before normalizing (mjCSite::Compile)
    CompiledSite out{&s, body, s.orientation.quat};
    if (const char* reason =
            apply_alternatives(s.orientation, c_.degree, c_.eulerseq, out.quat, nullptr)) {
      fail_orientation(s.at, reason);
    }
    normalize(out.quat.data(), 4);
    if (!(s.size[0] > 0)) {
      fail(s.at, "size",
           "a site needs a positive radius: size=\"r\"; it has size \"" + show3(s.size) + "\"");
    }
    return out;
  }

  // ---- motors ---------------------------------------------------------------------------------

  // The transmission (MuJoCo 2.2.2's xml reader, then mjCActuator::Compile): one of joint,
  // jointinparent, tendon, cranksite, site, body; the slider-crank's and the site's second site.
  void resolve_transmission(const MotorSpec& m, CompiledMotor& out) {
    struct Target {
      const char* attribute;
      const std::string* name;
      TransmissionType type;
    };
    const Target targets[] = {{"joint", &m.joint, TransmissionType::kJoint},
                              {"jointinparent", &m.jointinparent, TransmissionType::kJointInParent},
                              {"tendon", &m.tendon, TransmissionType::kTendon},
                              {"cranksite", &m.cranksite, TransmissionType::kSliderCrank},
                              {"site", &m.site, TransmissionType::kSite},
                              {"body", &m.body, TransmissionType::kBody}};
    const Target* chosen = nullptr;
    for (const Target& t : targets) {
      if (t.name->empty()) continue;
      if (chosen) {
        fail(m.at, t.attribute,
             std::string("an actuator has one transmission; this one names both ") +
                 chosen->attribute + " and " + t.attribute);
      }
      chosen = &t;
    }
    if (!chosen) {
      fail(m.at, "joint",
           "the actuator names no joint or tendon (nor jointinparent, site, cranksite, body): name "
           "what it drives");
    }
    const bool crank = chosen->type == TransmissionType::kSliderCrank;
    if (m.crank_attributes_written && !crank) {
      fail(m.at, "cranklength", "cranklength and slidersite belong to a slider-crank (cranksite)");
    }
    if (!m.refsite.empty() && chosen->type != TransmissionType::kSite) {
      fail(m.at, "refsite", "refsite belongs to a site transmission (site=)");
    }
    out.trntype = chosen->type;
    std::vector<std::string_view> site_names;
    for (const CompiledSite& s : sites_) site_names.push_back(s.spec->at.name);
    const auto site = [&](const std::string& name, const char* attribute) {
      return find_by_name(site_names, name, m.at, attribute, "site");
    };
    switch (chosen->type) {
      case TransmissionType::kJoint:
      case TransmissionType::kJointInParent: {
        std::vector<std::string_view> names;
        for (const CompiledJoint& j : joints_) names.push_back(j.spec->at.name);
        out.trnid[0] = find_by_name(names, *chosen->name, m.at, chosen->attribute, "joint");
        break;
      }
      case TransmissionType::kTendon: {
        std::vector<std::string_view> names;
        for (const TendonSpec& t : spec_.tendons) names.push_back(t.at.name);
        out.trnid[0] = find_by_name(names, m.tendon, m.at, "tendon", "tendon");
        break;
      }
      case TransmissionType::kSliderCrank:
        if (m.slidersite.empty()) {
          fail(m.at, "slidersite", "a slider-crank needs slidersite=\"NAME\", the site it slides along");
        }
        out.trnid[1] = site(m.slidersite, "slidersite");
        if (!(m.cranklength > 0)) {
          fail(m.at, "cranklength",
               "a slider-crank needs a positive cranklength (the rod's length); it has " +
                   show(m.cranklength));
        }
        out.trnid[0] = site(m.cranksite, "cranksite");
        break;
      case TransmissionType::kSite:
        if (!m.refsite.empty()) out.trnid[1] = site(m.refsite, "refsite");
        out.trnid[0] = site(m.site, "site");
        break;
      case TransmissionType::kBody: {
        std::vector<std::string_view> names{"world"};
        for (size_t b = 1; b < nodes_.size(); ++b) names.push_back(nodes_[b].spec->at.name);
        out.trnid[0] = find_by_name(names, m.body, m.at, "body", "body");
        break;
      }
    }
  }

  CompiledMotor compile_motor(const MotorSpec& m) {
    CompiledMotor out{&m};
    resolve_transmission(m, out);
    const bool on_joint = out.trntype == TransmissionType::kJoint ||
                          out.trntype == TransmissionType::kJointInParent;
    if (on_joint) {
      out.ctrlrange = inherited_ctrlrange(m, joints_[static_cast<size_t>(out.trnid[0])]);
    } else {
      if (m.inheritrange > 0) {
        fail(m.at, "inheritrange", "inheritrange takes a joint's range; this actuator drives no joint");
      }
      out.ctrlrange = m.ctrlrange;
    }
    out.forcelimited = resolve_limited(m.forcelimited, m.forcerange, c_.autolimits, m.at,
                                       "forcerange", "forcelimited");
    out.ctrllimited = resolve_limited(m.ctrllimited, out.ctrlrange, c_.autolimits, m.at,
                                      "ctrlrange", "ctrllimited");
    out.actlimited = resolve_limited(m.actlimited, m.actrange, c_.autolimits, m.at, "actrange",
                                     "actlimited");
    check_range(m.at, "forcerange", "forcelimited", out.forcelimited, m.forcerange);
    // an <intvelocity>'s, a <damper>'s and <adhesion>'s limits are implied, not written
    const bool implied = m.at.tag == "intvelocity" || m.at.tag == "damper" ||
                         m.at.tag == "adhesion";
    const std::string ctrl_flag =
        implied ? "<" + m.at.tag + "> (always ctrllimited)" : "ctrllimited";
    const std::string act_flag = implied ? "<" + m.at.tag + "> (always actlimited)" : "actlimited";
    check_range(m.at, "ctrlrange", ctrl_flag, out.ctrllimited, out.ctrlrange);
    check_range(m.at, "actrange", act_flag, out.actlimited, m.actrange);
    if (out.actlimited && m.dyntype == DynType::kNone) {
      fail(m.at, "actrange", "an activation range needs activation dynamics; dyntype is none");
    }
    check_muscle(m);
    return out;
  }

  // MuJoCo keeps the activations after the stateless actuators' controls (mjCModel's counts)
  void check_stateless_first() const {
    bool stateful = false;
    for (const MotorSpec& m : spec_.motors) {
      if (m.dyntype != DynType::kNone) {
        stateful = true;
      } else if (stateful) {
        fail(m.at, "dyntype",
             "stateless actuators must come before stateful ones (those with dyntype "
             "integrator, filter or muscle): move this one up");
      }
    }
  }

  // a muscle's parameters (mjCActuator::Compile), for its gain and its bias
  static void check_muscle(const MotorSpec& m) {
    for (const bool gain : {true, false}) {
      const bool muscle = gain ? m.gaintype == GainType::kMuscle : m.biastype == BiasType::kMuscle;
      if (!muscle) continue;
      const double* prm = gain ? m.gainprm.data() : m.biasprm.data();
      const char* attribute = gain ? "gainprm" : "biasprm";
      if (prm[0] >= prm[1]) {
        fail(m.at, attribute, "a muscle's range needs range[0] < range[1]");
      }
      if (prm[4] >= 1 || prm[5] <= 1) fail(m.at, attribute, "a muscle needs lmin < 1 < lmax");
      if (prm[3] <= 0 || prm[6] <= 0 || prm[7] <= 0 || prm[8] <= 0) {
        fail(m.at, attribute, "a muscle needs positive scale, vmax, fpmax and fvmax");
      }
    }
  }

  // MuJoCo 3's inheritrange (mjCActuator::Compile): a position servo (fixed gain, affine bias,
  // gainprm[0] = -biasprm[1]) with inheritrange > 0 takes as ctrlrange its joint's compiled range
  // (radians if limited) about its middle, scaled by inheritrange; other actuators ignore it
  static std::array<double, 2> inherited_ctrlrange(const MotorSpec& m, const CompiledJoint& j) {
    const bool servo = m.gaintype == GainType::kFixed && m.biastype == BiasType::kAffine &&
                       m.gainprm[0] == -m.biasprm[1];
    if (!(m.inheritrange > 0) || !servo) return m.ctrlrange;
    if (j.spec->type != JointType::kHinge && j.spec->type != JointType::kSlide) {
      fail(m.at, "inheritrange",
           "inheritrange needs a hinge or slide joint; joint '" + j.spec->at.name + "' is not one");
    }
    if (j.range[0] == j.range[1]) {
      fail(m.at, "inheritrange",
           "inheritrange takes the joint's range, and joint '" + j.spec->at.name + "' has none");
    }
    const double middle = 0.5 * (j.range[1] + j.range[0]);
    const double half = 0.5 * (j.range[1] - j.range[0]) * m.inheritrange;
    return {middle - half, middle + half};
  }

  static void check_range(const Place& at, const std::string& attribute, const std::string& flag,
                          bool limited, const std::array<double, 2>& range) {
    if (limited && range[0] >= range[1]) {
      fail(at, attribute,
           "with " + flag + " the " + attribute + " needs lower < upper; it is \"" +
               show(range[0]) + " " + show(range[1]) + "\"");
    }
  }

  // ---- whole-model checks -------------------------------------------------------------------

  static bool has_mass(const BodyInertia& in) {
    return in.mass >= 1e-15 && in.inertia[0] >= 1e-15 && in.inertia[1] >= 1e-15 &&
           in.inertia[2] >= 1e-15;
  }

  // a body that moves needs mass and inertia, unless a jointless child carries them (mujoco)
  void check_moving_bodies() const {
    for (size_t id = 1; id < nodes_.size(); ++id) {
      const BodySpec& b = *nodes_[id].spec;
      const CompiledBody& out = bodies_[id];
      if (b.joints.empty() || has_mass(out.inertial)) continue;
      bool carried = false;
      for (const int child : nodes_[id].children) {
        const size_t c = static_cast<size_t>(child);
        carried = carried || (nodes_[c].spec->joints.empty() && has_mass(bodies_[c].inertial));
      }
      if (carried) continue;
      const std::string state = "it has mass " + show(out.inertial.mass) +
                                " and principal "
                                "moments " +
                                show3(out.inertial.inertia);
      if (out.explicit_inertial) {
        const std::string attribute = out.inertial.mass < 1e-15 ? "mass" : "diaginertia";
        fail(b.inertial->at, attribute,
             "a body with joints needs positive mass and inertia; " + state);
      }
      fail(b.at, "",
           "a body with joints needs positive mass and inertia; " + state +
               (b.geoms.empty() ? " (give it an <inertial> or a geom)" : ""));
    }
  }

  // a keyframe's lists must have the model's sizes (mjCKey::Compile); missing ones are filled in
  // assemble_keys
  void check_key(const KeySpec& k) const {
    const auto check = [&](const std::optional<std::vector<double>>& v, const char* what, size_t n,
                           const char* size) {
      if (v && v->size() != n) {
        fail(k.at, what,
             std::string("keyframe ") + what + " has " + std::to_string(v->size()) + " number" +
                 (v->size() == 1 ? "" : "s") + " but the model has " + size + " = " +
                 std::to_string(n));
      }
    };
    check(k.qpos, "qpos", static_cast<size_t>(coordinates()), "nq");
    check(k.qvel, "qvel", static_cast<size_t>(dofs()), "nv");
    check(k.ctrl, "ctrl", motors_.size(), "nu");
    check(k.act, "act", static_cast<size_t>(activations()), "na");
    check(k.mpos, "mpos", 3 * static_cast<size_t>(nmocap_), "3 nmocap");
    check(k.mquat, "mquat", 4 * static_cast<size_t>(nmocap_), "4 nmocap");
  }

  // the model's na: one activation per actuator with dynamics
  int activations() const {
    int n = 0;
    for (const MotorSpec& m : spec_.motors) n += m.dyntype != DynType::kNone;
    return n;
  }

  // the model's nq and nv: a ball has a quaternion and three dofs, a free joint a position too
  int coordinates() const {
    int n = 0;
    for (const CompiledJoint& j : joints_) n += joint_nq(j.spec->type);
    return n;
  }
  int dofs() const {
    int n = 0;
    for (const CompiledJoint& j : joints_) n += joint_nv(j.spec->type);
    return n;
  }

  // ---- contact -------------------------------------------------------------------------------

  static void check_condim(const Place& at, int condim) {
    if (condim != 1 && condim != 3 && condim != 4 && condim != 6) {
      fail(at, "condim",
           "condim must be 1 (normal force only), 3 (and sliding friction), 4 (and torsional) or "
           "6 (and rolling); MuJoCo has no condim " +
               std::to_string(condim));
    }
  }

  // the geom or body called `name`, or a ParseError at `at` naming the attribute
  template <class Names>
  static int find_by_name(const Names& names, const std::string& name, const Place& at,
                          const char* attribute, const char* kind) {
    if (name.empty()) {
      fail(at, attribute, std::string("attribute '") + attribute + "' is empty: name a " + kind);
    }
    std::vector<std::string_view> candidates;
    for (size_t i = 0; i < names.size(); ++i) {
      if (names[i] == name) return static_cast<int>(i);
      candidates.push_back(names[i]);
    }
    fail(at, attribute,
         std::string("unknown ") + kind + " '" + name + "'" + did_you_mean(name, candidates));
  }

  // <contact> (mjCPair::Compile, mjCBodyPair::Compile): the geoms or bodies by name, ordered by
  // body id, and the body-pair signature; then both lists sorted by signature as MuJoCo sorts
  // them (std::sort on the signature alone, so pairs of one body pair keep the order libstdc++'s
  // sort gives them, which is MuJoCo's)
  void compile_contact() {
    std::vector<std::string> geom_names, body_names;
    for (const CompiledGeom& g : geoms_) geom_names.push_back(g.spec->at.name);
    for (size_t b = 0; b < nodes_.size(); ++b) {
      body_names.push_back(b == 0 ? std::string("world") : nodes_[b].spec->at.name);
    }
    for (const PairSpec& p : spec_.pairs) {
      check_condim(p.at, p.condim);
      CompiledPair out{&p};
      out.geom1 = find_by_name(geom_names, p.geom1, p.geom1_at, "geom1", "geom");
      out.geom2 = find_by_name(geom_names, p.geom2, p.geom2_at, "geom2", "geom");
      const int body1 = geoms_[static_cast<size_t>(out.geom1)].body;
      const int body2 = geoms_[static_cast<size_t>(out.geom2)].body;
      if (body1 > body2) std::swap(out.geom1, out.geom2);
      out.signature = body_pair_signature(body1, body2);
      pairs_.push_back(out);
    }
    for (const ExcludeSpec& x : spec_.excludes) {
      const int body1 = find_by_name(body_names, x.body1, x.body1_at, "body1", "body");
      const int body2 = find_by_name(body_names, x.body2, x.body2_at, "body2", "body");
      excludes_.push_back({body_pair_signature(body1, body2)});
    }
    std::sort(pairs_.begin(), pairs_.end(), [](const CompiledPair& a, const CompiledPair& b) {
      return a.signature < b.signature;
    });
    std::sort(excludes_.begin(), excludes_.end(),
              [](const CompiledExclude& a, const CompiledExclude& b) {
                return a.signature < b.signature;
              });
  }

  // what to do about a pair lever cannot compute, from the geom type that makes it so
  static std::string advice_for(GeomType a, GeomType b) {
    const auto has = [&](GeomType t) { return a == t || b == t; };
    std::string use;
    if (has(GeomType::kMesh)) {
      use =
          "give the mesh a binary STL or OBJ file, or give its body primitive collision geoms "
          "and make the mesh visual only (contype=\"0\" conaffinity=\"0\")";
    } else {
      use = "model the ground with a plane or boxes instead of the height field";
    }
    return use +
           ", or keep the two from colliding (contype/conaffinity, or <exclude> their bodies)";
  }

  // Geom pairs that can collide but that lever cannot compute: MuJoCo's candidates (mj_collision
  // with filterparent on: compatible contype/conaffinity bits, bodies not welded together, neither
  // welded to the other's parent, not excluded; and every <pair>) of types lever has no function
  // for. lever's collision stage skips them and warns when they come near each other; the
  // compiler names them now, with what to use instead.
  void warn_unsupported_pairs() {
    const auto weld_parent = [&](int w) {
      return w == 0 ? 0 : weld_[static_cast<size_t>(nodes_[static_cast<size_t>(w)].parent)];
    };
    const auto excluded = [&](int b1, int b2) {
      const int signature = body_pair_signature(b1, b2);  // excludes_ is sorted by it
      const auto at =
          std::lower_bound(excludes_.begin(), excludes_.end(), signature,
                           [](const CompiledExclude& x, int value) { return x.signature < value; });
      return at != excludes_.end() && at->signature == signature;
    };
    // a pair MuJoCo tests without being told (mj_collision's dynamic pairs)
    const auto dynamic_candidate = [&](int a, int b) {
      const CompiledGeom& ga = geoms_[static_cast<size_t>(a)];
      const CompiledGeom& gb = geoms_[static_cast<size_t>(b)];
      if (!(ga.spec->contype & gb.spec->conaffinity) &&
          !(gb.spec->contype & ga.spec->conaffinity)) {
        return false;
      }
      const int wa = weld_[static_cast<size_t>(ga.body)];
      const int wb = weld_[static_cast<size_t>(gb.body)];
      if (wa == wb) return false;
      if (!spec_.opt.disabled(kDisableFilterparent) && wa != 0 && wb != 0 &&
          (wa == weld_parent(wb) || wb == weld_parent(wa))) {
        return false;
      }
      return !excluded(ga.body, gb.body);
    };
    // a mesh geom whose mesh lever did not read has no shape to collide
    const auto unread_mesh = [&](int g) {
      const GeomSpec& spec = *geoms_[static_cast<size_t>(g)].spec;
      if (spec.type != GeomType::kMesh) return false;
      const size_t m = mesh_index(spec);
      return m >= mesh_cache_.size() || !mesh_cache_[m];
    };
    const auto unsupported_types = [&](int a, int b) {
      const GeomType ta = geoms_[static_cast<size_t>(a)].spec->type;
      const GeomType tb = geoms_[static_cast<size_t>(b)].spec->type;
      if (ta == GeomType::kPlane && tb == GeomType::kPlane) return false;
      return !has_collision_function(ta, tb) || unread_mesh(a) || unread_mesh(b);
    };
    // the first pairs are named, the rest only counted (a model of 10000 mesh geoms has 5e7)
    constexpr size_t kListed = 10;
    std::vector<std::pair<int, int>> unsupported;
    size_t count = 0;
    const auto note = [&](int a, int b) {
      if (++count <= kListed) unsupported.push_back({std::min(a, b), std::max(a, b)});
    };
    for (int a = 0; a < static_cast<int>(geoms_.size()); ++a) {
      for (int b = a + 1; b < static_cast<int>(geoms_.size()); ++b) {
        if (unsupported_types(a, b) && dynamic_candidate(a, b)) note(a, b);
      }
    }
    // explicit pairs not already counted as dynamic ones, each once
    std::set<std::pair<int, int>> explicit_pairs;
    for (const CompiledPair& p : pairs_) {
      const std::pair<int, int> key{std::min(p.geom1, p.geom2), std::max(p.geom1, p.geom2)};
      if (!unsupported_types(key.first, key.second) || !explicit_pairs.insert(key).second) continue;
      if (key.first == key.second || !dynamic_candidate(key.first, key.second)) {
        note(key.first, key.second);
      }
    }

    const auto label = [&](int g) {
      const std::string& name = geoms_[static_cast<size_t>(g)].spec->at.name;
      return name.empty() ? "#" + std::to_string(g) : "'" + name + "'";
    };
    for (size_t k = 0; k < unsupported.size(); ++k) {
      const auto [a, b] = unsupported[k];
      const GeomSpec& ga = *geoms_[static_cast<size_t>(a)].spec;
      const GeomSpec& gb = *geoms_[static_cast<size_t>(b)].spec;
      const std::string ta = type_name(ga.type), tb = type_name(gb.type);
      const std::string why = has_collision_function(ga.type, gb.type)
                                  ? "lever did not read the mesh (see its warning)"
                                  : "lever has no " + ta + "-" + tb + " contact";
      warnings_.push_back("geoms " + label(a) + " and " + label(b) + " (" + ta + ", " + tb +
                          "; lines " + line_text(ga.at) + " and " + line_text(gb.at) +
                          ") can collide and " + why +
                          ": it skips them, and warns whenever they come near each other; " +
                          advice_for(ga.type, gb.type));
    }
    if (count > kListed) {
      warnings_.push_back("and " + std::to_string(count - kListed) +
                          " more geom pairs that can collide and that lever cannot compute "
                          "(height fields, and meshes lever did not read)");
    }
  }

  // compiler/settotalmass scales every body, static ones included (mj_setTotalmass)
  void scale_total_mass() {
    if (!(c_.settotalmass > 0)) return;
    double total = 0;
    for (size_t id = 1; id < bodies_.size(); ++id) total += bodies_[id].inertial.mass;
    const double scale = std::max(1e-15, c_.settotalmass / std::max(1e-15, total));
    for (size_t id = 1; id < bodies_.size(); ++id) {
      BodyInertia& in = bodies_[id].inertial;
      in.mass *= scale;
      for (double& moment : in.inertia) moment *= scale;
      require_finite(nodes_[id].spec->at, "body", std::array<double, 1>{in.mass}, in.inertia);
    }
  }

  // ---- the Model --------------------------------------------------------------------------------

  Model assemble() const;
  // each kind's `user` lists in the model's order of its objects
  struct UserLists {
    std::vector<const UserData*> body, joint, geom, site, tendon, actuator, sensor;
  };
  UserLists user_lists() const {
    UserLists u;
    for (const BodyNode& n : nodes_) u.body.push_back(&n.spec->user);
    for (const CompiledJoint& j : joints_) u.joint.push_back(&j.spec->user);
    for (const CompiledGeom& g : geoms_) u.geom.push_back(&g.spec->user);
    for (const CompiledSite& s : sites_) u.site.push_back(&s.spec->user);
    for (const TendonSpec& t : spec_.tendons) u.tendon.push_back(&t.user);
    for (const CompiledMotor& a : motors_) u.actuator.push_back(&a.spec->user);
    for (const SensorSpec& s : spec_.sensors) u.sensor.push_back(&s.user);
    return u;
  }

  void assemble_bodies(Model& m) const;
  void assemble_joints(Model& m) const;
  void assemble_geoms_and_sites(Model& m) const;
  void assemble_contact(Model& m) const;
  void assemble_motors(Model& m) const;
  void assemble_keys(Model& m) const;
  void assemble_visual(Model& m) const;
  void assemble_meshes(Model& m) const;

  const ModelSpec& spec_;
  const CompilerSpec& c_;
  std::vector<BodyNode> nodes_;
  int nmocap_ = 0;  // the mocap bodies, numbered in body order
  std::vector<CompiledBody> bodies_;
  std::vector<CompiledGeom> geoms_;
  std::vector<CompiledJoint> joints_;
  std::vector<CompiledSite> sites_;
  std::vector<CompiledMotor> motors_;
  std::vector<bool> tendon_limited_;  ///< each tendon's limited, resolved
  std::vector<int> weld_;            ///< per body: the body it moves with (0: fixed to the world)
  std::vector<CompiledPair> pairs_;  ///< sorted by signature
  std::vector<CompiledExclude> excludes_;  ///< sorted by signature
  std::vector<std::string> warnings_;
  std::vector<std::optional<MeshMass>> mesh_cache_;  ///< per mesh, once read
  std::set<std::string> unreadable_meshes_;  ///< meshes read to collide only, and failed (warned)
};

Eigen::Vector3d eigen(const Vec3& v) { return {v[0], v[1], v[2]}; }
Eigen::Vector4d eigen(const Quat& q) { return {q[0], q[1], q[2], q[3]}; }

Model Compiler::assemble() const {
  Model m;
  m.name = spec_.name;
  m.opt = spec_.opt;
  m.compiler.inertiagrouprange = c_.inertiagrouprange;
  m.compiler.inertia_from_geoms_allowed = c_.inertiafromgeom != InertiaFromGeom::kFalse;
  // the counts first; size_model gives every array its length from them (the field table), and
  // the assemble_* functions write each row by index
  m.nbody = static_cast<int>(nodes_.size());
  m.njnt = static_cast<int>(joints_.size());
  m.nq = coordinates();
  m.nv = dofs();
  m.ngeom = static_cast<int>(geoms_.size());
  m.nsite = static_cast<int>(sites_.size());
  m.nu = static_cast<int>(motors_.size());
  m.na = activations();
  m.npair = static_cast<int>(pairs_.size());
  m.nexclude = static_cast<int>(excludes_.size());
  m.nkey = static_cast<int>(spec_.keys.size());
  m.nmesh = static_cast<int>(spec_.assets.meshes.size());
  for (const std::optional<MeshMass>& mesh : mesh_cache_) {
    if (!mesh) continue;
    m.nmeshvert += static_cast<int>(mesh->vert.size() / 3);
    m.nmeshgraph += static_cast<int>(mesh->graph.size());
    m.nmeshface += static_cast<int>(mesh->face.size() / 3);
  }
  m.neq = static_cast<int>(spec_.equalities.size());
  m.ntendon = static_cast<int>(spec_.tendons.size());
  m.nwrap = wrap_count(spec_.tendons);
  m.nmocap = nmocap_;
  const UserLists users = user_lists();
  m.nuser_body = user_width(UserKind::kBody, spec_.nuser, users.body);
  m.nuser_jnt = user_width(UserKind::kJoint, spec_.nuser, users.joint);
  m.nuser_geom = user_width(UserKind::kGeom, spec_.nuser, users.geom);
  m.nuser_site = user_width(UserKind::kSite, spec_.nuser, users.site);
  m.nuser_tendon = user_width(UserKind::kTendon, spec_.nuser, users.tendon);
  m.nuser_actuator = user_width(UserKind::kActuator, spec_.nuser, users.actuator);
  m.nuser_sensor = user_width(UserKind::kSensor, spec_.nuser, users.sensor);
  size_model(m);
  fill_user_rows(users.body, m.nuser_body, m.body_user);
  fill_user_rows(users.joint, m.nuser_jnt, m.jnt_user);
  fill_user_rows(users.geom, m.nuser_geom, m.geom_user);
  fill_user_rows(users.site, m.nuser_site, m.site_user);
  fill_user_rows(users.tendon, m.nuser_tendon, m.tendon_user);
  fill_user_rows(users.actuator, m.nuser_actuator, m.actuator_user);
  assemble_meshes(m);
  assemble_bodies(m);
  assemble_joints(m);
  assemble_geoms_and_sites(m);
  assemble_contact(m);
  assemble_tendons(spec_.tendons, tendon_limited_, m);  // tendon.cpp: after the joints' names
  assemble_equalities(spec_.equalities, m);  // equality.cpp: after the bodies', joints', tendons'
  assemble_motors(m);
  assemble_keys(m);
  assemble_visual(m);
  compile_sensors(spec_.sensors, m);  // last: sensors name the other objects
  fill_user_rows(users.sensor, m.nuser_sensor, m.sensor_user);  // once nsensor is known
  m.warnings = warnings_;
  return m;
}

void Compiler::assemble_bodies(Model& m) const {
  // the world: its own parent and root, at the origin, without joints or mass
  m.body_name[0] = "world";
  m.body_line[0] = 0;
  m.body_parentid[0] = 0;
  m.body_rootid[0] = 0;
  m.body_jntnum[0] = 0;
  m.body_jntadr[0] = -1;
  m.body_pos[0] = Eigen::Vector3d::Zero();
  m.body_quat[0] = Eigen::Vector4d(1, 0, 0, 0);
  m.body_ipos[0] = Eigen::Vector3d::Zero();
  m.body_iquat[0] = Eigen::Vector4d(1, 0, 0, 0);
  m.body_mass[0] = 0.0;
  m.body_inertia[0] = Eigen::Vector3d::Zero();
  m.body_explicit_inertial[0] = false;
  m.body_mocapid[0] = -1;
  int next_mocap = 0;
  for (size_t id = 1; id < nodes_.size(); ++id) {
    const BodySpec& b = *nodes_[id].spec;
    const CompiledBody& c = bodies_[id];
    const int parent = nodes_[id].parent;
    m.body_name[id] = b.at.name;
    m.body_line[id] = b.at.line;
    m.body_parentid[id] = parent;
    m.body_rootid[id] =
        parent == 0 ? static_cast<int>(id) : m.body_rootid[static_cast<size_t>(parent)];
    m.body_jntnum[id] = static_cast<int>(b.joints.size());
    m.body_jntadr[id] = b.joints.empty() ? -1 : c.first_joint;  // its dofs: assemble_joints
    m.body_pos[id] = eigen(c.pos);
    m.body_quat[id] = eigen(c.quat);
    m.body_ipos[id] = eigen(c.inertial.ipos);
    m.body_iquat[id] = eigen(c.inertial.iquat);
    m.body_mass[id] = c.inertial.mass;
    m.body_inertia[id] = eigen(c.inertial.inertia);
    m.body_explicit_inertial[id] = c.explicit_inertial;
    m.body_mocapid[id] = b.mocap ? next_mocap++ : -1;
  }
  for (size_t id = 0; id < nodes_.size(); ++id) {
    m.body_geomnum[id] = static_cast<int>(nodes_[id].spec->geoms.size());
    m.body_geomadr[id] = m.body_geomnum[id] > 0 ? bodies_[id].first_geom : -1;
  }
}

void Compiler::assemble_joints(Model& m) const {
  int qadr = 0, dadr = 0;
  for (size_t j = 0; j < joints_.size(); ++j) {
    const CompiledJoint& c = joints_[j];
    const JointSpec& s = *c.spec;
    m.jnt_name[j] = s.at.name;
    m.jnt_type[j] = s.type;
    m.jnt_qposadr[j] = qadr;
    m.jnt_dofadr[j] = dadr;
    m.jnt_bodyid[j] = c.body;
    m.jnt_limited[j] = c.limited;
    m.jnt_solref[j] = s.solref;
    m.jnt_solimp[j] = s.solimp;
    m.jnt_pos[j] = eigen(c.pos);
    m.jnt_axis[j] = eigen(c.axis);
    m.jnt_stiffness[j] = s.stiffness;
    m.jnt_range[j] = c.range;
    m.jnt_margin[j] = s.margin;
    // qpos0 (and the spring's rest) is the body as written: a free joint's is the body's pose,
    // a ball's the identity, a hinge's or a slide's its ref (springref)
    switch (s.type) {
      case JointType::kFree: {
        const CompiledBody& body = bodies_[static_cast<size_t>(c.body)];
        for (int k = 0; k < 3; ++k) m.qpos0[qadr + k] = body.pos[static_cast<size_t>(k)];
        for (int k = 0; k < 4; ++k) m.qpos0[qadr + 3 + k] = body.quat[static_cast<size_t>(k)];
        m.qpos_spring.segment<7>(qadr) = m.qpos0.segment<7>(qadr);
        break;
      }
      case JointType::kBall:
        m.qpos0.segment<4>(qadr) = Eigen::Vector4d(1, 0, 0, 0);
        m.qpos_spring.segment<4>(qadr) = m.qpos0.segment<4>(qadr);
        break;
      default: m.qpos0[qadr] = c.ref; m.qpos_spring[qadr] = c.springref;
    }
    for (int k = 0; k < joint_nv(s.type); ++k) {
      const size_t dof = static_cast<size_t>(dadr + k);
      m.dof_bodyid[dof] = c.body;
      m.dof_jntid[dof] = static_cast<int>(j);
      m.dof_armature[dof] = s.armature;
      m.dof_damping[dof] = s.damping;
      m.dof_frictionloss[dof] = s.frictionloss;
      m.dof_solref[dof] = s.solref_friction;
      m.dof_solimp[dof] = s.solimp_friction;
    }
    qadr += joint_nq(s.type);
    dadr += joint_nv(s.type);
  }
  // each body's dofs, and each dof's parent: the previous dof of its body, else the last dof of
  // the nearest ancestor that has one (mujoco's body "lastdof", carried down in body order)
  std::vector<int> last_dof(nodes_.size(), -1);
  for (size_t body = 0; body < nodes_.size(); ++body) {
    if (body > 0) last_dof[body] = last_dof[static_cast<size_t>(nodes_[body].parent)];
    const size_t njoints = nodes_[body].spec->joints.size();
    m.body_dofnum[body] = 0;
    m.body_dofadr[body] = -1;
    if (njoints == 0) continue;
    const int first_joint = bodies_[body].first_joint;
    const int first = m.jnt_dofadr[static_cast<size_t>(first_joint)];
    int count = 0;
    for (size_t k = 0; k < njoints; ++k) {
      count += joint_nv(m.jnt_type[static_cast<size_t>(first_joint) + k]);
    }
    m.body_dofadr[body] = first;
    m.body_dofnum[body] = count;
    for (int dof = first; dof < first + count; ++dof) {
      m.dof_parentid[static_cast<size_t>(dof)] = last_dof[body];
      last_dof[body] = dof;
    }
  }
}

void Compiler::assemble_geoms_and_sites(Model& m) const {
  for (size_t g = 0; g < geoms_.size(); ++g) {
    const CompiledGeom& c = geoms_[g];
    const GeomSpec& s = *c.spec;
    m.geom_name[g] = s.at.name;
    m.geom_type[g] = s.type;
    m.geom_bodyid[g] = c.body;
    m.geom_contype[g] = s.contype;
    m.geom_conaffinity[g] = s.conaffinity;
    m.geom_group[g] = s.group;
    m.geom_size[g] = eigen(c.size);
    m.geom_pos[g] = eigen(c.pos);
    m.geom_quat[g] = eigen(c.quat);
    m.geom_rgba[g] = Eigen::Vector4d(s.rgba[0], s.rgba[1], s.rgba[2], s.rgba[3]);
    m.geom_mass[g] = c.mass;
  }
  for (size_t i = 0; i < sites_.size(); ++i) {
    const CompiledSite& c = sites_[i];
    m.site_name[i] = c.spec->at.name;
    m.site_bodyid[i] = c.body;
    m.site_pos[i] = eigen(c.spec->pos);
    m.site_quat[i] = eigen(c.quat);
    m.site_size[i] = eigen(c.spec->size);
    m.site_type[i] = c.spec->type;
  }
}

// every mesh asset, as MuJoCo numbers them; one lever did not read has no vertices and no graph
void Compiler::assemble_meshes(Model& m) const {
  int vert = 0, graph = 0, face = 0;
  for (size_t k = 0; k < spec_.assets.meshes.size(); ++k) {
    const MeshMass* mesh = k < mesh_cache_.size() && mesh_cache_[k] ? &*mesh_cache_[k] : nullptr;
    m.mesh_vertadr[k] = vert;
    m.mesh_vertnum[k] = mesh ? static_cast<int>(mesh->vert.size() / 3) : 0;
    m.mesh_graphadr[k] = mesh && !mesh->graph.empty() ? graph : -1;
    m.mesh_faceadr[k] = face;
    m.mesh_facenum[k] = mesh ? static_cast<int>(mesh->face.size() / 3) : 0;
    if (!mesh) continue;
    for (int f = 0; f < m.mesh_facenum[k]; ++f) {
      const int* corners = mesh->face.data() + 3 * f;
      m.mesh_face[static_cast<size_t>(face + f)] = {corners[0], corners[1], corners[2]};
    }
    face += m.mesh_facenum[k];
    for (int v = 0; v < m.mesh_vertnum[k]; ++v) {
      const float* p = mesh->vert.data() + 3 * v;
      m.mesh_vert[static_cast<size_t>(vert + v)] = Eigen::Vector3d(p[0], p[1], p[2]);
    }
    std::copy(mesh->graph.begin(), mesh->graph.end(), m.mesh_graph.begin() + graph);
    vert += m.mesh_vertnum[k];
    graph += static_cast<int>(mesh->graph.size());
  }
  for (size_t g = 0; g < geoms_.size(); ++g) {
    const GeomSpec& s = *geoms_[g].spec;
    m.geom_dataid[g] = s.type == GeomType::kMesh ? static_cast<int>(mesh_index(s)) : -1;
  }
}

void Compiler::assemble_contact(Model& m) const {
  for (size_t g = 0; g < geoms_.size(); ++g) {
    const GeomSpec& s = *geoms_[g].spec;
    m.geom_condim[g] = s.condim;
    m.geom_priority[g] = s.priority;
    m.geom_solmix[g] = s.solmix;
    m.geom_friction[g] = eigen(s.friction);
    m.geom_solref[g] = s.solref;
    m.geom_solimp[g] = s.solimp;
    m.geom_margin[g] = s.margin;
    m.geom_gap[g] = s.gap;
    m.geom_rbound[g] = bounding_radius(s.type, geoms_[g].size);
  }
  for (size_t p = 0; p < pairs_.size(); ++p) {
    const CompiledPair& c = pairs_[p];
    const PairSpec& s = *c.spec;
    m.pair_dim[p] = s.condim;
    m.pair_geom1[p] = c.geom1;
    m.pair_geom2[p] = c.geom2;
    m.pair_signature[p] = c.signature;
    m.pair_solref[p] = s.solref;
    m.pair_solimp[p] = s.solimp;
    m.pair_margin[p] = s.margin;
    m.pair_gap[p] = s.gap;
    m.pair_friction[p] = s.friction;
  }
  for (size_t x = 0; x < excludes_.size(); ++x) m.exclude_signature[x] = excludes_[x].signature;
  // a negative <size> count means MuJoCo's default (mjCModel::SetSizes)
  m.nconmax = spec_.nconmax < 0 ? 100 : spec_.nconmax;
  m.njmax = spec_.njmax < 0 ? 500 : spec_.njmax;
}

void Compiler::assemble_motors(Model& m) const {
  for (size_t a = 0; a < motors_.size(); ++a) {
    const CompiledMotor& c = motors_[a];
    const MotorSpec& s = *c.spec;
    m.actuator_name[a] = s.at.name;
    m.actuator_trntype[a] = c.trntype;
    m.actuator_trnid[a] = c.trnid;
    m.actuator_cranklength[a] = s.cranklength;
    m.actuator_dyntype[a] = s.dyntype;
    m.actuator_dynprm[a] = s.dynprm;
    m.actuator_actlimited[a] = c.actlimited;
    m.actuator_actrange[a] = s.actrange;
    m.actuator_lengthrange[a] = s.lengthrange;
    m.actuator_gaintype[a] = s.gaintype;
    m.actuator_biastype[a] = s.biastype;
    m.actuator_gainprm[a] = s.gainprm;
    m.actuator_biasprm[a] = s.biasprm;
    m.actuator_gear[a] = s.gear;
    m.actuator_ctrllimited[a] = c.ctrllimited;
    m.actuator_forcelimited[a] = c.forcelimited;
    m.actuator_ctrlrange[a] = c.ctrlrange;
    m.actuator_forcerange[a] = s.forcerange;
  }
}

void Compiler::assemble_keys(Model& m) const {
  for (int k = 0; k < m.nkey; ++k) {
    const KeySpec& key = spec_.keys[static_cast<size_t>(k)];
    m.key_name[static_cast<size_t>(k)] = key.at.name;
    m.key_time[static_cast<size_t>(k)] = key.time;
    m.key_qpos.row(k) = m.qpos0.transpose();  // an unwritten qpos is qpos0, as in mujoco
    for (int i = 0; key.qpos && i < m.nq; ++i)
      m.key_qpos(k, i) = (*key.qpos)[static_cast<size_t>(i)];
    for (int i = 0; key.qvel && i < m.nv; ++i)
      m.key_qvel(k, i) = (*key.qvel)[static_cast<size_t>(i)];
    for (int i = 0; key.ctrl && i < m.nu; ++i)
      m.key_ctrl(k, i) = (*key.ctrl)[static_cast<size_t>(i)];
    for (int i = 0; key.act && i < m.na; ++i) m.key_act(k, i) = (*key.act)[static_cast<size_t>(i)];
    // the mocap bodies: as written, else where the bodies are (mjCKey::Compile)
    for (int b = 0; b < m.nbody; ++b) {
      const int id = m.body_mocapid[static_cast<size_t>(b)];
      if (id < 0) continue;
      for (int c = 0; c < 3; ++c) m.key_mpos(k, 3 * id + c) = m.body_pos[static_cast<size_t>(b)][c];
      for (int c = 0; c < 4; ++c) {
        m.key_mquat(k, 4 * id + c) = m.body_quat[static_cast<size_t>(b)][c];
      }
    }
    for (int i = 0; key.mpos && i < 3 * m.nmocap; ++i)
      m.key_mpos(k, i) = (*key.mpos)[static_cast<size_t>(i)];
    for (int i = 0; key.mquat && i < 4 * m.nmocap; ++i)
      m.key_mquat(k, i) = (*key.mquat)[static_cast<size_t>(i)];
    // a keyframe's quaternions are normalized at load. MuJoCo 2.2.2 does qpos's twice (when it
    // copies the keys into the model, and again at the end of its compile), and the second pass
    // can move the last bit, so lever does both: reset_keyframe then gives MuJoCo's qpos. The
    // mocap quaternions (mquat) it normalizes once.
    const auto normalize = [](double* q) {  // mju_normalize4
      const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
      if (norm < 1e-15) {
        q[0] = 1;
        q[1] = q[2] = q[3] = 0;
        return;
      }
      const double inverse = 1 / norm;
      for (int c = 0; c < 4; ++c) q[c] *= inverse;
    };
    for (int pass = 0; pass < 2; ++pass) {
      for (int j = 0; j < m.njnt; ++j) {
        const JointType type = m.jnt_type[static_cast<size_t>(j)];
        if (type != JointType::kBall && type != JointType::kFree) continue;
        const int adr = m.jnt_qposadr[static_cast<size_t>(j)] + (type == JointType::kFree ? 3 : 0);
        normalize(&m.key_qpos(k, adr));  // a row-major row: the four numbers are contiguous
      }
    }
    for (int i = 0; i < m.nmocap; ++i) normalize(&m.key_mquat(k, 4 * i));
  }
}

void Compiler::assemble_visual(Model& m) const {
  VisualInfo& v = m.visual;
  v.meshdir = c_.meshdir;
  v.texturedir = c_.texturedir;
  for (const Place& p : spec_.assets.meshes) v.mesh_name.push_back(p.name);
  v.mesh_file = spec_.assets.mesh_files;
  for (const Place& p : spec_.assets.materials) v.material_name.push_back(p.name);
  for (const Place& p : spec_.assets.textures) v.texture_name.push_back(p.name);
  v.light_name = spec_.assets.lights;
  v.camera_name = spec_.assets.cameras;
  for (const CompiledGeom& g : geoms_) {
    v.geom_mesh.push_back(g.spec->mesh);
    v.geom_material.push_back(g.spec->material);
  }
}

}  // namespace

Model compile(const ModelSpec& spec, Locations* where) { return Compiler(spec).run(where); }

}  // namespace lever::mjcf::detail
