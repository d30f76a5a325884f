// <sensor>: see sensors.hpp. The elements and what each one reads follow MuJoCo 2.2.2's
// xml_native_reader.cc (its sensor table and mjXReader::Sensor); the compiled arrays follow
// mjCSensor::Compile (user_objects.cc).
#include "sensors.hpp"

#include <array>
#include <string_view>

#include <lever/fields.hpp>

#include "reader.hpp"
#include "schema.hpp"
#include "values.hpp"

namespace lever::mjcf::detail {

namespace {

// What each sensor element reads: its type, the kind of object it is attached to, and the
// attribute that names that object (objname with objtype for the frame sensors).
struct SensorElement {
  std::string_view tag;
  SensorType type;
  std::string_view object_attribute;  ///< "" for the clock
  ObjectType objtype;                 ///< kUnknown where objtype= says it
  bool reference;                     ///< takes reftype and refname
};

using T = SensorType;
using O = ObjectType;
constexpr std::array<SensorElement, 36> kSensorElements = {{
    {"touch", T::kTouch, "site", O::kSite, false},
    {"accelerometer", T::kAccelerometer, "site", O::kSite, false},
    {"velocimeter", T::kVelocimeter, "site", O::kSite, false},
    {"gyro", T::kGyro, "site", O::kSite, false},
    {"force", T::kForce, "site", O::kSite, false},
    {"torque", T::kTorque, "site", O::kSite, false},
    {"magnetometer", T::kMagnetometer, "site", O::kSite, false},
    {"rangefinder", T::kRangefinder, "site", O::kSite, false},
    {"jointpos", T::kJointPos, "joint", O::kJoint, false},
    {"jointvel", T::kJointVel, "joint", O::kJoint, false},
    {"tendonpos", T::kTendonPos, "tendon", O::kTendon, false},
    {"tendonvel", T::kTendonVel, "tendon", O::kTendon, false},
    {"actuatorpos", T::kActuatorPos, "actuator", O::kActuator, false},
    {"actuatorvel", T::kActuatorVel, "actuator", O::kActuator, false},
    {"actuatorfrc", T::kActuatorFrc, "actuator", O::kActuator, false},
    {"ballquat", T::kBallQuat, "joint", O::kJoint, false},
    {"ballangvel", T::kBallAngVel, "joint", O::kJoint, false},
    {"jointlimitpos", T::kJointLimitPos, "joint", O::kJoint, false},
    {"jointlimitvel", T::kJointLimitVel, "joint", O::kJoint, false},
    {"jointlimitfrc", T::kJointLimitFrc, "joint", O::kJoint, false},
    {"tendonlimitpos", T::kTendonLimitPos, "tendon", O::kTendon, false},
    {"tendonlimitvel", T::kTendonLimitVel, "tendon", O::kTendon, false},
    {"tendonlimitfrc", T::kTendonLimitFrc, "tendon", O::kTendon, false},
    {"framepos", T::kFramePos, "objname", O::kUnknown, true},
    {"framequat", T::kFrameQuat, "objname", O::kUnknown, true},
    {"framexaxis", T::kFrameXAxis, "objname", O::kUnknown, true},
    {"frameyaxis", T::kFrameYAxis, "objname", O::kUnknown, true},
    {"framezaxis", T::kFrameZAxis, "objname", O::kUnknown, true},
    {"framelinvel", T::kFrameLinVel, "objname", O::kUnknown, true},
    {"frameangvel", T::kFrameAngVel, "objname", O::kUnknown, true},
    {"framelinacc", T::kFrameLinAcc, "objname", O::kUnknown, false},
    {"frameangacc", T::kFrameAngAcc, "objname", O::kUnknown, false},
    {"subtreecom", T::kSubtreeCom, "body", O::kBody, false},
    {"subtreelinvel", T::kSubtreeLinVel, "body", O::kBody, false},
    {"subtreeangmom", T::kSubtreeAngMom, "body", O::kBody, false},
    {"clock", T::kClock, "", O::kUnknown, false},
}};

const SensorElement* find_element(std::string_view tag) {
  for (const SensorElement& s : kSensorElements) {
    if (s.tag == tag) return &s;
  }
  return nullptr;
}

AttributeRule text_rule(std::string_view name, std::string_view meaning, bool required) {
  AttributeRule r;
  r.name = name;
  r.kind = ValueKind::kText;
  r.required = required;
  r.meaning = meaning;
  return r;
}

AttributeRule real_rule(std::string_view name, std::string_view meaning) {
  AttributeRule r;
  r.name = name;
  r.kind = ValueKind::kReal;
  r.default_value = "0";
  r.meaning = meaning;
  return r;
}

AttributeRule frame_type_rule(std::string_view name, std::string_view meaning, bool required) {
  AttributeRule r;
  r.name = name;
  r.kind = ValueKind::kKeyword;
  r.required = required;
  r.keywords = "body xbody geom site";
  r.unsupported_keywords = "camera";
  r.meaning = meaning;
  return r;
}

std::string_view meaning_of(const SensorElement& s) {
  switch (s.objtype) {
    case O::kSite: return "a sensor at a site";
    case O::kJoint: return "a sensor of a joint";
    case O::kTendon: return "a sensor of a tendon";
    case O::kActuator: return "a sensor of an actuator";
    case O::kBody: return "a sensor of the subtree hanging from a body";
    default: break;
  }
  return s.type == T::kClock ? "the simulation time" : "a sensor of a frame (body, geom, site)";
}

AttributeRule keyword_rule(std::string_view name, std::string_view accepted,
                           std::string_view refused, std::string_view meaning) {
  AttributeRule r;
  r.name = name;
  r.kind = ValueKind::kKeyword;
  r.required = true;
  r.keywords = accepted;
  r.unsupported_keywords = refused;
  r.meaning = meaning;
  return r;
}

// <user>: a sensor the model's callback evaluates (MuJoCo's mjcb_sensor), laid out as written
ElementRule user_sensor_rule() {
  ElementRule r;
  r.tag = "user";
  r.parent = "sensor";
  r.multiplicity = '*';
  r.attributes.push_back(text_rule("name", "sensor name", false));
  r.attributes.push_back(keyword_rule(
      "objtype", "body xbody joint geom site tendon actuator",
      "dof camera light mesh skin hfield texture material pair exclude equality sensor numeric "
      "text tuple key",
      "kind of object it is attached to"));
  r.attributes.push_back(text_rule("objname", "that object's name", true));
  r.attributes.push_back(keyword_rule("datatype", "real positive axis quaternion", "",
                                      "what its numbers are (noise and cutoff treat them so)"));
  r.attributes.push_back(keyword_rule("needstage", "none pos vel acc", "",
                                      "the stage after which the callback evaluates it"));
  AttributeRule dim;
  dim.name = "dim";
  dim.kind = ValueKind::kInteger;
  dim.required = true;
  dim.meaning = "how many numbers it outputs (axis: 3, quaternion: 4)";
  r.attributes.push_back(dim);
  r.attributes.push_back(real_rule("cutoff", "> 0: its numbers clipped to +-cutoff"));
  r.attributes.push_back(
      real_rule("noise", "standard deviation of noise added with <flag sensornoise=\"enable\">"));
  r.attributes.push_back(user_data_rule());
  r.meaning = "a user sensor: Model::sensor_callback (Python: model.set_sensor_callback) writes "
              "its numbers; without one they stay zero, as in MuJoCo";
  return r;
}

ObjectType object_type_named(const std::string& word) {
  return word == "body"       ? O::kBody
         : word == "xbody"    ? O::kXBody
         : word == "joint"    ? O::kJoint
         : word == "geom"     ? O::kGeom
         : word == "site"     ? O::kSite
         : word == "tendon"   ? O::kTendon
         : word == "actuator" ? O::kActuator
                              : O::kUnknown;
}

// A <user> sensor's own layout and object, each attribute checked as MuJoCo's compiler checks it.
void read_user_sensor(const Element& e, SensorSpec& s) {
  const auto word = [&e](const char* attribute) {
    return parse_value(e, *e.find(attribute), attribute_rule("sensor", "user", attribute)).text;
  };
  const std::string datatype = word("datatype"), stage = word("needstage");
  s.layout.datatype = datatype == "positive" ? SensorDataType::kPositive
                      : datatype == "axis"   ? SensorDataType::kAxis
                      : datatype == "quaternion" ? SensorDataType::kQuaternion
                                                 : SensorDataType::kReal;
  s.layout.stage = stage == "pos"   ? SensorStage::kPosition
                   : stage == "vel" ? SensorStage::kVelocity
                   : stage == "acc" ? SensorStage::kAcceleration
                                    : SensorStage::kNone;
  const Attribute* dim = e.find("dim");
  s.layout.dim = static_cast<int>(
      parse_value(e, *dim, attribute_rule("sensor", "user", "dim")).numbers[0]);
  if (s.layout.dim < 0) {
    fail(e.place(*dim), "dim", "dim must not be negative (found " + dim->value + ")");
  }
  if ((s.layout.datatype == SensorDataType::kAxis && s.layout.dim != 3) ||
      (s.layout.datatype == SensorDataType::kQuaternion && s.layout.dim != 4)) {
    fail(e.place(*dim), "dim",
         "a user sensor of datatype " + datatype + " has " +
             (s.layout.datatype == SensorDataType::kAxis ? "3" : "4") + " numbers (found dim " +
             dim->value + ")");
  }
  s.objtype = object_type_named(word("objtype"));
  s.layout.object = s.objtype;
  s.object_attribute = "objname";
  const Attribute* object = e.find("objname");
  s.object = object->value;
  s.object_at = e.place(*object);
}

}  // namespace

std::vector<ElementRule> sensor_rules() {
  std::vector<ElementRule> rules;
  rules.push_back({"sensor", "mujoco", '*', {}, "", "",
                   "sensors: their numbers are data.sensordata, each sensor's from sensor_adr"});
  for (const SensorElement& s : kSensorElements) {
    ElementRule r;
    r.tag = s.tag;
    r.parent = "sensor";
    r.multiplicity = '*';
    r.attributes.push_back(text_rule("name", "sensor name", false));
    if (s.objtype == O::kUnknown && s.type != T::kClock) {
      r.attributes.push_back(frame_type_rule("objtype", "kind of object whose frame it reads", true));
      r.attributes.push_back(text_rule("objname", "that object's name", true));
    } else if (!s.object_attribute.empty()) {
      r.attributes.push_back(text_rule(s.object_attribute, "the object it reads", true));
    }
    if (s.reference) {
      r.attributes.push_back(
          frame_type_rule("reftype", "kind of the reference frame (else the world)", false));
      r.attributes.push_back(text_rule("refname", "the reference frame's object", false));
    }
    r.attributes.push_back(real_rule("cutoff", "> 0: its numbers clipped to +-cutoff"));
    r.attributes.push_back(
        real_rule("noise", "standard deviation of noise added with <flag sensornoise=\"enable\">"));
    r.attributes.push_back(user_data_rule());
    r.meaning = meaning_of(s);
    rules.push_back(std::move(r));
  }
  rules.push_back(user_sensor_rule());
  return rules;
}

std::vector<SensorSpec> read_sensors(const Element& root) {
  std::vector<SensorSpec> sensors;
  for (const Element& section : root.children) {
    if (section.tag != "sensor") continue;
    for (const Element& e : section.children) {
      const SensorElement* kind = find_element(e.tag);
      SensorSpec s;
      s.at = e.place();
      s.type = kind ? kind->type : T::kUser;
      // the numbers, each checked as MuJoCo's compiler checks it
      for (const char* name : {"cutoff", "noise"}) {
        const Attribute* a = e.find(name);
        if (!a) continue;
        const double x = parse_value(e, *a, attribute_rule("sensor", e.tag, name)).numbers[0];
        if (x < 0) {
          fail(e.place(*a), name,
               std::string(name) + " must not be negative (found " + a->value + ")" +
                   (std::string_view(name) == "cutoff" ? ": it bounds the sensor's magnitude"
                                                       : ": it is a standard deviation"));
        }
        (std::string_view(name) == "cutoff" ? s.cutoff : s.noise) = x;
      }
      s.user.at = e.place();
      if (const Attribute* user = e.find("user")) {
        s.user.numbers = parse_value(e, *user, user_data_rule()).numbers;
        s.user.at = e.place(*user);
      }
      if (s.type == T::kUser) {
        read_user_sensor(e, s);
        sensors.push_back(std::move(s));
        continue;
      }
      s.layout = sensor_layout(s.type);
      if (kind->type == T::kClock) {
        sensors.push_back(std::move(s));
        continue;
      }
      // objtype and reftype checked against their keywords (camera: valid MJCF, refused)
      const auto object_type = [&e](const char* attribute) {
        const std::string word =
            parse_value(e, *e.find(attribute), attribute_rule("sensor", e.tag, attribute)).text;
        return word == "body" ? O::kBody
               : word == "xbody" ? O::kXBody
               : word == "geom"  ? O::kGeom
                                 : O::kSite;
      };
      s.object_attribute = std::string(kind->object_attribute);
      const Attribute* object = e.find(kind->object_attribute);
      s.object = object->value;
      s.object_at = e.place(*object);
      s.objtype = kind->objtype == O::kUnknown ? object_type("objtype") : kind->objtype;
      if (kind->reference) {
        const Attribute* reftype = e.find("reftype");
        const Attribute* refname = e.find("refname");
        if (refname && !reftype) {
          fail(e.place(*refname), "refname",
               "refname '" + refname->value + "' given but reftype is missing");
        }
        if (reftype && !refname) {
          fail(e.place(*reftype), "reftype", "reftype given but refname is missing");
        }
        if (reftype) {
          s.reftype = object_type("reftype");
          s.ref = refname->value;
          s.ref_at = e.place(*refname);
        }
      }
      sensors.push_back(std::move(s));
    }
  }
  return sensors;
}

namespace {

int find_object(const Model& model, ObjectType type, const std::string& name) {
  if (name.empty()) return -1;
  switch (type) {
    case O::kBody:
    case O::kXBody: return model.body(name);
    case O::kGeom: return model.geom(name);
    case O::kSite: return model.site(name);
    case O::kJoint: return model.joint(name);
    case O::kActuator: return model.actuator(name);
    case O::kTendon: return model.tendon(name);
    default: return -1;
  }
}

const char* object_kind(ObjectType type) {
  switch (type) {
    case O::kBody:
    case O::kXBody: return "body";
    case O::kGeom: return "geom";
    case O::kSite: return "site";
    case O::kJoint: return "joint";
    case O::kActuator: return "actuator";
    case O::kTendon: return "tendon";
    default: return "object";
  }
}

// "" or, when `name` is no object of `type` but is another kind's, " ('name' is a body)".
std::string other_kind(const Model& model, ObjectType type, const std::string& name) {
  for (ObjectType other : {O::kBody, O::kJoint, O::kGeom, O::kSite, O::kActuator}) {
    if (other == type || (other == O::kBody && type == O::kXBody)) continue;
    if (find_object(model, other, name) >= 0) {
      return std::string(" ('") + name + "' is " + (other == O::kActuator ? "an " : "a ") +
             object_kind(other) + ")";
    }
  }
  return "";
}

}  // namespace

void compile_sensors(const std::vector<SensorSpec>& sensors, Model& model) {
  model.nsensor = static_cast<int>(sensors.size());
  int adr = 0;
  for (const SensorSpec& s : sensors) adr += s.layout.dim;
  model.nsensordata = adr;
  size_model(model);
  adr = 0;
  for (int i = 0; i < model.nsensor; ++i) {
    const SensorSpec& s = sensors[i];
    const std::string tag = "<" + s.at.tag + ">";
    for (int k = 0; k < i; ++k) {
      if (!s.at.name.empty() && sensors[k].at.name == s.at.name) {
        fail(s.at, "name",
             "repeated sensor name '" + s.at.name + "' (also on line " +
                 std::to_string(sensors[k].at.line) + ")");
      }
    }
    const SensorLayout& layout = s.layout;
    int objid = -1, refid = -1;
    if (s.type != T::kClock) {
      objid = find_object(model, s.objtype, s.object);
      if (objid < 0) {
        fail(s.object_at, s.object_attribute,
             tag + " names " + object_kind(s.objtype) + " '" + s.object +
                 "', and the model has no " + object_kind(s.objtype) + " of that name" +
                 other_kind(model, s.objtype, s.object));
      }
    }
    if (s.reftype != O::kUnknown) {
      refid = find_object(model, s.reftype, s.ref);
      if (refid < 0) {
        fail(s.ref_at, "refname",
             tag + " names " + object_kind(s.reftype) + " '" + s.ref + "' as its reference, and " +
                 "the model has no " + object_kind(s.reftype) + " of that name" +
                 other_kind(model, s.reftype, s.ref));
      }
    }
    if (s.objtype == O::kJoint && s.type != T::kUser) {
      const JointType jt = model.jnt_type[objid];
      const bool ball = s.type == T::kBallQuat || s.type == T::kBallAngVel;
      if (ball && jt != JointType::kBall) {
        fail(s.object_at, "joint", tag + " reads a ball joint, and joint '" + s.object +
                                       "' is not one");
      }
      if (!ball && jt != JointType::kHinge && jt != JointType::kSlide) {
        fail(s.object_at, "joint", tag + " reads a hinge or slide joint, and joint '" + s.object +
                                       "' is " + (jt == JointType::kBall ? "a ball" : "free"));
      }
      const bool limit = s.type == T::kJointLimitPos || s.type == T::kJointLimitVel ||
                         s.type == T::kJointLimitFrc;
      if (limit && !model.jnt_limited[objid]) {
        fail(s.object_at, "joint", tag + " reads a joint limit, and joint '" + s.object +
                                       "' is not limited");
      }
    }
    if (s.type == T::kRangefinder) {
      for (int g = 0; g < model.ngeom; ++g) {
        const bool hfield = model.geom_type[g] == GeomType::kHfield;
        const bool unread_mesh = model.geom_type[g] == GeomType::kMesh &&
                                 (model.geom_dataid[g] < 0 ||
                                  model.mesh_facenum[static_cast<size_t>(model.geom_dataid[g])] == 0);
        if (hfield || unread_mesh) {
          fail(s.at, "", std::string("lever casts the rangefinder's ray at every geom type but ") +
                             (hfield ? "height fields" : "meshes it did not read (MSH files)") +
                             ", and the model has one (geom " +
                             (model.geom_name[g].empty() ? std::to_string(g)
                                                         : "'" + model.geom_name[g] + "'") +
                             ")");
        }
      }
    }
    if (s.cutoff > 0 && (layout.datatype == SensorDataType::kAxis ||
                         layout.datatype == SensorDataType::kQuaternion)) {
      fail(s.at, "cutoff", tag + "'s numbers are " +
                               (layout.datatype == SensorDataType::kAxis ? "an axis" : "a quaternion") +
                               ": a cutoff does not apply to them");
    }
    model.sensor_name[i] = s.at.name;
    model.sensor_type[i] = s.type;
    model.sensor_datatype[i] = layout.datatype;
    model.sensor_needstage[i] = layout.stage;
    model.sensor_objtype[i] = s.objtype;
    model.sensor_objid[i] = objid;
    model.sensor_reftype[i] = s.reftype;
    model.sensor_refid[i] = refid;
    model.sensor_dim[i] = layout.dim;
    model.sensor_adr[i] = adr;
    model.sensor_cutoff[i] = s.cutoff;
    model.sensor_noise[i] = s.noise;
    adr += layout.dim;
  }
}

}  // namespace lever::mjcf::detail
