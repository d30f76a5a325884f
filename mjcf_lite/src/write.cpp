// An MJCF file written again with some of a model's numbers (lever/mjcf/write.hpp).
//
// The file is loaded as usual, which records for each body, joint and actuator the index of its
// element in document order (reader.cpp numbers them); tinyxml2 reads the same text into a
// document whose pre-order walk gives the same numbering, so each object's element is found by
// its index. Edits go onto those elements only, and the result is loaded again and must compile to
// the model exactly: a file that cannot say the model is refused rather than written wrong.
#include <lever/error.hpp>
#include <lever/fields.hpp>
#include <lever/mjcf.hpp>
#include <lever/mjcf/write.hpp>

#ifdef LEVER_HAVE_TINYXML2
#include <tinyxml2.h>
#endif

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "compiler.hpp"
#include "orientation.hpp"
#include "problem.hpp"

namespace lever::mjcf {

namespace {

// The fields write_string writes, and those it may change without saying so: where an element
// is (body_line) and whether a body's inertia was written (body_explicit_inertial).
constexpr const char* kWritten[] = {"body_mass",        "body_ipos",       "body_iquat",
                                    "body_inertia",     "dof_armature",    "dof_damping",
                                    "actuator_gainprm", "actuator_biasprm"};
constexpr const char* kBookkeeping[] = {"body_line", "body_explicit_inertial"};

// How far a written body_iquat may read back from the model's: a unit quaternion that no
// quaternion normalizes to exactly (quat_compiling_to) is written as the nearest that does, a
// unit in the last place or two away (components are at most 1).
constexpr double kQuatRounding = 4 * std::numeric_limits<double>::epsilon();

bool listed(const char* name, const auto& list) {
  return std::any_of(std::begin(list), std::end(list),
                     [&](const char* n) { return std::strcmp(n, name) == 0; });
}

bool same(const FieldView& a, const FieldView& b) {
  if (a.rows != b.rows || a.cols != b.cols) return false;
  if (a.size() == 0) return true;  // an empty field's data() may be null: nothing to compare
  if (a.info->scalar != Scalar::kDouble) {
    const std::size_t bytes = a.info->scalar == Scalar::kInt ? sizeof(int) : sizeof(uint8_t);
    return std::memcmp(a.data, b.data, static_cast<std::size_t>(a.size()) * bytes) == 0;
  }
  return std::equal(a.doubles(), a.doubles() + a.size(), b.doubles());  // +0 == -0, as compiled
}

// The first field other than the written ones in which `model` differs from `file` and which
// does not follow from the written ones (as set_const derives them); "" if none.
std::string unwritable_difference(const Model& file, const Model& model) {
  if (file.nbody != model.nbody || file.njnt != model.njnt || file.nv != model.nv ||
      file.nq != model.nq || file.nu != model.nu || file.ngeom != model.ngeom ||
      file.nsite != model.nsite) {
    return "its sizes (bodies, joints, dofs, actuators, geoms, sites)";
  }
  // the file's model with the written fields taken from `model`: what may differ
  Model expected = file;
  expected.body_mass = model.body_mass;
  expected.body_ipos = model.body_ipos;
  expected.body_iquat = model.body_iquat;
  expected.body_inertia = model.body_inertia;
  expected.dof_armature = model.dof_armature;
  expected.dof_damping = model.dof_damping;
  expected.actuator_gainprm = model.actuator_gainprm;
  expected.actuator_biasprm = model.actuator_biasprm;
  set_const(expected);
  const std::vector<FieldView> f = model_fields(file), m = model_fields(model),
                               e = model_fields(expected);
  for (std::size_t i = 0; i < f.size(); ++i) {
    const char* name = f[i].info->name;
    if (listed(name, kWritten) || listed(name, kBookkeeping)) continue;
    if (!same(f[i], m[i]) && same(f[i], e[i])) return name;
  }
  return "";
}

#ifdef LEVER_HAVE_TINYXML2

bool quats_within(const FieldView& a, const FieldView& b, double bound) {
  if (a.size() != b.size()) return false;
  for (long i = 0; i < a.size(); ++i) {
    if (!(std::abs(a.doubles()[i] - b.doubles()[i]) <= bound)) return false;
  }
  return true;
}

std::string number(double x) { return detail::show(x + 0.0); }

std::string numbers(const double* x, int n) {
  std::string s;
  for (int i = 0; i < n; ++i) {
    if (i > 0) s += ' ';
    s += number(x[i]);
  }
  return s;
}

// entries up to the last nonzero one, at least `at_least`
template <class Array>
std::string used(const Array& prm, int at_least) {
  int count = static_cast<int>(prm.size());
  while (count > at_least && prm[static_cast<std::size_t>(count - 1)] == 0) --count;
  return numbers(prm.data(), count);
}

// A quaternion that the compiler's normalization (division by its computed length) turns into
// `q`: `q` itself when that is a fixed point, else `q` scaled by a length a few units in the last
// place from 1 (so that the division undoes the scaling), each component then moved by up to an
// ulp. Not every unit quaternion is the normalization of some quaternion (principal axes from an
// eigen-solver are unit only to rounding); then the candidate whose normalization is nearest,
// within kQuatRounding of `q` (write_string checks it).
detail::Quat quat_compiling_to(const Eigen::Vector4d& q) {
  const detail::Quat target{q[0], q[1], q[2], q[3]};
  const auto step = [](double x, int ulps) {
    for (; ulps > 0; --ulps) x = std::nextafter(x, HUGE_VAL);
    for (; ulps < 0; ++ulps) x = std::nextafter(x, -HUGE_VAL);
    return x;
  };
  constexpr int kScales = 4, kNudge = 1;
  detail::Quat best = target;
  double best_distance = HUGE_VAL;
  for (int k = 0; k <= 2 * kScales; ++k) {
    const double scale = step(1.0, k % 2 ? (k + 1) / 2 : -(k / 2));  // 1, then alternating sides
    for (int i = 0; i < 81; ++i) {  // every nudge in {-1, 0, 1}^4, none first
      const int nudge[4] = {i % 3, i / 3 % 3, i / 9 % 3, i / 27 % 3};
      detail::Quat candidate{};
      for (int c = 0; c < 4; ++c) {
        candidate[c] = step(q[c] * scale, nudge[c] == 2 ? -kNudge : nudge[c]);
      }
      detail::Quat compiled = candidate;
      detail::normalize(compiled.data(), 4);
      double distance = 0;
      for (int c = 0; c < 4; ++c) distance = std::max(distance, std::abs(compiled[c] - target[c]));
      if (distance < best_distance) {
        best = candidate;
        best_distance = distance;
      }
      if (distance == 0) return best;
    }
  }
  return best;
}

void collect(tinyxml2::XMLElement* e, std::vector<tinyxml2::XMLElement*>& out) {
  out.push_back(e);
  for (tinyxml2::XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
    collect(c, out);
  }
}

class Writer {
 public:
  Writer(const std::string& source, const std::string& filename) : filename_(filename) {
    if (doc_.Parse(source.c_str(), source.size()) != tinyxml2::XML_SUCCESS) {
      throw Error(filename + ": cannot read the model again (" + doc_.ErrorStr() + ").");
    }
    collect(doc_.RootElement(), elements_);
  }

