// Least-squares identification of the base parameters (see lever/identify.hpp).
#include <lever/error.hpp>
#include <lever/identify.hpp>
#include <lever/kinematics.hpp>

#ifdef LEVER_HAVE_TINYXML2
#include <tinyxml2.h>
#endif
#include <Eigen/QR>
#include <Eigen/SVD>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>

namespace lever::identify {

namespace {

constexpr int kPerBody = 10;

std::string label_of(const std::string& name, int index) {
  return name.empty() ? std::string("#").append(std::to_string(index)) : name;
}

// One CSV line split at commas, with "quoted, fields" as `lever simulate` writes them.
std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char ch = line[i];
    if (quoted) {
      if (ch == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        fields.back() += '"';
        ++i;
      } else if (ch == '"') {
        quoted = false;
      } else {
        fields.back() += ch;
      }
    } else if (ch == '"') {
      quoted = true;
    } else if (ch == ',') {
      fields.emplace_back();
    } else if (ch != '\r') {
      fields.back() += ch;
    }
  }
  return fields;
}

double clamp(double x, const std::array<double, 2>& range) {
  return std::min(std::max(x, range[0]), range[1]);
}

// The force actuator a of the prior applies for a command ctrl at its joint's position q and
// velocity qd, as actuation() computes it: ctrl clamped to ctrlrange, gain * ctrl + bias with the
// gain and bias affine in length = gear q and velocity = gear qd (a motor: gain 1, no bias),
// clamped to forcerange. The gear that carries it to the joint is applied by the caller.
double force_from_ctrl(const Model& prior, int a, double ctrl, double q, double qd) {
  if (prior.actuator_ctrllimited[a]) ctrl = clamp(ctrl, prior.actuator_ctrlrange[a]);
  const double gear = prior.actuator_gear[a][0];
  const double length = gear * q, velocity = gear * qd;
  const auto& g = prior.actuator_gainprm[a];
  const double gain = prior.actuator_gaintype[a] == GainType::kAffine
                          ? g[0] + g[1] * length + g[2] * velocity
                          : g[0];
  double force = gain * ctrl;
  if (prior.actuator_biastype[a] == BiasType::kAffine) {
    const auto& b = prior.actuator_biasprm[a];
    force += b[0] + b[1] * length + b[2] * velocity;
  }
  if (prior.actuator_forcelimited[a]) force = clamp(force, prior.actuator_forcerange[a]);
  return force;
}

}  // namespace

