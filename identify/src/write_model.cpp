// The prior's MJCF written again with the identified parameters (see lever/identify.hpp). It
// belongs in mjcf_lite, which knows each element's location, once that can write a model back.
#include <lever/error.hpp>
#include <lever/identify.hpp>
#include <lever/mjcf.hpp>

#ifdef LEVER_HAVE_TINYXML2
#include <tinyxml2.h>
#endif

#include <cstdio>
#include <functional>
#include <string>

namespace lever::identify {

void write_model(const std::string& prior_path, const Model& identified,
                 const std::string& out_path) {
#ifndef LEVER_HAVE_TINYXML2
  // the WebAssembly build reads MJCF with lever's own reader and has no XML writer
  (void)identified;
  throw Error(prior_path + " -> " + out_path +
              ": writing a model needs tinyxml2, which this build of lever does not have.");
#else
  tinyxml2::XMLDocument doc;
  if (doc.LoadFile(prior_path.c_str()) != tinyxml2::XML_SUCCESS) {
    throw Error(prior_path + ": cannot read the prior model (" + doc.ErrorStr() + ").");
  }
  tinyxml2::XMLElement* root = doc.FirstChildElement("mujoco");
  tinyxml2::XMLElement* world = root ? root->FirstChildElement("worldbody") : nullptr;
  if (world == nullptr) throw Error(prior_path + ": no <mujoco><worldbody>.");

  // an explicit <inertial> must count: inertiafromgeom="true" would override it
  if (tinyxml2::XMLElement* compiler = root->FirstChildElement("compiler")) {
    const char* fromgeom = compiler->Attribute("inertiafromgeom");
    if (fromgeom != nullptr && std::string(fromgeom) == "true") {
      compiler->SetAttribute("inertiafromgeom", "auto");
    }
  }

  const auto number = [](double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.17g", x + 0.0);
    return std::string(buf);
  };
  const auto vector = [&](const double* x, int n) {
    std::string s;
    for (int i = 0; i < n; ++i) {
      if (i > 0) s += ' ';
      s += number(x[i]);
    }
    return s;
  };

  // bodies and joints in document order, as MuJoCo numbers them
  int body = 0, joint = 0;
  const std::function<void(tinyxml2::XMLElement*)> visit = [&](tinyxml2::XMLElement* parent) {
    for (tinyxml2::XMLElement* e = parent->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const std::string tag = e->Name();
      if (tag == "joint") {
        if (joint >= identified.njnt) throw Error(prior_path + ": more joints than the model.");
        const int d = identified.jnt_dofadr[joint++];
        e->SetAttribute("armature", number(identified.dof_armature[d]).c_str());
        e->SetAttribute("damping", number(identified.dof_damping[d]).c_str());
      } else if (tag == "body") {
        const int b = ++body;
        if (b >= identified.nbody) throw Error(prior_path + ": more bodies than the model.");
        if (identified.body_mass[b] > 0) {
          tinyxml2::XMLElement* inertial = e->FirstChildElement("inertial");
          if (inertial == nullptr) {
            inertial = doc.NewElement("inertial");
            e->InsertFirstChild(inertial);
          }
          for (const char* attr :
               {"fullinertia", "diaginertia", "quat", "axisangle", "xyaxes", "zaxis", "euler"}) {
            inertial->DeleteAttribute(attr);
          }
          inertial->SetAttribute("pos", vector(identified.body_ipos[b].data(), 3).c_str());
          inertial->SetAttribute("quat", vector(identified.body_iquat[b].data(), 4).c_str());
          inertial->SetAttribute("mass", number(identified.body_mass[b]).c_str());
          inertial->SetAttribute("diaginertia",
                                 vector(identified.body_inertia[b].data(), 3).c_str());
        }
        visit(e);
      }
    }
  };
  visit(world);
  if (body != identified.nbody - 1 || joint != identified.njnt) {
    throw Error(prior_path + ": its bodies and joints do not match the identified model.");
  }

  // actuators whose gain (or tied bias) differs from the prior's, in document order
  const Model original = mjcf::load_file(prior_path);
  if (original.nu != identified.nu) {
    throw Error(prior_path + ": its actuators do not match the identified model.");
  }
  const auto used = [&](const auto& prm, int at_least) {  // entries up to the last nonzero
    int count = static_cast<int>(prm.size());
    while (count > at_least && prm[static_cast<std::size_t>(count - 1)] == 0) --count;
    return vector(prm.data(), count);
  };
  int actuator = 0;
  for (tinyxml2::XMLElement* section = root->FirstChildElement("actuator"); section;
       section = section->NextSiblingElement("actuator")) {
    for (tinyxml2::XMLElement* e = section->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const std::string tag = e->Name();
      if (tag != "motor" && tag != "general" && tag != "position" && tag != "velocity") continue;
      const int a = actuator++;
      if (a >= identified.nu) throw Error(prior_path + ": more actuators than the model.");
      if (identified.actuator_gainprm[a] == original.actuator_gainprm[a] &&
          identified.actuator_biasprm[a] == original.actuator_biasprm[a]) {
        continue;
      }
      const double gain = identified.actuator_gainprm[a][0];
      if (tag == "position") {
        e->SetAttribute("kp", number(gain).c_str());  // its bias -kp follows
      } else if (tag == "velocity") {
        e->SetAttribute("kv", number(gain).c_str());
      } else {
        if (tag == "motor") {  // a motor's gain is 1: say everything a <general> needs
          e->SetName("general");
          e->SetAttribute("dyntype", "none");
          e->SetAttribute("gaintype", "fixed");
          e->SetAttribute("biastype", "none");
        }
        e->SetAttribute("gainprm", used(identified.actuator_gainprm[a], 1).c_str());
        if (identified.actuator_biastype[a] == BiasType::kAffine) {
          e->SetAttribute("biasprm", used(identified.actuator_biasprm[a], 3).c_str());
        }
      }
    }
  }
  if (actuator != identified.nu) {
    throw Error(prior_path + ": its actuators do not match the identified model.");
  }
  if (doc.SaveFile(out_path.c_str()) != tinyxml2::XML_SUCCESS) {
    throw Error(out_path + ": cannot write the model.");
  }
#endif
}

}  // namespace lever::identify