  // the element the loader recorded at `at`, checked to be the one it names
  tinyxml2::XMLElement* element(const detail::Place& at) {
    if (at.element < 0 || at.element >= static_cast<int>(elements_.size()) ||
        at.tag != elements_[static_cast<std::size_t>(at.element)]->Name()) {
      throw Error(filename_ + ":" + std::to_string(at.line) + ": <" + at.tag +
                  ">: its element was not found again (lever's and tinyxml2's readers disagree).");
    }
    return elements_[static_cast<std::size_t>(at.element)];
  }

  // every <compiler> element's attribute `name`
  void edit_compiler(const char* name, const char* from, const char* to) {
    for (tinyxml2::XMLElement* c = doc_.RootElement()->FirstChildElement("compiler"); c;
         c = c->NextSiblingElement("compiler")) {
      const char* value = c->Attribute(name);
      if (value == nullptr || (from != nullptr && std::string(value) != from)) continue;
      if (to == nullptr) {
        c->DeleteAttribute(name);
      } else {
        c->SetAttribute(name, to);
      }
    }
  }

  // A body's <inertial>: the attributes whose compiled value changed, or all of them where the
  // element is new (`whole`) or its old values did not count (inertiafromgeom="true").
  void write_inertial(const Model& file, const Model& model, int b, const detail::Place& body,
                      const detail::Place& inertial, bool whole) {
    tinyxml2::XMLElement* e = nullptr;
    if (inertial.element >= 0) {
      e = element(inertial);
    } else {
      e = doc_.NewElement("inertial");
      element(body)->InsertFirstChild(e);
      whole = true;
    }
    if (whole || model.body_ipos[b] != file.body_ipos[b]) {
      e->SetAttribute("pos", numbers(model.body_ipos[b].data(), 3).c_str());
    }
    if (whole || model.body_mass[b] != file.body_mass[b]) {
      e->SetAttribute("mass", number(model.body_mass[b]).c_str());
    }
    if (whole || model.body_iquat[b] != file.body_iquat[b] ||
        model.body_inertia[b] != file.body_inertia[b]) {
      for (const char* a :
           {"fullinertia", "diaginertia", "quat", "axisangle", "xyaxes", "zaxis", "euler"}) {
        e->DeleteAttribute(a);
      }
      const detail::Quat quat = quat_compiling_to(model.body_iquat[b]);
      e->SetAttribute("quat", numbers(quat.data(), 4).c_str());
      e->SetAttribute("diaginertia", numbers(model.body_inertia[b].data(), 3).c_str());
    }
  }

