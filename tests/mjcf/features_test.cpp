// The parser's features, each checked against a value computed by hand in the test: angle units,
// orientation forms, default classes and childclass, limits, the joint and dof tree, options.
#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <lever/lever.hpp>
#include <lever/mjcf.hpp>
#include <numbers>

#include <lever/harness/models.hpp>

namespace {

// Model stores flags as bytes (so that each is an array view); the expected values as such.
std::vector<uint8_t> flags(std::initializer_list<bool> values) {
  return std::vector<uint8_t>(values.begin(), values.end());
}

using lever::Model;
using std::numbers::pi;

// a model with `compiler` and one movable body holding `inside`
Model body_with(const std::string& inside, const std::string& compiler = "") {
  return lever::mjcf::load_string("<mujoco>" + compiler + R"(
  <worldbody>
    <body name="b">
      <geom size="0.1"/>
      )" + inside + R"(
    </body>
  </worldbody>
</mujoco>)");
}

Eigen::Matrix3d rotation(const Eigen::Vector4d& q) {
  return Eigen::Quaterniond(q[0], q[1], q[2], q[3]).toRotationMatrix();
}

Eigen::Matrix3d about(const Eigen::Vector3d& axis, double degrees) {
  return Eigen::AngleAxisd(degrees * pi / 180, axis).toRotationMatrix();
}

const Eigen::Vector3d ex = Eigen::Vector3d::UnitX(), ey = Eigen::Vector3d::UnitY(),
                      ez = Eigen::Vector3d::UnitZ();

bool near(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b, double tolerance = 1e-15) {
  return (a - b).cwiseAbs().maxCoeff() <= tolerance;
}

}  // namespace

TEST_CASE("angles are in degrees by default, converted as MuJoCo converts them", "[mjcf]") {
  const Model m = body_with(R"(<joint name="h" range="-90 13" ref="30" springref="-60"/>
      <joint name="u" range="-90 90" limited="false" axis="1 0 0"/>
      <joint name="s" type="slide" range="-90 90" ref="2"/>)");
  // a limited hinge's range, ref and springref: x * (pi / 180), bit for bit
  CHECK(m.jnt_range[0][0] == -90 * (pi / 180));
  CHECK(m.jnt_range[0][1] == 13 * (pi / 180));
  CHECK(m.qpos0[0] == 30 * (pi / 180));
  CHECK(m.qpos_spring[0] == -60 * (pi / 180));
  // an unlimited hinge keeps its range as written; a slide is never converted
  CHECK(m.jnt_range[1] == std::array<double, 2>{-90, 90});
  CHECK(m.jnt_range[2] == std::array<double, 2>{-90, 90});
  CHECK(m.qpos0[2] == 2);

  const Model r =
      body_with(R"(<joint range="-1.2 2.4" ref="0.5"/>)", R"(<compiler angle="radian"/>)");
  CHECK(r.jnt_range[0] == std::array<double, 2>{-1.2, 2.4});
  CHECK(r.qpos0[0] == 0.5);
}

TEST_CASE("euler and axisangle angles use x / 180 * pi", "[mjcf]") {
  const Model m = body_with(R"(<body name="e" euler="0 0 30"><geom size="0.1"/></body>
      <body name="a" axisangle="0 0 2 77"><geom size="0.1"/></body>)");
  const double half = 30.0 / 180 * pi / 2;
  CHECK(m.body_quat[2] == Eigen::Vector4d(std::cos(half), 0, 0, std::sin(half)));
  const double half77 = 77.0 / 180 * pi / 2;
  CHECK(m.body_quat[3] == Eigen::Vector4d(std::cos(half77), 0, 0, std::sin(half77)));
}

