// The hostile-input table: malformed or hostile models and states, each run through the built
// `lever` as a student would run it. Every row must end with a clear message naming the problem
// (and file:line for a located XML error), the exit status the row states (1: the engine warned
// or a number came out non-finite; 2: refused), no crash (a signal is a failure), no "nan" or
// "inf" printed as a number, and bounded time and memory. Rows whose right behaviour is to load
// (a big but valid model) check that it loads within the same bounds.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <lever/mjcf.hpp>

#include <lever/harness/models.hpp>
#include "run_process.hpp"

namespace {

using lever::mjcf::Limits;

#ifdef LEVER_SANITIZED
constexpr double kSlowdown = 8;  // ASan + UBSan in a Debug build
#else
constexpr double kSlowdown = 1;
#endif
constexpr double kTimeBound = 20 * kSlowdown;  // s, any row
constexpr long kMemoryBoundKb = 1L << 20;      // 1 GiB (ASan's shadow memory is not resident)

const std::filesystem::path& dir() {
  static const std::filesystem::path d = [] {
    auto p =
        std::filesystem::temp_directory_path() / ("lever-hostile-" + std::to_string(::getpid()));
    std::filesystem::create_directories(p);
    return p;
  }();
  return d;
}

std::string write(const std::string& name, const std::string& text) {
  const std::filesystem::path p = dir() / name;
  std::ofstream(p, std::ios::binary) << text;
  return p.string();
}

std::string arm2_text() { return lever::test::slurp(lever::test::model_path("models/arm2.xml")); }

std::string body(int i, bool joint) {
  return "<body name=\"b" + std::to_string(i) + "\" pos=\"0 0 " + std::to_string(i % 7) + "\">" +
         (joint ? "<joint axis=\"0 1 0\"/>" : "") + "<geom size=\"0.1\"/></body>\n";
}

// n bodies side by side under the world, each with a joint or not
std::string flat(int n, bool joints) {
  std::string xml = "<mujoco>\n<worldbody>\n";
  for (int i = 0; i < n; ++i) xml += body(i, joints);
  return xml + "</worldbody>\n</mujoco>\n";
}

// a chain of n bodies, each inside the last
std::string chain(int n) {
  std::string xml = "<mujoco>\n<worldbody>\n";
  for (int i = 0; i < n; ++i) xml += "<body pos=\"0 0 0.1\"><joint/><geom size=\"0.05\"/>\n";
  for (int i = 0; i < n; ++i) xml += "</body>";
  return xml + "\n</worldbody>\n</mujoco>\n";
}

// default classes nested n deep
std::string nested_defaults(int n) {
  std::string xml = "<mujoco>\n<default>\n";
  for (int i = 0; i < n; ++i) xml += "<default class=\"c" + std::to_string(i) + "\">\n";
  for (int i = 0; i < n; ++i) xml += "</default>";
  return xml + "\n</default>\n<worldbody/>\n</mujoco>\n";
}

std::string many_classes(int n) {
  std::string xml = "<mujoco>\n<default>\n";
  for (int i = 0; i < n; ++i) xml += "<default class=\"c" + std::to_string(i) + "\"/>\n";
  return xml + "</default>\n<worldbody/>\n</mujoco>\n";
}

// an arm whose motor has no ctrlrange, so that a huge command is not clamped away
const char* const kUnlimited = R"(<mujoco model="unlimited">
  <worldbody>
    <body name="link" pos="0 0 1">
      <joint name="hinge" axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 0.5 0 0" size="0.05"/>
    </body>
  </worldbody>
  <actuator>
    <motor name="m" joint="hinge" ctrllimited="false" gear="1e300"/>
  </actuator>
</mujoco>
)";

struct Row {
  const char* id;
  std::vector<std::string> args;  ///< after `lever`; "@name" is the generated file `name`
  int exit;                       ///< expected exit status
  const char* phrase;             ///< in the first line of stderr ("" for exit 0)
  /// > 0: stderr starts with "<file>:<line>: error:"; 0: with "<file>: error:"; -1: with
  /// "<file>"; -2: no location (a state, not a file, is at fault)
  int line = -2;
};