  void write_joint(const Model& model, int j, const detail::Place& at) {
    tinyxml2::XMLElement* e = element(at);
    if (std::string(e->Name()) == "freejoint") {  // it takes no armature or damping
      e->SetName("joint");
      e->SetAttribute("type", "free");
    }
    const int d = model.jnt_dofadr[j];
    e->SetAttribute("armature", number(model.dof_armature[d]).c_str());
    e->SetAttribute("damping", number(model.dof_damping[d]).c_str());
  }

  void write_actuator(const Model& model, int a, const detail::Place& at) {
    tinyxml2::XMLElement* e = element(at);
    const std::string tag = e->Name();
    const double gain = model.actuator_gainprm[a][0];
    if (tag == "position") {
      e->SetAttribute("kp", number(gain).c_str());  // its bias -kp follows
    } else if (tag == "velocity") {
      e->SetAttribute("kv", number(gain).c_str());  // its bias -kv follows
    } else if (tag == "intvelocity" || tag == "damper" || tag == "cylinder" ||
               tag == "adhesion") {
      write_as_general(model, a, e);
    } else {
      if (tag == "motor") {  // a motor has no gain attribute: say what a <general> needs
        e->SetName("general");
        e->SetAttribute("dyntype", "none");
        e->SetAttribute("gaintype", "fixed");
        e->SetAttribute("biastype", "none");
      }
      e->SetAttribute("gainprm", used(model.actuator_gainprm[a], 1).c_str());
      if (model.actuator_biastype[a] == BiasType::kAffine) {
        e->SetAttribute("biasprm", used(model.actuator_biasprm[a], 3).c_str());
      }
    }
  }