Trajectory read_csv(const Model& prior, const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Error(path + ": cannot open the trajectory file.");
  std::string line;
  if (!std::getline(in, line)) throw Error(path + ":1: empty file: expected a header row.");
  const std::vector<std::string> header = split_csv(line);
  std::map<std::string, int> column;
  for (std::size_t c = 0; c < header.size(); ++c) column[header[c]] = static_cast<int>(c);
  const auto find = [&](const std::string& name, bool required) {
    const auto it = column.find(name);
    if (it != column.end()) return it->second;
    if (required) {
      throw Error(path + ":1: no column '" + name + "' (is the file from another model? " +
                  "the prior '" + prior.name + "' names its joints and motors as `lever " +
                  "simulate --csv` does)");
    }
    return -1;
  };
  const int nv = prior.nv, nu = prior.nu;
  const int time_col = find("time", true);
  std::vector<int> qpos_col(nv), qvel_col(nv), qacc_col(nv), constraint_col(nv);
  bool have_qacc = true, have_constraint = true;
  for (int j = 0; j < prior.njnt; ++j) {
    const std::string name = label_of(prior.jnt_name[j], j);
    const int d = prior.jnt_dofadr[j];
    qpos_col[d] = find("qpos[" + name + "]", true);
    qvel_col[d] = find("qvel[" + name + "]", true);
    qacc_col[d] = find("qacc[" + name + "]", false);
    constraint_col[d] = find("qfrc_constraint[" + name + "]", false);
    have_qacc = have_qacc && qacc_col[d] >= 0;
    have_constraint = have_constraint && constraint_col[d] >= 0;
  }
  std::vector<int> force_col(nu), ctrl_col(nu);
  bool have_force = true;
  for (int a = 0; a < nu; ++a) {
    const std::string name = label_of(prior.actuator_name[a], a);
    force_col[a] = find("actuator_force[" + name + "]", false);
    have_force = have_force && force_col[a] >= 0;
  }
  if (!have_force) {
    for (int a = 0; a < nu; ++a)
      ctrl_col[a] = find("ctrl[" + label_of(prior.actuator_name[a], a) + "]", true);
  }

  // the rows, every field a finite number
  std::vector<std::vector<double>> rows;
  int line_number = 1;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.empty() || line == "\r") continue;
    const std::vector<std::string> fields = split_csv(line);
    if (fields.size() != header.size()) {
      throw Error(path + ":" + std::to_string(line_number) + ": " + std::to_string(fields.size()) +
                  " fields, the header has " + std::to_string(header.size()) + ".");
    }
    std::vector<double> row(fields.size(), 0.0);
    const auto parse = [&](int c) {
      if (c < 0) return;
      const std::string& f = fields[static_cast<std::size_t>(c)];
      char* end = nullptr;
      const double x = std::strtod(f.c_str(), &end);
      if (f.empty() || end != f.c_str() + f.size() || !std::isfinite(x)) {
        throw Error(path + ":" + std::to_string(line_number) + ": column '" +
                    header[static_cast<std::size_t>(c)] + "': '" + f + "' is not a finite number.");
      }
      row[static_cast<std::size_t>(c)] = x;
    };
    parse(time_col);
    for (int d = 0; d < nv; ++d) {
      parse(qpos_col[d]);
      parse(qvel_col[d]);
      if (have_qacc) parse(qacc_col[d]);
      if (have_constraint) parse(constraint_col[d]);
    }
    for (int a = 0; a < nu; ++a) parse(have_force ? force_col[a] : ctrl_col[a]);
    rows.push_back(std::move(row));
  }

  // samples: every row, or all but the last when qacc is differenced
  const int count = static_cast<int>(rows.size()) - (have_qacc ? 0 : 1);
  if (count < 1) throw Error(path + ": too few rows (" + std::to_string(rows.size()) + ").");
  Trajectory t;
  t.time.resize(count);
  t.qpos.resize(nv, count);
  t.qvel.resize(nv, count);
  t.qacc.resize(nv, count);
  t.force.setZero(nv, count);
  const auto at = [&](int r, int c) {
    return rows[static_cast<std::size_t>(r)][static_cast<std::size_t>(c)];
  };
  for (int r = 0; r < count; ++r) {
    const int k = r;
    t.time[k] = at(r, time_col);
    for (int d = 0; d < nv; ++d) {
      t.qpos(d, k) = at(r, qpos_col[d]);
      t.qvel(d, k) = at(r, qvel_col[d]);
      if (have_qacc) {
        t.qacc(d, k) = at(r, qacc_col[d]);
      } else {
        // the velocity change over the step that starts at this row: what a semi-implicit
        // Euler step applied (its implicit-damping acceleration), a row's forces act over it
        const double dt = at(r + 1, time_col) - at(r, time_col);
        if (!(dt > 0)) {
          throw Error(path + ":" + std::to_string(r + 3) + ": time does not increase.");
        }
        t.qacc(d, k) = (at(r + 1, qvel_col[d]) - at(r, qvel_col[d])) / dt;
      }
      if (have_constraint) t.force(d, k) += at(r, constraint_col[d]);
    }
    for (int a = 0; a < nu; ++a) {
      const int d = prior.jnt_dofadr[prior.actuator_trnid[a]];
      // the row's actuator force, or its ctrl through the prior's actuator at the row's state
      const double force =
          have_force ? at(r, force_col[a])
                     : force_from_ctrl(prior, a, at(r, ctrl_col[a]), t.qpos(d, k), t.qvel(d, k));
      t.force(d, k) += prior.actuator_gear[a][0] * force;
    }
  }
  t.qacc_source = have_qacc ? "the qacc columns"
                            : "forward differences of qvel, (qvel[k+1] - qvel[k]) / (t[k+1] - "
                              "t[k]) (the last row dropped)";
  t.force_source = have_force ? "actuator_force times gear"
                              : "ctrl through the prior's actuators (ctrl clamped, gain * ctrl + "
                                "bias at the row's qpos and qvel, force clamped) times gear";
  if (!have_constraint) t.force_source += "; no qfrc_constraint columns: joint stops taken as zero";
  return t;
}