TEST_CASE("every orientation form gives the rotation it describes", "[mjcf]") {
  const Model m = lever::mjcf::load_string(R"(<mujoco>
  <worldbody>
    <body name="quat" quat="0 1 0 0"><geom size="0.1"/></body>
    <body name="unnormalized" quat="2 0 0 2"><geom size="0.1"/></body>
    <body name="axisangle" axisangle="0 0 1 90"><geom size="0.1"/></body>
    <body name="xyaxes" xyaxes="0 1 0 -1 0.3 0"><geom size="0.1"/></body>
    <body name="zaxis" zaxis="2 0 0"><geom size="0.1"/></body>
    <body name="euler" euler="90 90 0"><geom size="0.1"/></body>
  </worldbody>
</mujoco>)");
  CHECK(near(rotation(m.body_quat[1]), about(ex, 180)));
  CHECK(near(rotation(m.body_quat[2]), about(ez, 90)));
  CHECK(near(rotation(m.body_quat[3]), about(ez, 90)));
  CHECK(near(rotation(m.body_quat[4]), about(ez, 90)));  // y is made orthogonal to x
  CHECK(near(rotation(m.body_quat[5]) * ez, ex));        // the minimal rotation taking z to x
  CHECK(near(rotation(m.body_quat[5]), about(ey, 90)));
  // default eulerseq "xyz": rotating axes, x first
  CHECK(near(rotation(m.body_quat[6]), about(ex, 90) * about(ey, 90)));
}

TEST_CASE("eulerseq: lower case rotates with the body, upper case about fixed axes", "[mjcf]") {
  const std::string body = R"(<body name="r" euler="30 45 60"><geom size="0.1"/></body>)";
  const Model intrinsic = body_with(body, R"(<compiler eulerseq="zyx"/>)");
  const Model extrinsic = body_with(body, R"(<compiler eulerseq="ZYX"/>)");
  CHECK(
      near(rotation(intrinsic.body_quat[2]), about(ez, 30) * about(ey, 45) * about(ex, 60), 1e-14));
  CHECK(
      near(rotation(extrinsic.body_quat[2]), about(ex, 60) * about(ey, 45) * about(ez, 30), 1e-14));
}

TEST_CASE("fromto places, sizes and turns a geom, +z points from `to` back to `from`", "[mjcf]") {
  const Model m = lever::mjcf::load_string(R"(<mujoco>
  <worldbody>
    <geom type="capsule" fromto="0 0 0 0.5 0 0" size="0.025"/>
    <geom type="box" fromto="0 0 1 0 2 1" size="0.1"/>
  </worldbody>
</mujoco>)");
  CHECK(m.geom_pos[0] == Eigen::Vector3d(0.25, 0, 0));
  CHECK(m.geom_size[0] == Eigen::Vector3d(0.025, 0.25, 0));
  CHECK(near(rotation(m.geom_quat[0]) * ez, -ex));
  // a box (or ellipsoid) gets the radius on both sides and the half-length along z
  CHECK(m.geom_pos[1] == Eigen::Vector3d(0, 1, 1));
  CHECK(m.geom_size[1] == Eigen::Vector3d(0.1, 0.1, 1));
  CHECK(near(rotation(m.geom_quat[1]) * ez, -ey));
}

TEST_CASE("sites: position, orientation forms, partial size", "[mjcf]") {
  const Model m = body_with(R"(<site name="tip" pos="0.4 0 0" size="0.02"/>
      <site name="turned" euler="0 0 90" size="0.01 0.2"/>)");
  REQUIRE(m.nsite == 2);
  CHECK(m.site(std::string("tip")) == 0);
  CHECK(m.site_bodyid[0] == 1);
  CHECK(m.site_pos[0] == Eigen::Vector3d(0.4, 0, 0));
  CHECK(m.site_size[0] == Eigen::Vector3d(0.02, 0.005, 0.005));
  CHECK(m.site_size[1] == Eigen::Vector3d(0.01, 0.2, 0.005));
  CHECK(m.site_quat[0] == Eigen::Vector4d(1, 0, 0, 0));
}