  // A shortcut whose own attributes cannot hold any gain and bias (an intvelocity's, damper's,
  // cylinder's, adhesion's): rewritten as the <general> it compiles to, every parameter written,
  // with the limits it implied
  static void write_as_general(const Model& model, int a, tinyxml2::XMLElement* e) {
    const std::string tag = e->Name();
    for (const char* own : {"kp", "kv", "gain", "timeconst", "area", "diameter", "bias"}) {
      e->DeleteAttribute(own);
    }
    e->SetName("general");
    if (tag == "damper" || tag == "adhesion") e->SetAttribute("ctrllimited", "true");
    if (tag == "intvelocity") e->SetAttribute("actlimited", "true");
    const char* const dyn[] = {"none", "integrator", "filter", "muscle", "user"};
    const char* const gain[] = {"fixed", "affine", "muscle", "user"};
    const char* const bias[] = {"none", "affine", "muscle", "user"};
    e->SetAttribute("dyntype", dyn[static_cast<int>(model.actuator_dyntype[a])]);
    e->SetAttribute("gaintype", gain[static_cast<int>(model.actuator_gaintype[a])]);
    e->SetAttribute("biastype", bias[static_cast<int>(model.actuator_biastype[a])]);
    // whole: a shorter list would take its tail from the class's <general> default
    e->SetAttribute("dynprm", numbers(model.actuator_dynprm[a].data(), kDynParameters).c_str());
    e->SetAttribute("gainprm", numbers(model.actuator_gainprm[a].data(), kGainParameters).c_str());
    e->SetAttribute("biasprm", numbers(model.actuator_biasprm[a].data(), kBiasParameters).c_str());
  }

  std::string text() {
    tinyxml2::XMLPrinter printer;
    doc_.Print(&printer);
    return printer.CStr();
  }

