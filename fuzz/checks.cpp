// The fuzz targets' checks; see checks.hpp.
#include "checks.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <exception>
#include <filesystem>
#include <limits>
#include <new>
#include <vector>

#include <lever/lever.hpp>
#include <lever/mjcf.hpp>

namespace lever::fuzz {

namespace {

template <typename List>
bool all_finite(const List& list) {
  return std::all_of(list.begin(), list.end(), [](const auto& x) { return x.allFinite(); });
}

// The first output of data that is not finite, or "" (every output of forward and inverse).
std::string non_finite_output(const Data& d) {
  struct Field {
    const char* name;
    bool ok;
  };
  const Field fields[] = {
      {"qpos", d.qpos.allFinite()},
      {"qvel", d.qvel.allFinite()},
      {"xpos", all_finite(d.xpos)},
      {"xquat", all_finite(d.xquat)},
      {"xmat", all_finite(d.xmat)},
      {"xipos", all_finite(d.xipos)},
      {"ximat", all_finite(d.ximat)},
      {"site_xpos", all_finite(d.site_xpos)},
      {"site_xmat", all_finite(d.site_xmat)},
      {"xanchor", all_finite(d.xanchor)},
      {"xaxis", all_finite(d.xaxis)},
      {"subtree_com", all_finite(d.subtree_com)},
      {"cdof", all_finite(d.cdof)},
      {"cvel", all_finite(d.cvel)},
      {"M", d.M.allFinite()},
      {"qLDiagInv", d.qLDiagInv.allFinite()},
      {"actuator_length", d.actuator_length.allFinite()},
      {"actuator_velocity", d.actuator_velocity.allFinite()},
      {"actuator_force", d.actuator_force.allFinite()},
      {"qfrc_actuator", d.qfrc_actuator.allFinite()},
      {"qfrc_passive", d.qfrc_passive.allFinite()},
      {"qfrc_bias", d.qfrc_bias.allFinite()},
      {"qfrc_smooth", d.qfrc_smooth.allFinite()},
      {"qacc_smooth", d.qacc_smooth.allFinite()},
      {"qfrc_constraint", d.qfrc_constraint.allFinite()},
      {"qacc", d.qacc.allFinite()},
      {"qfrc_inverse", d.qfrc_inverse.allFinite()},
      {"efc_pos", d.efc_pos.head(d.nefc).allFinite()},
      {"efc_force", d.efc_force.head(d.nefc).allFinite()},
      {"efc_aref", d.efc_aref.head(d.nefc).allFinite()},
      {"energy", std::isfinite(d.energy[0]) && std::isfinite(d.energy[1])},
  };
  for (const Field& f : fields) {
    if (!f.ok) return f.name;
  }
  return "";
}

// After one engine call: finite outputs unless a warning says why not.
std::string after(const char* call, const Data& d) {
  if (warning_count(d) > 0) return "";
  const std::string field = non_finite_output(d);
  if (field.empty()) return "";
  return std::string(call) + " left " + field + " non-finite without recording a warning";
}

// Reads the fuzzer's bytes as choices and numbers; past the end everything reads as 0.
class Bytes {
 public:
  Bytes(const std::uint8_t* data, std::size_t size) : p_(data), n_(size) {}

  std::uint8_t byte() {
    if (n_ == 0) return 0;
    --n_;
    return *p_++;
  }

  // One number, mostly from a menu of hostile values, else raw bits or a small ordinary value.
  double number() {
    switch (byte() % 16) {
      case 0: return std::numeric_limits<double>::quiet_NaN();
      case 1: return std::numeric_limits<double>::infinity();
      case 2: return -std::numeric_limits<double>::infinity();
      case 3: return 1e300;
      case 4: return -1e300;
      case 5: return std::numeric_limits<double>::denorm_min();
      case 6: return 1e10;                        // MuJoCo's bound: not yet bad
      case 7: return std::nextafter(1e10, 2e10);  // just bad
      case 8: return std::numeric_limits<double>::max();
      case 9: return -0.0;
      case 10: return 1e9;  // large but good: what it gives may not be
      case 11: {
        double x = 0;
        std::uint8_t raw[sizeof x] = {};
        for (std::uint8_t& b : raw) b = byte();
        std::memcpy(&x, raw, sizeof x);
        return x;  // any bit pattern, signalling NaNs included
      }
      default: return static_cast<double>(static_cast<std::int8_t>(byte())) / 16.0;
    }
  }

  void fill(Eigen::Ref<Eigen::VectorXd> v) {
    for (Eigen::Index i = 0; i < v.size(); ++i) v[i] = number();
  }