TEST_CASE("default classes: nesting, childclass, class, partial vectors", "[mjcf]") {
  const Model m = lever::mjcf::load_string(R"(<mujoco>
  <compiler angle="radian"/>
  <default>
    <joint damping="1" axis="0 1 0"/>
    <geom type="box" size="0.1 0.2 0.3"/>
    <motor gear="3 0 0 0 0 1" ctrlrange="-1 1"/>
    <default class="arm">
      <joint armature="0.5"/>
      <geom size="0.5" euler="0 0 1.5707963267948966"/>
      <default class="wrist">
        <joint damping="2"/>
        <motor gear="7"/>
      </default>
    </default>
  </default>
  <worldbody>
    <body name="a" childclass="arm">
      <joint name="a"/>
      <geom name="a" quat="0 1 0 0"/>
      <body name="b">
        <joint name="b" class="wrist"/>
        <geom name="b" class="main"/>
      </body>
    </body>
    <body name="c">
      <joint name="c" damping="3"/>
      <geom name="c"/>
    </body>
  </worldbody>
  <actuator>
    <motor joint="a"/>
    <motor joint="b" class="wrist"/>
    <motor joint="c" gear="5"/>
  </actuator>
</mujoco>)");
  // childclass reaches the body's own elements and everything below it
  CHECK(m.dof_armature == std::vector<double>{0.5, 0.5, 0});
  CHECK(m.dof_damping == std::vector<double>{1, 2, 3});
  CHECK(m.jnt_axis[2] == Eigen::Vector3d(0, 1, 0));
  // a partial size overwrites only the numbers written
  CHECK(m.geom_size[0] == Eigen::Vector3d(0.5, 0.2, 0.3));
  // an orientation inherited from the class wins over the element's own quat (MuJoCo 2.2.2)
  CHECK(near(rotation(m.geom_quat[0]), about(ez, 90)));
  // class="main" is the top-level class, whatever childclass is active
  CHECK(m.geom_size[1] == Eigen::Vector3d(0.1, 0.2, 0.3));
  CHECK(m.geom_quat[1] == Eigen::Vector4d(1, 0, 0, 0));
  // motors take their own class or the top-level one, never a body's childclass
  CHECK(m.actuator_gear[0] == std::array<double, 6>{3, 0, 0, 0, 0, 1});
  CHECK(m.actuator_gear[1] == std::array<double, 6>{7, 0, 0, 0, 0, 1});
  CHECK(m.actuator_gear[2] == std::array<double, 6>{5, 0, 0, 0, 0, 1});
  CHECK(m.actuator_ctrlrange[2] == std::array<double, 2>{-1, 1});
}

TEST_CASE("a nested class is a copy of its parent taken when it is read", "[mjcf]") {
  const Model m = lever::mjcf::load_string(R"(<mujoco>
  <default>
    <default class="early"/>
    <joint damping="1"/>
  </default>
  <default>
    <joint armature="2"/>
  </default>
  <worldbody>
    <body name="b"><joint class="early"/><joint/><geom size="0.1"/></body>
  </worldbody>
</mujoco>)");
  // the parent's own elements come first, whatever their position; a later top-level
  // <default> edits the top-level class again but does not reach the nested copy
  CHECK(m.dof_damping == std::vector<double>{1, 1});
  CHECK(m.dof_armature == std::vector<double>{0, 2});
}

TEST_CASE("limits: a range alone makes a joint or motor limited (autolimits)", "[mjcf]") {
  const Model m = lever::mjcf::load_string(R"(<mujoco>
  <compiler angle="radian"/>
  <worldbody>
    <body name="b">
      <joint name="ranged" range="-1 1"/>
      <joint name="zero" range="0 0" axis="1 0 0"/>
      <joint name="off" range="2 -2" limited="false" axis="0 1 0"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
  <actuator>
    <motor joint="ranged" ctrlrange="-5 5"/>
    <motor joint="zero" forcerange="-3 3" ctrllimited="false"/>
  </actuator>
</mujoco>)");
  CHECK(m.jnt_limited == flags({true, false, false}));
  CHECK(m.jnt_range[2] == std::array<double, 2>{2, -2});  // kept as written, unchecked
  CHECK(m.actuator_ctrllimited == flags({true, false}));
  CHECK(m.actuator_forcelimited == flags({false, true}));
  CHECK(m.actuator_trnid == std::vector<std::array<int, 2>>{{0, -1}, {1, -1}});
}