 private:
  std::string filename_;
  tinyxml2::XMLDocument doc_;
  std::vector<tinyxml2::XMLElement*> elements_;  // in document order
};

bool inertial_differs(const Model& a, const Model& b, int body) {
  return a.body_mass[body] != b.body_mass[body] || a.body_ipos[body] != b.body_ipos[body] ||
         a.body_iquat[body] != b.body_iquat[body] || a.body_inertia[body] != b.body_inertia[body];
}

#endif

}  // namespace

std::string write_string(const std::string& source, const Model& model,
                         const std::string& filename) {
  detail::Locations where;
  const Model file = detail::load_located(source, filename, {}, &where);
  if (!where.included_files.empty()) {
    // the elements are found by their index in the one file written: included ones are elsewhere
    throw Error(filename + ": the model includes other files (" + where.included_files.front() +
                (where.included_files.size() > 1 ? ", ..." : "") +
                "), and writing a model back writes one file; put the included elements into the "
                "model file to write it.");
  }
  for (const detail::Place& body : where.body) {
    if (body.tag == "body" && body.element < 0 && body.line > 0) {
      // a <composite>'s bodies have no element of their own to write into
      throw Error(filename + ": body '" + body.name + "' is generated by a <composite> (line " +
                  std::to_string(body.line) +
                  "), and writing a model back writes only elements of the file; write the "
                  "composite's bodies out by hand to write it.");
    }
  }
  const std::string differs = unwritable_difference(file, model);
  if (!differs.empty()) {
    throw Error(filename + ": the model differs from the file in " + differs +
                ", which writing a model back does not write (only inertials, joint armature and "
                "damping, actuator gains).");
  }
#ifndef LEVER_HAVE_TINYXML2
  // the WebAssembly build reads MJCF with lever's own reader and has no XML writer
  throw Error(filename +
              ": writing a model needs tinyxml2, which this build of lever does not have.");
#else
  Writer writer(source, filename);
  std::vector<int> bodies;
  bool whole_inertials = false;  // the file's <inertial> values did not count as written
  for (int b = 1; b < model.nbody; ++b) {
    if (inertial_differs(file, model, b)) bodies.push_back(b);
  }
  if (!bodies.empty()) {
    // inertiafromgeom="true" ignores every <inertial>; "auto" keeps the ones written, so bodies
    // whose <inertial> "true" ignored are written with what they compiled to
    bool fromgeom_true = false;
    bool total_mass = false;  // settotalmass would rescale what is written: all written instead
    {
      tinyxml2::XMLDocument probe;
      probe.Parse(source.c_str(), source.size());
      for (tinyxml2::XMLElement* c = probe.RootElement()->FirstChildElement("compiler"); c;
           c = c->NextSiblingElement("compiler")) {
        const char* fromgeom = c->Attribute("inertiafromgeom");
        if (fromgeom != nullptr && std::string(fromgeom) == "true") fromgeom_true = true;
        if (c->Attribute("settotalmass") != nullptr && c->DoubleAttribute("settotalmass") > 0) {
          total_mass = true;
        }
      }
    }
    for (int b = 1; b < model.nbody; ++b) {
      const bool has_element = where.inertial[static_cast<std::size_t>(b)].element >= 0;
      if ((fromgeom_true && has_element) || (total_mass && model.body_mass[b] > 0)) {
        bodies.push_back(b);
      }
    }
    std::sort(bodies.begin(), bodies.end());
    bodies.erase(std::unique(bodies.begin(), bodies.end()), bodies.end());
    whole_inertials = fromgeom_true || total_mass;
    writer.edit_compiler("inertiafromgeom", "true", "auto");
    writer.edit_compiler("settotalmass", nullptr, nullptr);
  }
  for (const int b : bodies) {
    writer.write_inertial(file, model, b, where.body[static_cast<std::size_t>(b)],
                          where.inertial[static_cast<std::size_t>(b)], whole_inertials);
  }
  for (int j = 0; j < model.njnt; ++j) {
    const int d = model.jnt_dofadr[j];
    if (file.dof_armature[d] != model.dof_armature[d] ||
        file.dof_damping[d] != model.dof_damping[d]) {
      writer.write_joint(model, j, where.joint[static_cast<std::size_t>(j)]);
    }
  }
  for (int a = 0; a < model.nu; ++a) {
    if (file.actuator_gainprm[a] != model.actuator_gainprm[a] ||
        file.actuator_biasprm[a] != model.actuator_biasprm[a]) {
      writer.write_actuator(model, a, where.actuator[static_cast<std::size_t>(a)]);
    }
  }
  std::string text = writer.text();

  // what was written must say the model: loaded again, every field is the model's (its principal
  // axes to kQuatRounding, and what set_const derives from them as it derives it from those)
  const Model back = load_string(text, filename + " (written)");
  Model expected = model;
  if (quats_within(model_field(model, "body_iquat"), model_field(back, "body_iquat"),
                   kQuatRounding)) {
    expected.body_iquat = back.body_iquat;
    set_const(expected);
  }
  const std::vector<FieldView> m = model_fields(expected), w = model_fields(back);
  for (std::size_t i = 0; i < m.size(); ++i) {
    if (listed(m[i].info->name, kBookkeeping) || same(m[i], w[i])) continue;
    throw Error(filename + ": the model's " + m[i].info->name +
                " cannot be written into this file (read back, it differs); nothing was written.");
  }
  return text;
#endif
}

void write_file(const std::string& source_path, const Model& model, const std::string& out_path) {
  const std::string text = write_string(detail::read_model_file(source_path), model, source_path);
  // into a neighbour first, so that a failed write leaves no half file at out_path
  const std::string partial = out_path + ".partial";
  {
    std::ofstream out(partial, std::ios::binary | std::ios::trunc);
    out << text;
    if (!out.flush()) {
      std::error_code ignored;
      std::filesystem::remove(partial, ignored);
      throw Error(out_path + ": cannot write the model.");
    }
  }
  std::error_code ec;
  std::filesystem::rename(partial, out_path, ec);
  if (ec) {
    std::filesystem::remove(partial, ec);
    throw Error(out_path + ": cannot write the model.");
  }
}

}  // namespace lever::mjcf
