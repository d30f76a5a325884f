// The model as written, after defaults: one typed record per element, in document order, before
// any frame, inertia or limit is computed. parse.cpp fills it, compiler.cpp compiles it.
#pragma once

#include <array>
#include <lever/model.hpp>
#include <optional>
#include <string>
#include <vector>

#include "problem.hpp"
#include "sensors.hpp"
#include "user.hpp"

namespace lever::mjcf::detail {

using Vec3 = std::array<double, 3>;
using Quat = std::array<double, 4>;  // (w, x, y, z)
using Vec6 = std::array<double, 6>;

enum class Limited { kFalse, kTrue, kAuto };
enum class InertiaFromGeom { kFalse, kTrue, kAuto };

/// `quat` and the alternatives written or inherited; MuJoCo keeps them side by side and lets the
/// alternatives win (compiler.cpp applies its priority).
struct Orientation {
  Quat quat{1, 0, 0, 0};
  std::optional<std::array<double, 4>> axisangle;
  std::optional<Vec6> xyaxes;
  std::optional<Vec3> zaxis;
  std::optional<Vec3> euler;
  std::optional<Vec6> fullinertia;  // <inertial> only
};

struct JointSpec {
  Place at;
  JointType type = JointType::kHinge;
  Vec3 pos{}, axis{0, 0, 1};
  std::array<double, 2> range{};
  Limited limited = Limited::kAuto;
  double damping = 0, stiffness = 0, springref = 0, armature = 0, ref = 0, margin = 0;
  std::array<double, 2> solref{};
  std::array<double, 5> solimp{};
  double frictionloss = 0;
  std::array<double, 2> solref_friction{};
  std::array<double, 5> solimp_friction{};
  UserData user;
};

struct GeomSpec {
  Place at;
  GeomType type = GeomType::kSphere;
  Vec3 size{};
  std::optional<Vec6> fromto;
  Vec3 pos{};
  Orientation orientation;
  double density = 1000;
  std::optional<double> mass;
  bool shellinertia = false;  ///< a mesh's inertia as a shell (MuJoCo 2.2.2's typeinertia)
  int group = 0, contype = 1, conaffinity = 1, condim = 3;
  // contact parameters
  int priority = 0;
  double solmix = 1, margin = 0, gap = 0;
  Vec3 friction{};
  std::array<double, 2> solref{};
  std::array<double, 5> solimp{};
  std::array<double, 4> rgba{};
  std::string mesh, material;  ///< asset names, "" if none
  UserData user;
};

struct SiteSpec {
  Place at;
  GeomType type = GeomType::kSphere;
  Vec3 pos{};
  Orientation orientation;
  Vec3 size{};
  UserData user;
};

struct InertialSpec {
  Place at;
  Vec3 pos{};
  double mass = 0;
  Vec3 diaginertia{};
  Orientation orientation;
};

struct BodySpec {
  Place at;
  Vec3 pos{};
  Orientation orientation;
  bool mocap = false;  ///< placed by Data's mocap_pos/mocap_quat (a child of the world, no joints)
  UserData user;
  std::optional<InertialSpec> inertial;
  std::vector<JointSpec> joints;
  std::vector<GeomSpec> geoms;
  std::vector<SiteSpec> sites;
  std::vector<BodySpec> children;
};

/// Any actuator (<motor>, <position>, <velocity>, <general>), in <general>'s terms: the shortcut
/// elements only fill in the gain and bias types and parameters (parse.cpp).
struct MotorSpec {
  Place at;
  std::string joint;
  std::string tendon;  ///< a tendon transmission: the tendon's name (joint is then "")
  /// the other transmissions' names as written ("" if not): jointinparent, site (with refsite),
  /// a slider-crank's cranksite and slidersite
  std::string jointinparent, site, refsite, cranksite, slidersite;
  std::string body;  ///< a body transmission (adhesion): the body whose contacts it acts through
  double cranklength = 0;
  bool crank_attributes_written = false;  ///< cranklength or slidersite on the element itself
  DynType dyntype = DynType::kNone;
  GainType gaintype = GainType::kFixed;
  BiasType biastype = BiasType::kNone;
  std::array<double, kDynParameters> dynprm{1};
  std::array<double, 2> actrange{}, lengthrange{};
  Limited actlimited = Limited::kAuto;
  std::array<double, kGainParameters> gainprm{1};
  std::array<double, kBiasParameters> biasprm{};
  Vec6 gear{};
  std::array<double, 2> ctrlrange{}, forcerange{};
  Limited ctrllimited = Limited::kAuto, forcelimited = Limited::kAuto;
  /// MuJoCo 3's: if positive, a position servo's ctrlrange is its joint's range about the middle,
  /// scaled by it (0: ctrlrange as written)
  double inheritrange = 0;
  UserData user;
};

/// A <key>: what it writes, before the sizes are known (compiler.cpp checks them).
struct KeySpec {
  Place at;
  double time = 0;
  std::optional<std::vector<double>> qpos, qvel, ctrl, act, mpos, mquat;
};

/// A <contact><pair>: its parameters as written over its class (MuJoCo 2.2.2 takes none from
/// the two geoms).
struct PairSpec {
  Place at;
  std::string geom1, geom2;
  Place geom1_at, geom2_at;  ///< where the attributes are, for errors
  int condim = 3;
  std::array<double, 5> friction{};
  std::array<double, 2> solref{};
  std::array<double, 5> solimp{};
  double margin = 0, gap = 0;
};

/// An <equality> constraint (<connect>, <weld>, <joint>) over its class: the objects by name
/// (object 2 "" when not written) and MuJoCo's eq_data as written (equality.cpp).
struct EqualitySpec {
  Place at;
  EqualityType type = EqualityType::kConnect;
  std::string name1, name2;
  Place name1_at, name2_at;  ///< where the attributes are, for errors
  bool active = true;
  std::array<double, 2> solref{};
  std::array<double, 5> solimp{};
  std::array<double, kEqualityData> data{};
};

/// One object of a tendon's path: a <fixed>'s <joint joint coef>, a <spatial>'s <site site>,
/// <geom geom sidesite> or <pulley divisor>.
struct TendonPathSpec {
  Place at;  ///< its naming attribute (joint, site, geom; a pulley's divisor), for errors
  WrapType type = WrapType::kJoint;  ///< kJoint, kSite, kPulley, or kSphere for any geom
  std::string name;                  ///< the joint, site or geom ("" for a pulley)
  double prm = 0;                    ///< a joint's coef, a pulley's divisor
  std::string sidesite;              ///< a geom's side site ("" for none)
  Place sidesite_at;
};

/// A <tendon><fixed> or <spatial> over its class (tendon.cpp).
struct TendonSpec {
  Place at;
  bool spatial = false;
  std::vector<TendonPathSpec> path;
  Limited limited = Limited::kAuto;
  std::array<double, 2> range{};
  std::array<double, 2> solref_limit{}, solref_friction{};
  std::array<double, 5> solimp_limit{}, solimp_friction{};
  double margin = 0, stiffness = 0, damping = 0, frictionloss = 0, springlength = -1;
  double width = 0.003;
  UserData user;
};

/// A <contact><exclude>.
struct ExcludeSpec {
  Place at;
  std::string body1, body2;
  Place body1_at, body2_at;
};

/// What a <mesh> says about its shape: read only if one of its geoms must give a body mass.
struct MeshSource {
  Vec3 refpos{};
  Quat refquat{1, 0, 0, 0};
  Vec3 scale{1, 1, 1};
  double density = 1000;  ///< geom density of the mesh's default class (MuJoCo uses it)
};

/// The visual-only parts of a model (assets, lights, cameras): names, for reference checks.
struct AssetSpec {
  std::vector<Place> meshes, materials, textures;  ///< the asset's name in Place::name
  std::vector<std::string> mesh_files;             ///< per mesh; "" if inline
  std::vector<MeshSource> mesh_sources;            ///< per mesh
  std::vector<std::string> lights, cameras;
};

struct CompilerSpec {
  bool degree = true;
  bool autolimits = true;  // lever: true, as in MuJoCo 3 (2.2.2: false)
  InertiaFromGeom inertiafromgeom = InertiaFromGeom::kAuto;
  std::array<int, 2> inertiagrouprange{0, 5};
  std::string eulerseq = "xyz";
  double boundmass = 0, boundinertia = 0;
  bool balanceinertia = false;
  double settotalmass = -1;
  std::string meshdir, texturedir;
  bool exactmeshinertia = false;
  bool convexhull = true;  ///< hull graphs for the meshes that can collide (MuJoCo's default)
  LengthRangeOptions lengthrange;  ///< <compiler><lengthrange>
};

struct ModelSpec {
  std::string name;
  CompilerSpec compiler;
  Options opt;
  BodySpec world;  ///< the world body: its geoms, sites and child bodies
  std::vector<MotorSpec> motors;
  std::vector<KeySpec> keys;
  std::vector<PairSpec> pairs;
  std::vector<ExcludeSpec> excludes;
  std::vector<SensorSpec> sensors;
  std::vector<EqualitySpec> equalities;
  std::vector<TendonSpec> tendons;
  int nconmax = -1, njmax = -1;  ///< <size>; -1: MuJoCo's defaults
  UserSizes nuser;               ///< <size nuser_*>
  AssetSpec assets;
  std::string model_dir;  ///< folder of the model file, with a trailing '/', or "" (mesh files)
};

}  // namespace lever::mjcf::detail