TEST_CASE("joint parameters, solref/solimp defaults and partial values", "[mjcf]") {
  const Model m = body_with(R"(<joint name="a" pos="0.1 0 0" axis="0 0 2" stiffness="10"
        armature="0.2" damping="0.3" margin="0.01" solreflimit="0.05"/>
      <joint name="b" type="slide" axis="3 4 0" solimplimit="0.8 0.9"/>)");
  CHECK(m.jnt_type ==
        std::vector<lever::JointType>{lever::JointType::kHinge, lever::JointType::kSlide});
  CHECK(m.jnt_pos[0] == Eigen::Vector3d(0.1, 0, 0));
  CHECK(m.jnt_axis[0] == Eigen::Vector3d(0, 0, 1));
  CHECK(m.jnt_axis[1] == Eigen::Vector3d(0.6, 0.8, 0));
  CHECK(m.jnt_stiffness[0] == 10);
  CHECK(m.dof_armature[0] == 0.2);
  CHECK(m.dof_damping[0] == 0.3);
  CHECK(m.jnt_margin[0] == 0.01);
  CHECK(m.jnt_solref[0] == std::array<double, 2>{0.05, 1});
  CHECK(m.jnt_solref[1] == std::array<double, 2>{0.02, 1});
  CHECK(m.jnt_solimp[0] == std::array<double, 5>{0.9, 0.95, 0.001, 0.5, 2});
  CHECK(m.jnt_solimp[1] == std::array<double, 5>{0.8, 0.9, 0.001, 0.5, 2});
}

TEST_CASE("bodies are numbered depth-first, joints and dofs follow the body tree", "[mjcf]") {
  const Model m = lever::mjcf::load_string(R"(<mujoco>
  <worldbody>
    <body name="a">
      <body name="a1"><joint name="a1"/><geom size="0.1"/></body>
      <joint name="a"/>
      <geom size="0.1"/>
      <body name="a2"><joint name="a2x"/><joint name="a2y" axis="0 1 0"/><geom size="0.1"/></body>
    </body>
    <body name="s"><geom size="0.1"/>
      <body name="s1"><joint name="s1"/><geom size="0.1"/></body>
    </body>
  </worldbody>
</mujoco>)");
  CHECK(m.body_name == std::vector<std::string>{"world", "a", "a1", "a2", "s", "s1"});
  CHECK(m.body_parentid == std::vector<int>{0, 0, 1, 1, 0, 4});
  CHECK(m.body_rootid == std::vector<int>{0, 1, 1, 1, 4, 4});
  // a joint written after a child body still comes before the child's joints
  CHECK(m.jnt_name == std::vector<std::string>{"a", "a1", "a2x", "a2y", "s1"});
  CHECK(m.jnt_bodyid == std::vector<int>{1, 2, 3, 3, 5});
  CHECK(m.dof_parentid == std::vector<int>{-1, 0, 0, 2, -1});
  CHECK(m.body_jntadr == std::vector<int>{-1, 0, 1, 2, -1, 4});
  CHECK(m.body_jntnum == std::vector<int>{0, 1, 1, 2, 0, 1});
  CHECK(m.body_dofadr == m.body_jntadr);
  CHECK(m.jnt_qposadr == std::vector<int>{0, 1, 2, 3, 4});
  CHECK(m.geom_bodyid == std::vector<int>{1, 2, 3, 4, 5});
  CHECK(m.body_geomadr == std::vector<int>{-1, 0, 1, 2, 3, 4});
  CHECK((m.nq == 5 && m.nv == 5 && m.njnt == 5 && m.nbody == 6 && m.ngeom == 5));
}

