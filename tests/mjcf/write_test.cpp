// lever::mjcf::write_string / write_file (lever/mjcf/write.hpp): a model file written again with
// changed inertials, armature, damping and gains. Read back, the changed fields are the model's
// exactly and every other field is the file's; every element keeps every attribute it had except
// the ones written; a model the file cannot say is refused and nothing is written.
#include <catch2/catch.hpp>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <lever/fields.hpp>
#include <lever/lever.hpp>
#include <lever/mjcf.hpp>
#include <lever/mjcf/write.hpp>
#include <lever/regressor.hpp>
#include <limits>
#include <set>
#include <sstream>

#include <lever/harness/models.hpp>

#include "reader.hpp"

namespace {

using lever::Model;
using lever::mjcf::detail::Element;

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

bool same_field(const lever::FieldView& a, const lever::FieldView& b) {
  if (a.rows != b.rows || a.cols != b.cols) return false;
  if (a.size() == 0) return true;  // an empty field's data may be null
  if (a.info->scalar != lever::Scalar::kDouble) {
    const std::size_t bytes = a.info->scalar == lever::Scalar::kInt ? sizeof(int) : 1;
    return std::memcmp(a.data, b.data, static_cast<std::size_t>(a.size()) * bytes) == 0;
  }
  return std::equal(a.doubles(), a.doubles() + a.size(), b.doubles());
}

// every field of `back` equals `model`'s, but where an element is and whether an inertia was
// written explicitly; principal axes that no quaternion normalizes to exactly are written as the
// nearest that does (write.hpp): within 4 epsilons, and the rest derived from them as set_const
// derives it
void check_fields(const Model& model, const Model& back) {
  Model expected = model;
  for (int b = 0; b < model.nbody; ++b) {
    INFO("body_iquat of body " << b);
    CHECK((back.body_iquat[b] - model.body_iquat[b]).cwiseAbs().maxCoeff() <=
          4 * std::numeric_limits<double>::epsilon());
  }
  expected.body_iquat = back.body_iquat;
  lever::set_const(expected);
  const auto e = lever::model_fields(expected), b = lever::model_fields(back);
  REQUIRE(e.size() == b.size());
  for (std::size_t i = 0; i < e.size(); ++i) {
    const std::string name = e[i].info->name;
    if (name == "body_line" || name == "body_explicit_inertial") continue;
    INFO(name);
    CHECK(same_field(e[i], b[i]));
  }
}

// The attributes write_string may change on an element of this tag.
const std::set<std::string>& writable(const std::string& tag) {
  static const std::set<std::string> none,
      inertial{"pos",       "quat",   "mass",  "diaginertia", "fullinertia",
               "axisangle", "xyaxes", "zaxis", "euler"},
      joint{"armature", "damping", "type"},
      actuator{"kp", "kv", "gainprm", "biasprm", "dyntype", "gaintype", "biastype"},
      // a shortcut rewritten as a <general>: its own attributes become the general's
      shortcut{"kp",   "kv",        "gain", "timeconst", "area",    "diameter",
               "bias", "dynprm",    "gainprm", "biasprm", "dyntype", "gaintype",
               "biastype", "ctrllimited", "actlimited"},
      compiler{"inertiafromgeom", "settotalmass"};
  if (tag == "inertial") return inertial;
  if (tag == "joint" || tag == "freejoint") return joint;
  if (tag == "motor" || tag == "position" || tag == "velocity" || tag == "general") {
    return actuator;
  }
  if (tag == "intvelocity" || tag == "damper" || tag == "cylinder" || tag == "adhesion") {
    return shortcut;
  }
  if (tag == "compiler") return compiler;
  return none;
}

// Every element of `before` is in `after` (in order; <inertial> elements `after` adds are
// skipped) with each of its attributes unchanged, but those write_string writes.
void check_untouched(const Element& before, const Element& after, int& inserted) {
  INFO("<" << before.tag << "> at line " << before.line);
  const bool shortcut = before.tag == "intvelocity" || before.tag == "damper" ||
                        before.tag == "cylinder" || before.tag == "adhesion";
  const bool renamed = ((before.tag == "motor" || shortcut) && after.tag == "general") ||
                       (before.tag == "freejoint" && after.tag == "joint");
  CHECK((after.tag == before.tag || renamed));
  for (const auto& a : before.attributes) {
    if (writable(before.tag).count(a.name)) continue;
    const auto* kept = after.find(a.name);
    INFO("attribute " << a.name);
    REQUIRE(kept != nullptr);
    CHECK(kept->value == a.value);
  }
  std::size_t j = 0;
  for (const Element& child : before.children) {
    while (j < after.children.size() && after.children[j].tag == "inertial" &&
           child.tag != "inertial") {
      ++inserted;
      ++j;
    }
    REQUIRE(j < after.children.size());
    check_untouched(child, after.children[j++], inserted);
  }
  for (; j < after.children.size(); ++j) {
    CHECK(after.children[j].tag == "inertial");
    ++inserted;
  }
}

// `model` with every body's mass, centre of mass and inertia, every dof's armature and damping and
// every fixed gain (with a servo's tied bias) changed: what identification might hand back.
Model changed(Model model) {
  for (int b = 1; b < model.nbody; ++b) {
    if (model.body_mass[b] <= 0) continue;
    model.body_mass[b] *= 1.25;
    model.body_ipos[b] += Eigen::Vector3d(0.01, -0.02, 0.005);
    model.body_inertia[b] *= 1.5;  // scaling keeps the triangle inequality
  }
  for (int d = 0; d < model.nv; ++d) {
    model.dof_armature[d] += 0.01;
    model.dof_damping[d] += 0.5;
  }
  for (int a = 0; a < model.nu; ++a) {
    if (model.actuator_gaintype[a] != lever::GainType::kFixed) continue;
    const int tied = lever::gain_tied_bias(model, a);
    model.actuator_gainprm[a][0] *= 1.5;
    if (tied > 0) model.actuator_biasprm[a][tied] = -model.actuator_gainprm[a][0];
  }
  lever::set_const(model);
  return model;
}

void round_trip(const std::string& text, const std::string& filename, const Model& edited) {
  const std::string written = lever::mjcf::write_string(text, edited, filename);
  const Model back = lever::mjcf::load_string(written, filename);
  check_fields(edited, back);
  int inserted = 0;
  check_untouched(lever::mjcf::detail::read_document(text),
                  lever::mjcf::detail::read_document(written), inserted);
}

}  // namespace

