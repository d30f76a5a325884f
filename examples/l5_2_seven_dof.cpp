// Lesson 5.2: a 7-DOF arm with position servos: which poses are singular, and why the model
// needs armature to be stable at all.
//
// INPUT   panda7.xml (7-DOF Panda-class arm, <general> position servos, implicit integrator,
//         keyframe `home`)
// PROCESS (1) reset to the `home` keyframe and print the state it gives;
//         (2) the ee site's 6 x 7 Jacobian at home: singular values (Eigen's SVD), manipulability
//             sqrt(det(J J^T)) and condition number; then `lever check`'s section (7): the most
//             singular poses over the joint ranges and which joint axes align there;
//         (3) the step's linearisation at home by central differences of lever::step: spectral
//             radius under the model's implicit integrator and under explicit Euler; then
//             `lever check`'s section (8): the largest stable timesteps, and the smallest armature
//             that keeps Euler stable, confirmed by simulating with and without it
// OUTPUT  printed tables
//
// Run: l5_2_seven_dof [path/to/panda7.xml]     (default: panda7.xml of the installed lever)
#include <cmath>
#include <cstdio>
#include <string>

#include <lever/check.hpp>
#include <lever/lever.hpp>
#include <lever/mjcf.hpp>

namespace {

std::string list(const Eigen::VectorXd& v, const char* fmt = "%.4g") {
  std::string out = "[";
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    char buf[32];
    std::snprintf(buf, sizeof buf, fmt, v[i] + 0.0);
    out += (i ? " " : "") + std::string(buf);
  }
  return out + "]";
}

// The step's spectral radius at (qpos, qvel, ctrl): A = d x' / d x by central differences.
double step_radius(const lever::Model& model, const lever::Data& start) {
  const int n = model.nq + model.nv;
  const double eps = 1e-6;
  lever::Data d(model);
  Eigen::MatrixXd A(n, n);
  for (int i = 0; i < n; ++i) {
    Eigen::VectorXd x[2];
    for (int side = 0; side < 2; ++side) {
      lever::reset(model, d);
      d.qpos = start.qpos;
      d.qvel = start.qvel;
      d.ctrl = start.ctrl;
      (i < model.nq ? d.qpos[i] : d.qvel[i - model.nq]) += side ? -eps : eps;
      lever::step(model, d);
      x[side].resize(n);
      x[side] << d.qpos, d.qvel;
    }
    A.col(i) = (x[0] - x[1]) / (2 * eps);
  }
  return lever::eigenvalues(A).cwiseAbs().maxCoeff();
}

}  // namespace

int main(int argc, char** argv) {
  const std::string path = argc > 1 ? argv[1] : std::string(LEVER_MODELS_DIR) + "/panda7.xml";
  try {
    const lever::Model model = lever::mjcf::load_file(path);
    lever::Data data(model);

    // (1) the keyframe
    lever::reset_keyframe(model, data, "home");
    std::printf("(1) %s: %d joints, integrator %s, timestep %g s; keyframe home:\n",
                model.name.c_str(), model.njnt, lever::integrator_name(model.opt.integrator),
                model.opt.timestep);
    std::printf("    qpos %s\n    ctrl %s (position targets)\n", list(data.qpos).c_str(),
                list(data.ctrl).c_str());

    // (2) the Jacobian at home
    lever::forward(model, data);
    const int ee = model.site("ee");
    Eigen::MatrixXd jacp(3, model.nv), jacr(3, model.nv), J(6, model.nv);
    lever::jac_site(model, data, ee, jacp, jacr);
    J << jacp, jacr;
    const Eigen::VectorXd sigma = lever::singular_values(J);
    std::printf("(2) ee Jacobian (6 x %d) at home: singular values %s\n", model.nv,
                list(sigma).c_str());
    std::printf("    manipulability sqrt(det(J J^T)) = %.4g, condition number = %.4g\n",
                std::sqrt((J * J.transpose()).determinant()), sigma[0] / sigma[5]);

    const lever::check::SingularPoses singular = lever::check::check_singular_poses(model);
    for (const lever::check::SiteSingularity& site : singular.sites) {
      for (const lever::check::JacobianAt& at : site.worst) {
        std::printf("    %s: q = %s sigma_min %.3g, condition %.3g\n", at.where.c_str(),
                    list(at.q, "%.3f").c_str(), at.sigma[at.sigma.size() - 1], at.condition);
        for (const lever::check::JointAlignment& a : at.aligned) {
          std::printf("      %s and %s %s\n", a.first.c_str(), a.second.c_str(),
                      a.collinear ? "collinear" : "parallel");
        }
      }
    }

    // (3) stability of the step at home
    lever::reset_keyframe(model, data, "home");
    lever::Model euler = model;
    euler.opt.integrator = lever::Integrator::kEuler;
    std::printf("(3) spectral radius of the step at home: %s %.4f, Euler %.4f (stable below 1)\n",
                lever::integrator_name(model.opt.integrator), step_radius(model, data),
                step_radius(euler, data));
    const lever::check::StepStability st = lever::check::check_step_stability(model, "home");
    const lever::check::StabilityAt& home = st.states.front();
    std::printf("    largest stable timestep: %s %.4g s, Euler %.4g s\n", st.integrator.c_str(),
                home.max_dt_model, home.max_dt_euler);
    std::printf(
        "    smallest armature for a stable Euler step at %g s: %.4g kg m^2 on every joint\n",
        st.timestep, home.armature_all);
    for (size_t j = 0; j < st.joints.size(); ++j) {
      std::printf("      %s: %.4g with the others given %g x that\n", st.joints[j].c_str(),
                  home.armature_each[j], st.ample);
    }
    for (const lever::check::StabilityRun& run : home.runs) {
      std::string outcome = run.settled ? "settles" : "does not settle";
      if (!run.bounded()) outcome = "blows up at step " + std::to_string(run.blowup_step);
      std::printf(
          "    simulated %d steps, %s with armature %s: %s (|qvel| %.3g over the last tenth)\n",
          run.steps, run.integrator.c_str(), run.armature.c_str(), outcome.c_str(), run.final_qvel);
    }
  } catch (const lever::Error& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
  return 0;
}