TEST_CASE("options, compiler settings, names and source lines", "[mjcf]") {
  const Model m = lever::mjcf::load_string(R"(<mujoco model="demo">
  <option timestep="0.001" gravity="0 0 -1.62" integrator="RK4"/>
  <compiler inertiagrouprange="1 3" inertiafromgeom="auto"/>
  <worldbody>
    <body name="b">
      <geom name="g" size="0.1" group="2" rgba="1 0 0 0.5" contype="0" conaffinity="2"/>
    </body>
  </worldbody>
</mujoco>)");
  CHECK(m.name == "demo");
  CHECK(m.source.empty());
  CHECK(m.opt.timestep == 0.001);
  CHECK(m.opt.gravity == Eigen::Vector3d(0, 0, -1.62));
  CHECK(m.opt.integrator == lever::Integrator::kRK4);
  CHECK(m.compiler.inertiagrouprange == std::array<int, 2>{1, 3});
  CHECK(m.compiler.inertia_from_geoms_allowed);
  CHECK(m.body_line == std::vector<int>{0, 5});
  CHECK(m.geom(std::string("g")) == 0);
  CHECK(m.geom_group[0] == 2);
  CHECK(m.geom_contype[0] == 0);
  CHECK(m.geom_conaffinity[0] == 2);
  CHECK(m.geom_rgba[0] == Eigen::Vector4d(1, 0, 0, 0.5));

  const Model defaults = lever::mjcf::load_string("<mujoco/>");
  CHECK(defaults.name == "MuJoCo Model");
  CHECK(defaults.opt.timestep == 0.002);
  CHECK(defaults.opt.gravity == Eigen::Vector3d(0, 0, -9.81));
  CHECK(defaults.opt.integrator == lever::Integrator::kEuler);
  CHECK(defaults.nbody == 1);
}

TEST_CASE("arm2 loads from its file with what the lesson says it contains", "[mjcf]") {
  const std::string path = lever::test::model_path("models/arm2.xml");
  const Model m = lever::mjcf::load_file(path);
  CHECK(m.source == path);
  CHECK(m.name == "arm2");
  CHECK(m.jnt_axis[0] == Eigen::Vector3d(0, -1, 0));
  CHECK(m.jnt_range[0] == std::array<double, 2>{-1.2, 2.4});
  CHECK(m.dof_damping == std::vector<double>{0.02, 0.02});
  CHECK(m.body_mass == std::vector<double>{0, 1.0, 0.8});
  CHECK(m.body_ipos[2] == Eigen::Vector3d(0.2, 0, 0));
  CHECK(m.body_explicit_inertial == flags({false, true, true}));
  CHECK(m.actuator_ctrlrange[1] == std::array<double, 2>{-15, 15});
  CHECK(m.actuator_ctrllimited == flags({true, true}));
  CHECK(m.site_name == std::vector<std::string>{"ee"});
  // the pedestal is vertical: +z turned by pi about x, so +z points from `to` to `from`
  CHECK(near(rotation(m.geom_quat[0]) * ez, -ez));
}

// ---- contact -------------------------------------------------------------------------