TEST_CASE(
    "write: every model file, written with changed inertials, damping and gains, reads back "
    "as the changed model",
    "[mjcf][write]") {
  std::vector<std::string> files = lever::test::all_model_files();
  files.push_back(lever::test::model_path("tests/menagerie/panda_style.xml"));
  files.push_back(lever::test::model_path("tests/derivatives/servo_affine.xml"));
  files.push_back(lever::test::model_path("tests/models/actuators/shortcuts.xml"));
  files.push_back(lever::test::model_path("tests/models/actuators/adhesion.xml"));
  for (const std::string& file : files) {
    INFO(file);
    const Model prior = lever::mjcf::load_file(file);
    round_trip(read_text(file), file, changed(prior));
  }
}

TEST_CASE("write: what is unchanged is not written", "[mjcf][write]") {
  const std::string file = lever::test::model_path("models/panda7.xml");
  const std::string text = read_text(file);
  const Model prior = lever::mjcf::load_file(file);
  // the prior itself: the same text, as tinyxml2 prints it, and the same model
  const std::string same = lever::mjcf::write_string(text, prior, file);
  check_fields(prior, lever::mjcf::load_string(same, file));
  CHECK(lever::mjcf::write_string(same, prior, file) == same);
  // one body's mass: only its <inertial> changes
  Model edited = prior;
  edited.body_mass[3] *= 2;
  lever::set_const(edited);
  const std::string written = lever::mjcf::write_string(text, edited, file);
  const Element before = lever::mjcf::detail::read_document(same),
                after = lever::mjcf::detail::read_document(written);
  // the two documents differ in one attribute of one element
  std::vector<std::string> differences;
  const std::function<void(const Element&, const Element&)> walk = [&](const Element& x,
                                                                       const Element& y) {
    REQUIRE(x.children.size() == y.children.size());
    REQUIRE(x.attributes.size() == y.attributes.size());
    for (std::size_t i = 0; i < x.attributes.size(); ++i) {
      if (x.attributes[i].value != y.attributes[i].value) {
        differences.push_back(x.tag + " " + x.attributes[i].name);
      }
    }
    for (std::size_t i = 0; i < x.children.size(); ++i) walk(x.children[i], y.children[i]);
  };
  walk(before, after);
  CHECK(differences == std::vector<std::string>{"inertial mass"});
}