// contact models: malformed <contact> elements, contacts beyond nconmax at run time,
// and geom pairs lever has no collision function for
const char* const kTwoSpheres =
    "<mujoco>\n<worldbody>\n<geom name=\"a\" size=\"1\"/>\n<body><joint/><geom name=\"b\" "
    "size=\"1\"/></body>\n</worldbody>\n";

void make_contact_files() {
  const std::string two = kTwoSpheres;
  write("pair-no-geom2.xml", two + "<contact><pair geom1=\"a\"/></contact>\n</mujoco>\n");
  write("pair-unknown-geom.xml",
        two + "<contact><pair geom1=\"a\" geom2=\"nosuch\"/></contact>\n</mujoco>\n");
  write("pair-bad-friction.xml",
        two + "<contact><pair geom1=\"a\" geom2=\"b\" friction=\"1 x\"/></contact>\n</mujoco>\n");
  write("pair-nested.xml", two +
                               "<contact><pair geom1=\"a\" geom2=\"b\"><pair geom1=\"a\" "
                               "geom2=\"b\"/></pair></contact>\n</mujoco>\n");
  write("exclude-unknown-body.xml",
        two + "<contact><exclude body1=\"world\" body2=\"nosuch\"/></contact>\n</mujoco>\n");
  write("geom-condim-2.xml",
        "<mujoco>\n<worldbody>\n<geom name=\"a\" size=\"1\"/>\n<body><joint/><geom name=\"b\" "
        "size=\"1\" condim=\"2\"/></body>\n</worldbody>\n</mujoco>\n");
  // a box resting on a plane makes four contacts: two more than nconmax allows
  write("contact-nconmax-2.xml",
        "<mujoco>\n<size nconmax=\"2\"/>\n<worldbody>\n<geom name=\"floor\" type=\"plane\" "
        "size=\"1 1 0.1\"/>\n<body pos=\"0 0 0.099\"><freejoint/><geom name=\"box\" "
        "type=\"box\" size=\"0.1 0.1 0.1\"/></body>\n</worldbody>\n</mujoco>\n");
  write("contact-cylinders.xml",
        "<mujoco>\n<worldbody>\n<geom name=\"floor\" type=\"plane\" size=\"1 1 0.1\"/>\n"
        "<body pos=\"0 0 0.1\"><freejoint/><geom name=\"cyl1\" type=\"cylinder\" size=\"0.05 "
        "0.1\"/></body>\n<body pos=\"0.05 0 0.2\"><freejoint/><geom name=\"cyl2\" "
        "type=\"cylinder\" size=\"0.05 0.1\"/></body>\n</worldbody>\n</mujoco>\n");
  write("contact-mesh-sphere.xml",
        "<mujoco>\n<asset>\n<mesh name=\"m\" vertex=\"0 0 0 1 0 0 0 1 0 0 0 1\"/>\n</asset>\n"
        "<worldbody>\n<geom name=\"tet\" type=\"mesh\" mesh=\"m\"/>\n<body pos=\"0.2 0.2 0.2\">"
        "<freejoint/><geom name=\"ball\" size=\"0.1\"/></body>\n</worldbody>\n</mujoco>\n");
  write("contact-hfield.xml",
        "<mujoco>\n<asset>\n<hfield name=\"h\" nrow=\"2\" ncol=\"2\" size=\"1 1 0.1 0.1\"/>\n"
        "</asset>\n<worldbody>\n<geom type=\"hfield\" hfield=\"h\"/>\n</worldbody>\n</mujoco>\n");
}