 private:
  const std::uint8_t* p_;
  std::size_t n_;
};

struct Prepared {
  Model euler, rk4;
};

// Every model of the repository, loaded once per process, in both integrators.
const std::vector<Prepared>& models(const std::string& root) {
  static const std::vector<Prepared> loaded = [&root] {
    std::vector<std::string> files;
    for (const char* dir : {"models", "tests/models"}) {
      const std::filesystem::path p = std::filesystem::path(root) / dir;
      std::error_code ec;
      for (const auto& entry : std::filesystem::directory_iterator(p, ec)) {
        if (entry.path().extension() == ".xml") files.push_back(entry.path().string());
      }
    }
    std::sort(files.begin(), files.end());
    std::vector<Prepared> out;
    for (const std::string& f : files) {
      Prepared p{mjcf::load_file(f), {}};
      p.euler.opt.integrator = Integrator::kEuler;
      p.rk4 = p.euler;
      p.rk4.opt.integrator = Integrator::kRK4;
      out.push_back(std::move(p));
    }
    return out;
  }();
  return loaded;
}

// Contacts: more contacts or rows than the model's nconmax / njmax is refused with a
// StateError that says which size to raise (MuJoCo truncates with a warning); that is the
// documented answer to a state, not a finding. Any other StateError still is.
bool contact_capacity_refusal(const StateError& e) {
  const std::string what = e.what();
  return what.find("nconmax") != std::string::npos || what.find("njmax") != std::string::npos;
}

// Warnings a loaded model may raise at rest: a near-singular M (kInertia), as in MuJoCo, and a
// pair of geoms lever has no collision function for that touch (kContactUnsupported), which the
// loader named and the step records. A bad state at rest is not legitimate.
int legitimate_warnings(const Data& data) {
  return data.warning[static_cast<int>(Warning::kInertia)].number +
         data.warning[static_cast<int>(Warning::kContactUnsupported)].number;
}

std::string evaluate_loaded(const Model& loaded) {
  for (const Integrator integrator : {Integrator::kEuler, Integrator::kRK4}) {
    Model model = loaded;
    model.opt.integrator = integrator;
    set_const(model);  // it validated once; it must again
    Data data(model);
    try {
      forward(model, data);
    } catch (const StateError& e) {
      if (contact_capacity_refusal(e)) return "";
      throw;
    }
    if (warning_count(data) > legitimate_warnings(data)) {
      return "a loaded model raised a warning at qpos0: " + warning_text(data);
    }
    if (std::string f = non_finite_output(data); !f.empty()) {
      return "forward at qpos0 left " + f + " non-finite";
    }
    inverse(model, data);
    if (std::string f = after("inverse at qpos0", data); !f.empty()) return f;
    try {
      step(model, data);
    } catch (const StateError& e) {
      if (contact_capacity_refusal(e)) return "";
      throw;
    }
    if (std::string f = after("a step from qpos0", data); !f.empty()) return f;
  }
  return "";
}

}  // namespace

std::string check_mjcf(const std::uint8_t* data, std::size_t size) {
  const std::string xml(reinterpret_cast<const char*>(data), size);
  Model model;
  try {
    model = mjcf::load_string(xml, "fuzz.xml");
  } catch (const mjcf::ParseError& e) {
    if (e.problem().empty()) return std::string("a ParseError without a message: ") + e.what();
    return "";
  } catch (const Error& e) {
    return std::string("load_string threw a lever::Error that is not a ParseError: ") + e.what();
  } catch (const std::bad_alloc&) {
    return "load_string ran out of memory (std::bad_alloc)";
  } catch (const std::exception& e) {
    return std::string("load_string threw a non-lever exception: ") + e.what();
  }
  try {
    return evaluate_loaded(model);
  } catch (const std::exception& e) {
    return std::string("a loaded model failed to evaluate: ") + e.what();
  }
}

int engine_model_count(const std::string& models_dir) {
  return static_cast<int>(models(models_dir).size());
}

std::string check_engine(const std::uint8_t* data, std::size_t size,
                         const std::string& models_dir) {
  const std::vector<Prepared>& all = models(models_dir);
  if (all.empty()) return "no model of models/ or tests/models/ could be loaded";
  Bytes in(data, size);
  const Prepared& chosen = all[in.byte() % all.size()];
  const std::uint8_t flags = in.byte();
  const Model& model = (flags & 1) ? chosen.rk4 : chosen.euler;
  try {
    Data d(model);
    in.fill(d.qpos);
    in.fill(d.qvel);
    in.fill(d.ctrl);
    in.fill(d.qfrc_applied);
    forward(model, d);
    if (std::string f = after("forward", d); !f.empty()) return f;

    if (flags & 2) {
      in.fill(d.qacc);
      inverse(model, d);
      if (std::string f = after("inverse", d); !f.empty()) return f;
    }

    const int steps = 1 + (flags >> 2) % 4;
    for (int k = 0; k < steps; ++k) {
      step(model, d);
      if (std::string f = after("step", d); !f.empty()) return f;
      // controls for the next step, which may be bad again
      if (flags & 0x40) in.fill(d.ctrl);
    }
    return "";
  } catch (const StateError& e) {
    if (contact_capacity_refusal(e)) return "";  // a fuzzed state with more contacts than room
    return std::string("the engine threw: ") + e.what();
  } catch (const std::exception& e) {
    return std::string("the engine threw: ") + e.what();
  }
}

}  // namespace lever::fuzz