TEST_CASE("the load warns of exactly the colliding pairs lever cannot compute", "[mjcf][contact]") {
  // every pair of geom types MuJoCo 2.2.2 collides is lever's (height fields are refused): what
  // remains is a mesh lever cannot read, here one given by inline vertices
  const char* xml = R"(<mujoco>
  <asset><mesh name="blob" vertex="0 0 0 0.1 0 0 0 0.1 0 0 0 0.1"/></asset>
  <worldbody>
    <geom name="floor" type="plane" size="0 0 1"/>
    <body name="a"><joint/>
      <geom name="can" type="cylinder" size="0.05 0.1"/>
      <geom name="egg" type="ellipsoid" size="0.05 0.06 0.07"/>
    </body>
    <body name="b" pos="1 0 0"><joint/><inertial pos="0 0 0" mass="1" diaginertia="1 1 1"/>
      <geom name="rod" type="capsule" size="0.02 0.2"/>
      <geom name="ghost" type="mesh" mesh="blob" contype="0" conaffinity="0"/>
    </body>
    <body name="c" pos="2 0 0"><joint/><inertial pos="0 0 0" mass="1" diaginertia="1 1 1"/>
      <geom name="puck" type="mesh" mesh="blob"/>
    </body>
  </worldbody>
  <contact>
    <exclude body1="c" body2="a"/>
    <pair geom1="ghost" geom2="egg"/>
  </contact>
</mujoco>)";
  const lever::Model m = lever::mjcf::load_string(xml);
  // the mesh (read for puck, which can collide), then floor-puck, rod-puck (dynamic; a-c
  // excluded; can, egg and rod collide with each other and the floor in lever; the untouchable
  // ghost is not read), and ghost-egg named by its <pair>
  REQUIRE(m.warnings.size() == 4);
  CHECK_THAT(m.warnings[0], Catch::Contains("mesh geom 'puck' can collide") &&
                                Catch::Contains("gives its vertices inline"));
  CHECK_THAT(m.warnings[1],
             Catch::StartsWith("geoms 'floor' and 'puck' (plane, mesh; lines 4 and 14) can "
                               "collide and lever did not read the mesh") &&
                 Catch::Contains("give the mesh a binary STL or OBJ file"));
  CHECK_THAT(m.warnings[2], Catch::StartsWith("geoms 'rod' and 'puck' (capsule, mesh"));
  CHECK_THAT(m.warnings[3], Catch::StartsWith("geoms 'egg' and 'ghost' (ellipsoid, mesh"));
  // what the compiler wrote for the collision stage
  CHECK(m.geom_rbound[0] == 0.0);
  CHECK(m.geom_rbound[3] == Approx(0.2 + 0.02).epsilon(1e-15));
  CHECK(m.nmesh == 1);
  CHECK(m.mesh_vertnum[0] == 0);  // not read
  CHECK(m.geom_dataid[5] == 0);
  CHECK(m.geom_dataid[3] == -1);
  REQUIRE(m.nexclude == 1);
  CHECK(m.exclude_signature[0] == ((1 + 1) << 16) + 3 + 1);
  REQUIRE(m.npair == 1);
  CHECK(m.pair_geom1[0] == 2);  // the lower body's geom first
  CHECK(m.pair_geom2[0] == 4);
}

TEST_CASE("every pair of primitives collides in lever", "[mjcf][contact]") {
  const lever::Model m = lever::mjcf::load_string(R"(<mujoco>
  <worldbody>
    <geom type="plane" size="1 1 0.1"/>
    <body><joint/><geom type="box" size="0.1 0.1 0.1"/><geom type="ellipsoid" size="0.1 0.1 0.2"/></body>
    <body><joint/><geom type="sphere" size="0.1"/><geom type="cylinder" size="0.1 0.1"/></body>
  </worldbody>
</mujoco>)");
  CHECK(m.warnings.empty());
}

TEST_CASE("a camera's quat is kept as written, never refused as zero", "[mjcf]") {
  // visual only: lever keeps the camera's attributes as text, and a unit quaternion is not zero
  const Model model = lever::mjcf::load_string(R"(<mujoco>
  <default><camera quat="0 1 0 0"/></default>
  <worldbody>
    <camera name="world_view" quat="1 0 0 0"/>
    <body name="b">
      <joint/>
      <geom size="0.1"/>
      <camera name="wrist" pos="0 0 0.1" quat="0.7071068 0 0.7071068 0"/>
    </body>
  </worldbody>
</mujoco>)");
  CHECK(model.visual.camera_name == std::vector<std::string>{"world_view", "wrist"});
  // the geometry's quaternions are still checked
  CHECK_THROWS_WITH(body_with(R"(<site quat="0 0 0 0"/>)"),
                    Catch::Contains("quaternion '0 0 0 0' has (nearly) zero length"));
}