TEST_CASE(
    "write: default classes, childclass, a <motor>, a <freejoint> and "
    "inertiafromgeom=\"true\"",
    "[mjcf][write]") {
  // damping and kp come from classes; the motor becomes a <general>; the free joint a <joint
  // type="free">; under inertiafromgeom="true" the <inertial> of b2 was ignored, and must stay so
  // in effect when b1's inertial is written (and "true" becomes "auto")
  const std::string text = R"(<mujoco>
  <compiler inertiafromgeom="true"/>
  <default>
    <default class="arm">
      <joint damping="0.3" armature="0.02"/>
      <position kp="40"/>
    </default>
  </default>
  <worldbody>
    <body name="base" pos="0 0 1">
      <freejoint name="float"/>
      <geom type="box" size="0.1 0.1 0.1"/>
      <body name="b1" childclass="arm" pos="0 0 0.1">
        <joint name="j1" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03"/>
        <body name="b2" pos="0.3 0 0">
          <joint name="j2" axis="0 1 0"/>
          <inertial pos="0.1 0 0" mass="5" diaginertia="1 1 1"/>
          <geom type="sphere" size="0.05" pos="0.2 0 0"/>
        </body>
      </body>
    </body>
  </worldbody>
  <actuator>
    <position name="p1" joint="j1" class="arm"/>
    <motor name="m2" joint="j2" gear="2"/>
  </actuator>
</mujoco>)";
  const Model prior = lever::mjcf::load_string(text, "classes.xml");
  REQUIRE(prior.body_mass[3] != 5);  // b2's <inertial> is ignored
  round_trip(text, "classes.xml", changed(prior));
  // only b1 changed: b2 is written as it compiled, not as its ignored <inertial> says
  Model edited = prior;
  edited.body_mass[2] *= 3;
  lever::set_const(edited);
  const std::string written = lever::mjcf::write_string(text, edited, "classes.xml");
  check_fields(edited, lever::mjcf::load_string(written, "classes.xml"));
  CHECK(written.find("inertiafromgeom=\"auto\"") != std::string::npos);
}

TEST_CASE("write: a model the file cannot say is refused, and nothing is written",
          "[mjcf][write]") {
  const std::string file = lever::test::model_path("models/arm2.xml");
  const Model prior = lever::mjcf::load_file(file);
  const std::string out =
      (std::filesystem::temp_directory_path() / "lever_write_test_refused.xml").string();
  std::filesystem::remove(out);

  Model moved = prior;  // a body's position is not written
  moved.body_pos[2].x() += 0.1;
  lever::set_const(moved);
  CHECK_THROWS_WITH(lever::mjcf::write_file(file, moved, out),
                    Catch::Contains("body_pos") && Catch::Contains("does not write"));
  CHECK_FALSE(std::filesystem::exists(out));

  Model fewer = lever::mjcf::load_file(lever::test::model_path("models/arm3.xml"));
  CHECK_THROWS_WITH(lever::mjcf::write_file(file, fewer, out), Catch::Contains("sizes"));
  CHECK_FALSE(std::filesystem::exists(out));

  CHECK_THROWS_AS(lever::mjcf::write_file(file + ".missing", prior, out), lever::mjcf::ParseError);
  CHECK_FALSE(std::filesystem::exists(out));

  lever::mjcf::write_file(file, changed(prior), out);
  check_fields(changed(prior), lever::mjcf::load_file(out));
  std::filesystem::remove(out);
}