// the files the rows use, made once
void make_files() {
  const std::string arm2 = arm2_text();
  std::mt19937 rng(2718);
  std::string junk(4096, '\0');
  for (char& c : junk) c = static_cast<char>(rng() & 0xff);

  write("empty.xml", "");
  write("blank.xml", " \n\t\n");
  write("truncated-half.xml", arm2.substr(0, arm2.size() / 2));
  write("truncated-in-attribute.xml", arm2.substr(0, arm2.find("pos=\"") + 7));
  write("binary.xml", junk);
  write("nul-bytes.xml", std::string("<mujoco>\0<worldbody/></mujoco>", 30));
  write("utf16.xml",
        std::string("\xff\xfe<\0m\0u\0j\0o\0c\0o\0>\0<\0/\0m\0u\0j\0o\0c\0o\0>\0", 36));
  write("utf8-bom.xml", "\xef\xbb\xbf" + arm2);
  write("latin1-name.xml",
        "<mujoco model=\"bra\xe7o\">\n<worldbody>\n" + body(0, true) + "</worldbody>\n</mujoco>\n");
  write("huge-name.xml", "<mujoco>\n<worldbody>\n<body name=\"" + std::string(1 << 20, 'x') +
                             "\"><joint/><geom size=\"0.1\"/></body>\n</worldbody>\n</mujoco>\n");
  write("long-number-list.xml", "<mujoco>\n<worldbody>\n<geom size=\"0.1\" pos=\"" +
                                    std::string(5000, '1') + "\"/>\n</worldbody>\n</mujoco>\n");
  write("static-10000.xml", flat(Limits::kBodies, false));
  write("bodies-10001.xml", flat(Limits::kBodies + 1, false));
  {
    // side by side the spheres touch: as many contacts as joints, beyond nconmax (refused), or
    // none when they do not collide
    const std::string touching = flat(Limits::kJoints, true);
    write("touching-1000.xml", touching);
    std::string apart = touching;
    apart.replace(apart.find("<worldbody>"), 11,
                  "<default><geom contype=\"0\" conaffinity=\"0\"/></default>\n<worldbody>");
    write("joints-1000.xml", apart);
  }
  write("joints-1001.xml", flat(Limits::kJoints + 1, true));
  write("chain-95.xml", chain(95));
  write("chain-200.xml", chain(200));
  write("chain-30000.xml", chain(30000));
  write("defaults-nested-90.xml", nested_defaults(90));
  write("defaults-nested-150.xml", nested_defaults(150));
  write("classes-1001.xml", many_classes(Limits::kClasses + 1));
  write("size-1e308.xml",
        "<mujoco>\n<worldbody>\n<body>\n<joint/>\n<geom type=\"box\" size=\"1e308 1e308 1e308\"/>\n"
        "</body>\n</worldbody>\n</mujoco>\n");
  write("size-1e309.xml",
        "<mujoco>\n<worldbody>\n<geom size=\"1e309\"/>\n</worldbody>\n</mujoco>\n");
  write("denormal-mass.xml",
        "<mujoco>\n<worldbody>\n<body>\n<joint/>\n<inertial pos=\"0 0 0\" mass=\"4.9e-324\" "
        "diaginertia=\"1 1 1\"/>\n</body>\n</worldbody>\n</mujoco>\n");
  write("denormal-static.xml",
        "<mujoco>\n<worldbody>\n<body>\n<inertial pos=\"0 0 0\" mass=\"1e-310\" "
        "diaginertia=\"1e-310 1e-310 1e-310\"/>\n</body>\n</worldbody>\n</mujoco>\n");
  write("attrnan.xml", "<mujoco>\n<worldbody>\n<geom size=\"nan\"/>\n</worldbody>\n</mujoco>\n");
  write("attrinf.xml", "<mujoco>\n<option gravity=\"0 0 -inf\"/>\n<worldbody/>\n</mujoco>\n");
  write("unknown-element.xml", "<mujoco>\n<worldbody>\n<bodyy/>\n</worldbody>\n</mujoco>\n");
  write("unsupported-element.xml", "<mujoco>\n<custom/>\n<worldbody/>\n</mujoco>\n");
  write("urdf.xml", "<robot name=\"r\">\n<link name=\"l\"/>\n</robot>\n");
  write("big-file.xml",
        "<mujoco>\n<!--" + std::string(Limits::kDocumentBytes, ' ') + "-->\n</mujoco>\n");
  std::string tags = "<mujoco>\n";
  for (int i = 0; i < Limits::kTags; ++i) tags += "<!---->";
  write("too-many-tags.xml", tags + "\n</mujoco>\n");
  write("timestep-zero.xml", "<mujoco>\n<option timestep=\"0\"/>\n<worldbody/>\n</mujoco>\n");
  write("timestep-negative.xml",
        "<mujoco>\n<option timestep=\"-0.001\"/>\n<worldbody/>\n</mujoco>\n");
  write("negative-damping.xml",
        "<mujoco>\n<worldbody>\n<body>\n<joint name=\"j\" damping=\"-1\"/>\n<geom size=\"0.1\"/>\n"
        "</body>\n</worldbody>\n</mujoco>\n");
  write("gravity-1e300.xml",
        "<mujoco>\n<option gravity=\"0 0 -1e300\"/>\n<worldbody>\n<body pos=\"0 0 1\">\n"
        "<joint name=\"j\" axis=\"0 1 0\"/>\n<geom size=\"0.1\" pos=\"0.5 0 0\"/>\n</body>\n"
        "</worldbody>\n</mujoco>\n");
  write("offsets-overflow.xml",
        "<mujoco>\n<worldbody>\n<body pos=\"1e308 0 0\">\n<geom size=\"0.1\"/>\n"
        "<body name=\"far\" pos=\"1e308 0 0\">\n<joint/>\n<geom size=\"0.1\"/>\n</body>\n</body>\n"
        "</worldbody>\n</mujoco>\n");
  write("two-roots.xml", "<mujoco/>\n<mujoco/>\n");
  write("text-in-element.xml", "<mujoco>\n<worldbody>hello</worldbody>\n</mujoco>\n");
  write("billion-laughs.xml",
        "<?xml version=\"1.0\"?>\n<!DOCTYPE lolz [<!ENTITY lol \"lol\"><!ENTITY lol2 "
        "\"&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;\">]>\n<mujoco model=\"&lol2;\">\n"
        "<worldbody/>\n</mujoco>\n");
  std::string attrs = "<mujoco>\n<worldbody>\n<geom size=\"0.1\"";
  for (int i = 0; i < 10000; ++i) attrs += " a" + std::to_string(i) + "=\"1\"";
  write("many-attributes.xml", attrs + "/>\n</worldbody>\n</mujoco>\n");
  write("repeated-attribute.xml",
        "<mujoco>\n<worldbody>\n<geom size=\"0.1\" size=\"0.2\"/>\n</worldbody>\n</mujoco>\n");
  std::string long_names = flat(Limits::kJoints, true);
  for (int i = 0; i < Limits::kJoints; ++i) {
    const std::string from = "<body name=\"b" + std::to_string(i) + "\" pos=\"0 0 " +
                             std::to_string(i % 7) + "\"><joint ";
    const size_t at = long_names.find(from);
    long_names.insert(at + from.size(),
                      "name=\"" + std::string(4000, 'j') + std::to_string(i) + "\" ");
  }
  long_names.insert(long_names.rfind("</mujoco>"),
                    "<actuator><motor joint=\"" + std::string(4000, 'k') + "\"/></actuator>\n");
  write("long-names-1000-joints.xml", long_names);
  write("unclosed-comment.xml", "<mujoco>\n<!-- never closed\n<worldbody/>\n</mujoco>\n");
  // contact: valid MJCF that lever refuses, each with its reason
  write("contact-noslip.xml", "<mujoco>\n<option noslip_iterations=\"10\"/>\n</mujoco>\n");
  write("contact-condim-5.xml",
        "<mujoco>\n<worldbody>\n<geom name=\"a\" size=\"1\"/>\n<body><joint/><geom name=\"b\" "
        "size=\"1\"/></body>\n</worldbody>\n<contact><pair geom1=\"a\" geom2=\"b\" "
        "condim=\"5\"/></contact>\n</mujoco>\n");
  write("contact-moving-plane.xml",
        "<mujoco>\n<worldbody>\n<body><joint/><geom size=\"1\"/>\n<geom type=\"plane\" "
        "size=\"1 1 1\"/></body>\n</worldbody>\n</mujoco>\n");
  std::string pairs =
      "<mujoco>\n<worldbody>\n<geom name=\"floor\" type=\"plane\" size=\"0 0 1\"/>\n";
  pairs += "<body><joint/><geom name=\"g\" type=\"cylinder\" size=\"0.1 0.1\"/></body>\n";
  pairs += "</worldbody>\n<contact>\n";
  for (int i = 0; i < 20000; ++i)
    pairs += "<pair geom1=\"g\" geom2=\"floor\"/><exclude body1=\"world\" body2=\"world\"/>\n";
  write("contact-20000-pairs.xml", pairs + "</contact>\n</mujoco>\n");
  write("cdata.xml", "<mujoco>\n<worldbody><![CDATA[<body/>]]></worldbody>\n</mujoco>\n");
  make_contact_files();
  write("unlimited.xml", kUnlimited);
  std::filesystem::create_directories(dir() / "a-directory.xml");
}