TEST_CASE("MuJoCo 3's position kv: biasprm[2] = -kv, the class's kv inherited", "[mjcf]") {
  const Model m = lever::mjcf::load_string(R"(<mujoco>
  <default>
    <position kp="10" kv="2"/>
    <default class="stiff">
      <position kp="100"/>
    </default>
    <default class="plain">
      <position kp="5" kv="0"/>
    </default>
  </default>
  <worldbody>
    <body name="b">
      <joint name="j"/>
      <geom size="0.1"/>
    </body>
  </worldbody>
  <actuator>
    <position joint="j" kp="50" kv="3"/>
    <position joint="j"/>
    <position joint="j" class="stiff"/>
    <general joint="j" class="stiff"/>
    <position joint="j" class="plain"/>
    <velocity joint="j" kv="7"/>
  </actuator>
</mujoco>)");
  REQUIRE(m.nu == 6);
  const auto bias = [&](int a) {
    const auto& b = m.actuator_biasprm[static_cast<size_t>(a)];
    return std::vector<double>{b[0], b[1], b[2], b[3]};
  };
  CHECK(m.actuator_gainprm[0][0] == 50.0);
  CHECK(bias(0) == std::vector<double>{0, -50, -3, 0});
  CHECK(bias(1) == std::vector<double>{0, -10, -2, 0});   // the main class's kp and kv
  CHECK(bias(2) == std::vector<double>{0, -100, -2, 0});  // kv inherited by the nested class
  CHECK(bias(3) == std::vector<double>{0, -100, -2, 0});  // a <general> takes the prototype
  CHECK(bias(4) == std::vector<double>{0, -5, 0, 0});     // kv="0": no damping
  CHECK(m.actuator_kind[0] == lever::ActuatorKind::kPositionServo);
  // a velocity servo's kv is its gain, untouched by the position's
  CHECK(m.actuator_gainprm[5][0] == 7.0);
  CHECK(bias(5) == std::vector<double>{0, 0, -7, 0});
}

TEST_CASE("MuJoCo 3's inheritrange: ctrlrange from the joint's compiled range", "[mjcf]") {
  const Model m = lever::mjcf::load_string(R"(<mujoco>
  <default>
    <default class="arm"><position kp="10" inheritrange="0.5"/></default>
  </default>
  <worldbody>
    <body name="b">
      <joint name="hinge" range="-30 90"/>
      <geom size="0.1"/>
      <body name="c">
        <joint name="slider" type="slide" range="0 0.1"/>
        <geom size="0.1"/>
      </body>
    </body>
  </worldbody>
  <actuator>
    <position joint="hinge" class="arm"/>
    <position joint="slider" inheritrange="1"/>
    <motor joint="hinge" class="arm"/>
  </actuator>
</mujoco>)");
  REQUIRE(m.nu == 3);
  // the hinge's range in radians (compiler angle="degree"), about its middle, halved
  const double lo = -30 * (pi / 180.0), hi = 90 * (pi / 180.0);
  const double middle = 0.5 * (hi + lo), half = 0.5 * (hi - lo) * 0.5;
  CHECK(m.actuator_ctrlrange[0][0] == middle - half);
  CHECK(m.actuator_ctrlrange[0][1] == middle + half);
  CHECK(m.actuator_ctrllimited[0]);
  CHECK(m.actuator_ctrlrange[1][0] == 0.0);
  CHECK(m.actuator_ctrlrange[1][1] == 0.1);
  // a motor ignores the inheritrange of its class (its bias is not a servo's)
  CHECK(m.actuator_ctrlrange[2][0] == 0.0);
  CHECK(m.actuator_ctrlrange[2][1] == 0.0);
  CHECK_FALSE(m.actuator_ctrllimited[2]);
  // on a ball joint, as MuJoCo 3
  CHECK_THROWS_WITH(lever::mjcf::load_string(R"(<mujoco><worldbody><body name="b">
    <joint name="ball" type="ball"/><geom size="0.1"/></body></worldbody>
    <actuator><position joint="ball" inheritrange="1"/></actuator></mujoco>)"),
                    Catch::Contains("inheritrange needs a hinge or slide joint"));
}