Result identify(const Model& prior, const Trajectory& data) {
  const int nv = prior.nv;
  const auto N = static_cast<int>(data.time.size());
  if (data.qpos.rows() != nv || data.qpos.cols() != N || data.qvel.cols() != N ||
      data.qacc.cols() != N || data.force.cols() != N || data.force.rows() != nv) {
    throw Error("identify: the trajectory's arrays do not fit the model (nv " + std::to_string(nv) +
                ", " + std::to_string(N) + " samples).");
  }
  Result r;
  r.base = base_parameters(prior);
  const int rank = r.base.rank;
  r.samples = N;
  r.equations = N * nv;
  if (r.equations < rank + 1) {
    throw Error("identify: " + std::to_string(r.equations) + " equations (samples x dofs) for " +
                std::to_string(rank) + " base parameters: too few samples.");
  }

  // the base regressor stacked over the samples, and the forces it must explain
  Data work(prior);
  Eigen::MatrixXd Y(nv, regressor_columns(prior));
  Eigen::MatrixXd W(r.equations, rank);
  Eigen::VectorXd target(r.equations);
  for (int k = 0; k < N; ++k) {
    work.qpos = data.qpos.col(k);
    work.qvel = data.qvel.col(k);
    kinematics(prior, work);
    regressor(prior, work, data.qacc.col(k), Y);
    W.middleRows(k * nv, nv) = r.base.base_regressor(Y);
    for (int j = 0; j < prior.njnt; ++j) {  // springs are the prior's
      const int q = prior.jnt_qposadr[j], d = prior.jnt_dofadr[j];
      target[k * nv + d] =
          data.force(d, k) + prior.jnt_stiffness[j] * (data.qpos(q, k) - prior.qpos_spring[q]);
    }
  }

  // least squares, standard errors, and the directions the data does not excite
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(W);
  r.estimate = qr.solve(target);
  r.prior = r.base.K * model_parameters(prior);
  const Eigen::VectorXd residual = target - W * r.estimate;
  r.residual_rms = std::sqrt(residual.squaredNorm() / r.equations);
  const double sigma2 = residual.squaredNorm() / (r.equations - rank);
  const Eigen::MatrixXd information = W.transpose() * W;
  const Eigen::MatrixXd covariance =
      sigma2 * information.ldlt().solve(Eigen::MatrixXd::Identity(rank, rank));
  r.standard_error = covariance.diagonal().cwiseMax(0.0).cwiseSqrt();

  Eigen::VectorXd norms = W.colwise().norm().transpose();
  for (int c = 0; c < rank; ++c) norms[c] = norms[c] > 0 ? norms[c] : 1.0;
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(W * norms.cwiseInverse().asDiagonal(),
                                              Eigen::ComputeThinV);
  const Eigen::VectorXd& s = svd.singularValues();
  for (int c = 0; c < rank; ++c) {
    if (s[c] >= 1e-6 * s[0]) continue;
    int dominant = 0;
    svd.matrixV().col(c).cwiseAbs().maxCoeff(&dominant);
    const std::string& name = r.base.names[static_cast<std::size_t>(dominant)];
    if (std::find(r.unexcited.begin(), r.unexcited.end(), name) == r.unexcited.end()) {
      r.unexcited.push_back(name);
    }
  }

  // the full parameters closest to the prior (scaled by each kind's size) with K pi = estimate
  const Eigen::VectorXd pi0 = model_parameters(prior);
  const int n = static_cast<int>(pi0.size());
  const int bodies = prior.nbody - 1;
  Eigen::VectorXd scale(n);
  const auto kind_of = [&](int c) {
    if (c >= kPerBody * bodies) return c < kPerBody * bodies + nv ? 4 : 5;  // armature, damping
    const int k = c % kPerBody;
    return k == 0 ? 0 : (k <= 3 ? 1 : 2);  // mass, first moment, inertia
  };
  double kind_size[6] = {0, 0, 0, 0, 0, 0};
  for (int c = 0; c < n; ++c)
    kind_size[kind_of(c)] = std::max(kind_size[kind_of(c)], std::abs(pi0[c]));
  for (int c = 0; c < n; ++c) {
    const double floor = kind_size[kind_of(c)] > 0 ? 1e-3 * kind_size[kind_of(c)] : 1e-6;
    scale[c] = std::max(std::abs(pi0[c]), floor);
  }
  const Eigen::MatrixXd KS = r.base.K * scale.asDiagonal();
  const Eigen::VectorXd step = KS.completeOrthogonalDecomposition().solve(r.estimate - r.prior);
  r.parameters = pi0 + scale.cwiseProduct(step);

  // inertia the data cannot see stays the prior's about the (new) centre of mass
  for (int b = 1; b <= bodies; ++b) {
    const int at = kPerBody * (b - 1);
    const double m = r.parameters[at], m0 = pi0[at];
    if (!(m > 0) || !(m0 > 0)) continue;
    const Eigen::Vector3d c = r.parameters.segment<3>(at + 1) / m;
    const Eigen::Vector3d c0 = pi0.segment<3>(at + 1) / m0;
    // the parallel-axis term of each inertia entry, in the order xx yy zz xy xz yz
    const auto shift = [](double mass, const Eigen::Vector3d& x) {
      Eigen::Matrix<double, 6, 1> p;
      p << mass * (x[1] * x[1] + x[2] * x[2]), mass * (x[0] * x[0] + x[2] * x[2]),
          mass * (x[0] * x[0] + x[1] * x[1]), -mass * x[0] * x[1], -mass * x[0] * x[2],
          -mass * x[1] * x[2];
      return p;
    };
    const Eigen::Matrix<double, 6, 1> central0 = pi0.segment<6>(at + 4) - shift(m0, c0);
    const Eigen::Matrix<double, 6, 1> moved = shift(m, c);
    bool free_diagonal = false;
    for (int e = 0; e < 6; ++e) {
      if (!r.base.K.col(at + 4 + e).isZero(0)) continue;
      r.parameters[at + 4 + e] = central0[e] + moved[e];
      free_diagonal = free_diagonal || e < 3;
    }
    // A prior at the edge of the rigid bodies (a thin rod: two equal moments, the third near
    // zero) leaves it as soon as a moment the data sees changes. Then raise the smallest unseen
    // moment by the least amount that makes the body rigid again (bisection): it changes no base
    // parameter.
    const auto rigid = [&](const InertialParameters& pb) {
      try {
        to_inertial(pb);
        return true;
      } catch (const ModelError&) {
        return false;
      }
    };
    InertialParameters pb = r.parameters.segment<kPerBody>(at);
    if (!free_diagonal || rigid(pb)) continue;
    int smallest = -1;  // the unseen diagonal entry with the smallest moment about the centre
    for (int e = 0; e < 3; ++e) {
      if (!r.base.K.col(at + 4 + e).isZero(0)) continue;
      const double central = pb[4 + e] - moved[e];
      if (smallest < 0 || central < pb[4 + smallest] - moved[smallest]) smallest = e;
    }
    const auto raised = [&](double t) {
      InertialParameters out = pb;
      out[4 + smallest] += t;
      return out;
    };
    // twice the triangle inequality's deficit is enough when the principal axes are the body's
    const Eigen::Vector3d central = pb.segment<3>(4) - moved.head<3>();
    const double deficit = std::max(0.0, 2 * central.maxCoeff() - central.sum());
    double lo = 0.0, hi = 2 * deficit + 1e-12 * central.cwiseAbs().maxCoeff();
    if (!rigid(raised(hi))) continue;  // not repairable this way: reported below
    for (int i = 0; i < 100; ++i) {
      const double mid = 0.5 * (lo + hi);
      (rigid(raised(mid)) ? hi : lo) = mid;
    }
    // and 1e-9 of the largest moment more: the compilers check A + B >= C without tolerance
    r.parameters.segment<kPerBody>(at) = raised(hi + 1e-9 * central.cwiseAbs().maxCoeff());
  }

  // armature and damping that came out negative by rounding only (an estimate of zero) are zero
  for (int c = kPerBody * bodies; c < n; ++c) {
    if (r.parameters[c] < 0 && r.parameters[c] > -1e-12 * std::max(1.0, kind_size[kind_of(c)])) {
      r.parameters[c] = 0.0;
    }
  }

  try {
    Model check = prior;
    set_model_parameters(check, r.parameters);
  } catch (const Error& e) {
    r.not_physical = e.what();
  }
  return r;
}

Model identified_model(const Model& prior, const Result& result) {
  Model out = prior;
  set_model_parameters(out, result.parameters);
  return out;
}

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
  if (doc.SaveFile(out_path.c_str()) != tinyxml2::XML_SUCCESS) {
    throw Error(out_path + ": cannot write the model.");
  }
#endif
}

}  // namespace lever::identify