std::vector<Row> rows() {
  const std::string arm2 = lever::test::model_path("models/arm2.xml");
  return {
      // ---- XML: malformed -----------------------------------------------------------------
      {"empty file", {"model", "@empty.xml"}, 2, "the document is empty", 0},
      {"blank file", {"model", "@blank.xml"}, 2, "malformed XML", -1},
      {"truncated in the middle", {"model", "@truncated-half.xml"}, 2, "malformed XML", -1},
      {"truncated inside an attribute",
       {"model", "@truncated-in-attribute.xml"},
       2,
       "malformed XML",
       -1},
      {"binary junk", {"model", "@binary.xml"}, 2, "error:", -1},
      {"NUL byte after the root tag", {"model", "@nul-bytes.xml"}, 2, "malformed XML", -1},
      {"UTF-16 encoding", {"model", "@utf16.xml"}, 2, "error:", -1},
      {"unclosed comment", {"model", "@unclosed-comment.xml"}, 2, "comment", 2},
      {"two root elements", {"model", "@two-roots.xml"}, 2, "one root element", 2},
      {"repeated attribute", {"model", "@repeated-attribute.xml"}, 2, "attribute", 3},
      {"text inside an element", {"model", "@text-in-element.xml"}, 2, "unexpected text", 2},
      {"CDATA inside an element", {"model", "@cdata.xml"}, 2, "unexpected text", 2},
      // ---- XML: not the subset ------------------------------------------------------------
      {"unknown element", {"model", "@unknown-element.xml"}, 2, "unknown element <bodyy>", 3},
      {"unsupported element",
       {"model", "@unsupported-element.xml"},
       2,
       "not supported by lever",
       2},
      {"URDF instead of MJCF", {"model", "@urdf.xml"}, 2, "this is URDF", 1},
      // ---- contact: valid MJCF lever does not have -----------------------------------------
      {"noslip solver", {"model", "@contact-noslip.xml"}, 2, "no noslip solver", 2},
      {"pair condim 5", {"model", "@contact-condim-5.xml"}, 2, "MuJoCo has no condim 5", 6},
      {"plane in a moving body", {"model", "@contact-moving-plane.xml"}, 2, "use a box", 4},
      {"20000 pairs and exclusions of one geom pair",
       {"model", "@contact-20000-pairs.xml"},
       0,
       "",
       -2},
      {"<pair> without geom2",
       {"model", "@pair-no-geom2.xml"},
       2,
       "missing required attribute 'geom2'",
       6},
      {"<pair> naming a geom that does not exist",
       {"forward", "@pair-unknown-geom.xml"},
       2,
       "unknown geom 'nosuch'",
       6},
      {"<pair> friction that is not a number",
       {"model", "@pair-bad-friction.xml"},
       2,
       "'x' is not a number",
       6},
      {"<pair> inside <pair>", {"model", "@pair-nested.xml"}, 2, "is not allowed in <pair>", 6},
      {"<exclude> naming a body that does not exist",
       {"simulate", "@exclude-unknown-body.xml"},
       2,
       "unknown body 'nosuch'",
       6},
      {"geom condim 2", {"forward", "@geom-condim-2.xml"}, 2, "MuJoCo has no condim 2", 4},
      {"height field", {"forward", "@contact-hfield.xml"}, 2, "not supported by lever", 3},
      {"10000 unknown attributes", {"model", "@many-attributes.xml"}, 2, "unknown attribute", 3},
      // ---- files -----------------------------------------------------------------------------
      {"missing file", {"model", "@does-not-exist.xml"}, 2, "no such file", 0},
      {"directory instead of a file", {"model", "@a-directory.xml"}, 2, "directory", 0},
      {"device instead of a file", {"model", "/dev/zero"}, 2, "not a regular file", -2},
      {"file over 8 MiB", {"model", "@big-file.xml"}, 2, "bytes long; lever accepts at most", 0},
      // ---- limits ----------------------------------------------------------------------------
      {"1 MiB attribute value", {"model", "@huge-name.xml"}, 2, "bytes long", 3},
      {"5000-digit number", {"model", "@long-number-list.xml"}, 2, "bytes long", 3},
      {"200001 tags", {"model", "@too-many-tags.xml"}, 2, "more than 200000 tags", 2},
      {"10001 bodies", {"model", "@bodies-10001.xml"}, 2, "more than 10000 bodies", 10003},
      {"1001 joints", {"model", "@joints-1001.xml"}, 2, "more than 1000 joints", 1003},
      {"1002 default classes (the main one and 1001 nested)",
       {"model", "@classes-1001.xml"},
       2,
       "more than 1000 default classes",
       1002},
      {"bodies nested 200 deep", {"model", "@chain-200.xml"}, 2, "nested more than 100", -1},
      {"bodies nested 30000 deep", {"model", "@chain-30000.xml"}, 2, "nested more than 100", -1},
      {"defaults nested 150 deep",
       {"model", "@defaults-nested-150.xml"},
       2,
       "nested more than 100",
       -1},
      {"1000 joints with 4000-byte names, a motor naming none of them",
       {"model", "@long-names-1000-joints.xml"},
       2,
       "unknown joint",
       1004},
      // ---- numbers ---------------------------------------------------------------------------
      {"size 1e308 overflows the mass", {"model", "@size-1e308.xml"}, 2, "too large", 5},
      {"size 1e309 is not a double", {"model", "@size-1e309.xml"}, 2, "too large for a double", 3},
      {"nan in an attribute", {"model", "@attrnan.xml"}, 2, "not a finite number", 3},
      {"-inf in an attribute", {"model", "@attrinf.xml"}, 2, "not a finite number", 2},
      {"denormal mass on a moving body",
       {"model", "@denormal-mass.xml"},
       2,
       "positive mass and inertia",
       5},
      {"zero timestep", {"model", "@timestep-zero.xml"}, 2, "timestep must be positive", 2},
      {"negative timestep", {"model", "@timestep-negative.xml"}, 2, "timestep must be positive", 2},
      {"negative damping", {"model", "@negative-damping.xml"}, 2, "must not be negative", 4},
      {"gravity 1e300", {"model", "@gravity-1e300.xml"}, 2, "more than 1e10", 5},
      {"positions that overflow", {"model", "@offsets-overflow.xml"}, 2, "too large", 5},
      {"lever check on a broken file", {"check", "@truncated-half.xml"}, 2, "malformed XML", -1},
      {"lever simulate on a missing file",
       {"simulate", "@does-not-exist.xml"},
       2,
       "no such file",
       0},
      // ---- big or odd but valid: loads within the bounds ---------------------------------------
      {"10000 static bodies", {"model", "@static-10000.xml"}, 0, ""},
      {"1000 joints side by side", {"forward", "@joints-1000.xml"}, 0, ""},
      {"1000 touching spheres: more contacts than nconmax",
       {"forward", "@touching-1000.xml"},
       2,
       "raise <size nconmax>"},
      {"bodies nested 95 deep", {"forward", "@chain-95.xml"}, 0, ""},
      // contacts at run time: more than nconmax is refused before anything is
      // printed; a pair lever cannot collide is a warning (exit 1), never skipped silently
      {"a box on a plane with nconmax 2: simulate --json",
       {"simulate", "@contact-nconmax-2.xml", "--steps", "5", "--json"},
       2,
       "raise <size nconmax>"},
      {"a box on a plane with nconmax 2: forward --json",
       {"forward", "@contact-nconmax-2.xml", "--json"},
       2,
       "raise <size nconmax>"},
      {"two cylinders touching: their contacts, by MPR", {"forward", "@contact-cylinders.xml"}, 0, ""},
      {"a sphere on a mesh: simulate --json",
       {"simulate", "@contact-mesh-sphere.xml", "--steps", "5", "--json"},
       1,
       "gives its vertices inline, which lever does not read"},
      {"defaults nested 90 deep", {"model", "@defaults-nested-90.xml"}, 0, ""},
      {"UTF-8 byte-order mark", {"forward", "@utf8-bom.xml"}, 0, ""},
      {"Latin-1 byte in the model name", {"model", "@latin1-name.xml"}, 0, ""},
      {"denormal mass on a static body", {"forward", "@denormal-static.xml"}, 0, ""},
      {"entity declarations (billion laughs) are not expanded",
       {"model", "@billion-laughs.xml"},
       0,
       ""},
      // ---- states through the command line -----------------------------------------------------
      {"--qpos nan", {"forward", arm2, "--qpos", "nan,0"}, 2, "not a finite number"},
      {"--qvel inf", {"forward", arm2, "--qvel", "0,inf"}, 2, "not a finite number"},
      {"--ctrl -infinity", {"simulate", arm2, "--ctrl", "-infinity,0"}, 2, "not a finite number"},
      {"--qpos 1e309", {"forward", arm2, "--qpos", "1e309,0"}, 2, "too large for a double"},
      {"--qpos with three numbers for two joints",
       {"forward", arm2, "--qpos", "1,2,3"},
       2,
       "needs 2 comma-separated numbers"},
      {"--qpos empty", {"forward", arm2, "--qpos", ""}, 2, "needs 2 comma-separated numbers"},
      {"--qpos 1e11 (bad: beyond 1e10)",
       {"forward", arm2, "--qpos", "1e11,0"},
       1,
       "warning: qpos is NaN or larger than 1e10"},
      {"--qvel 1e300",
       {"forward", arm2, "--qvel", "1e300,0"},
       1,
       "warning: qvel is NaN or larger than 1e10"},
      {"--qvel 1e300 --json",
       {"forward", arm2, "--qvel", "1e300,0", "--json"},
       1,
       "warning: qvel is NaN or larger than 1e10"},
      {"--qvel 5e9 with the elbow bent: qacc blows up",
       {"forward", arm2, "--qpos", "0,0.5", "--qvel", "0,5e9"},
       1,
       "warning: qacc is NaN or larger than 1e10"},
      {"--ctrl 1e11 on a motor without ctrlrange",
       {"forward", "@unlimited.xml", "--ctrl", "1e11"},
       1,
       "warning: ctrl is NaN or larger than 1e10"},
      {"--ctrl 1e10 times gear 1e300 overflows",
       {"forward", "@unlimited.xml", "--ctrl", "1e10"},
       1,
       "warning: qacc is NaN or larger than 1e10"},
      {"--ctrl 1e300 on arm2 is clamped to its ctrlrange",
       {"forward", arm2, "--ctrl", "1e300,0"},
       0,
       ""},
      {"--qpos denormal", {"forward", arm2, "--qpos", "4.9e-324,-4.9e-324"}, 0, ""},
      {"simulate --qvel 1e300: reset, then a normal run",
       {"simulate", arm2, "--qvel", "1e300,0", "--steps", "20"},
       1,
       "warning: qvel is NaN or larger than 1e10"},
      {"simulate --qpos 1e11 --json",
       {"simulate", arm2, "--qpos", "1e11,0", "--steps", "5", "--json"},
       1,
       "warning: qpos is NaN or larger than 1e10"},
      {"simulate --qvel 1e300 --csv -",
       {"simulate", arm2, "--qvel", "1e300,0", "--steps", "5", "--csv", "-"},
       1,
       "warning: qvel is NaN or larger than 1e10"},
      {"simulate --ctrl 1e11 every step, gear 1e300",
       {"simulate", "@unlimited.xml", "--ctrl", "1e11", "--steps", "5"},
       1,
       "warning: ctrl is NaN or larger than 1e10"},
      {"simulate --steps 99999999999",
       {"simulate", arm2, "--steps", "99999999999"},
       2,
       "more than one run's limit"},
      {"simulate --duration 1e300",
       {"simulate", arm2, "--duration", "1e300"},
       2,
       "more than one run's limit"},
      {"simulate --duration nan",
       {"simulate", arm2, "--duration", "nan"},
       2,
       "not a finite number"},
      {"simulate --steps -1", {"simulate", arm2, "--steps", "-1"}, 2, "must not be negative"},
  };
}

// "nan", "inf", "infinity" as a word, as printf and iostreams print a non-finite double (and
// "Infinity" as some JSON writers do), outside the user's own text that a message quotes
// back ('nan' in "--qpos: 'nan' is not a finite number"). The warnings' own wording ("qvel is NaN
// or larger than 1e10") is text, not a number, and is not matched.
bool prints_non_finite(const std::string& text) {
  const std::string unquoted = std::regex_replace(text, std::regex("'[^'\\n]*'"), "''");
  static const std::regex word("(^|[^A-Za-z_])[-+]?(nan|inf|infinity|Infinity)([^A-Za-z_]|$)");
  return std::regex_search(unquoted, word);
}

std::string first_line(const std::string& s) { return s.substr(0, s.find('\n')); }

}  // namespace

TEST_CASE("hostile inputs: a clear message, the right exit status, no crash, no NaN", "[hostile]") {
  make_files();
  const std::vector<Row> table = rows();
  REQUIRE(table.size() >= 50);
  for (const Row& row : table) {
    {
      std::vector<std::string> argv{LEVER_EXE};
      std::string file;
      for (const std::string& a : row.args) {
        if (a.rfind('@', 0) == 0) {
          file = (dir() / a.substr(1)).string();
          argv.push_back(file);
        } else {
          argv.push_back(a);
        }
      }
      const lever::test::Process p = lever::test::run_process(argv, kTimeBound);
      INFO(row.id << "\nstatus " << p.status << ", signal " << p.signal << ", " << p.seconds
                  << " s, " << p.max_rss_kb << " KiB\nstderr: " << p.err.substr(0, 2000)
                  << "\nstdout: " << p.out.substr(0, 500));
      CHECK(!p.timed_out);
      CHECK(p.signal == 0);
      CHECK(p.status == row.exit);
      CHECK(p.seconds < kTimeBound);
      CHECK(p.max_rss_kb < kMemoryBoundKb);
      CHECK(!prints_non_finite(p.out));
      CHECK(!prints_non_finite(p.err));
      if (row.exit == 0) {
        // success writes nothing to stderr but the loader's warnings (pairs lever cannot collide)
        std::istringstream lines(p.err);
        for (std::string line; std::getline(lines, line);) {
          CHECK_THAT(line, Catch::StartsWith("lever ") && Catch::Contains(": warning: "));
        }
        continue;
      }
      REQUIRE(!p.err.empty());
      const std::string message = first_line(p.err);
      CHECK_THAT(message, Catch::Contains(row.phrase));
      if (row.exit == 2) {
        // refused: one line, nothing on stdout
        CHECK(std::count(p.err.begin(), p.err.end(), '\n') == 1);
        CHECK(p.out.empty());
      }
      if (row.line > 0) {
        CHECK_THAT(message, Catch::StartsWith(file + ":" + std::to_string(row.line) + ": error: "));
      } else if (row.line == 0) {
        CHECK_THAT(message, Catch::StartsWith(file + ": error: "));
      } else if (row.line == -1) {
        CHECK_THAT(message, Catch::StartsWith(file + ":"));
      }
    }
  }
}
