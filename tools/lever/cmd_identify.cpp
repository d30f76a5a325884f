// lever identify: the base inertial parameters (and armature, damping) of a model from a
// trajectory.
//
//   lever identify PRIOR.xml DATA.csv [--identify-gain all|NAME,..] [--known-mass BODY=KG]...
//                  [--write-model OUT.xml] [--json]
//
// DATA.csv is in `lever simulate --csv`'s columns (lever/identify.hpp's read_csv says which are
// needed). The identification is lever::identify's; this command parses and prints.
// --identify-gain: estimate these actuators' gains (gainprm[0], fixed-gain actuators) from the
// ctrl columns as well.
// --known-mass BODY=KG (repeatable): the body's mass is known, its centre of mass and inertia per
// unit mass the prior's; its parameters move to the known side (this pins the scale that every
// estimated gain shares with the inertia).
// --json: one object: base (name, prior, estimate, standard_error, physical per base parameter),
// samples, equations, dropped, gains (names), known_masses ({body, mass}), residual_rms,
// estimate_physical, physical_residual_rms, distance_to_prior ({body, distance}), unexcited
// (names), not_physical (null or why), qacc_source, force_source.
// Exit 0; 1 when some base parameter is not excited or the identified model is not physical
// (then --write-model writes nothing); bad input exits 2.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include <lever/identify.hpp>
#include <lever/mjcf.hpp>

#include "cli.hpp"
#include "commands.hpp"
#include "forward_state.hpp"

namespace lever::cli {

void declare_identify(CLI::App& command) {
  command.add_option("PRIOR.xml", "the prior: the model whose parameters are identified")
      ->type_name("FILE")
      ->required();
  command
      .add_option("DATA.csv",
                  "a trajectory in `lever simulate --csv`'s columns: time, qpos[j],\n"
                  "qvel[j], and qacc[j] (else qvel's forward difference),\n"
                  "actuator_force[m] (else ctrl[m] through the prior's actuators),\n"
                  "qfrc_constraint[j]")
      ->type_name("FILE")
      ->required();
  add_value(command, "identify-gain", "all|NAME,..",
            "estimate these actuators' gains (gainprm[0]; `all`: every fixed\n"
            "gain) from the ctrl columns; rows where their force may clamp\n"
            "are dropped. Keep one gain known: the data fixes the scale only\n"
            "through forces known in absolute terms")
      ->check(not_empty_check());
  add_value(command, "known-mass", "BODY=KG",
            "the body's mass is known (its centre of mass and inertia per unit\n"
            "mass are the prior's): pins the scale, so every gain can be\n"
            "estimated; repeatable")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  add_value(command, "write-model", "OUT.xml",
            "PRIOR.xml with the identified inertials, armature, damping, gains:\n"
            "the physical model (every pseudo-inertia positive definite) that\n"
            "fits the data, closest to the prior")
      ->check(not_empty_check());
  add_switch(command, "json", "one JSON object with every base parameter and the fit");
  command.footer(
      "Exit status: 0; 1 when a base parameter is not excited or the identified model is not\n"
      "physical (then --write-model writes nothing); 2 for bad input.");
}

int cmd_identify(const Args& command_line) {
  const auto [args, prior_path, prior] = begin("identify", command_line);
  const std::string& data_path = args.positional()[1];
  const identify::Trajectory data = identify::read_csv(prior, data_path);
  identify::Options options;
  if (args.has("identify-gain")) {
    options.gains = identify::gain_actuators_named(prior, args.get("identify-gain"));
  }
  for (const std::string& known : args.get_all("known-mass")) {
    options.known_masses.push_back(identify::known_mass_named(prior, known));
  }
  const auto body_label = [&](int b) {
    return prior.body_name[b].empty() ? std::string("#").append(std::to_string(b))
                                      : prior.body_name[b];
  };
  const identify::Result r = identify::identify(prior, data, options);

  if (args.has("json")) {
    Json json(stdout);
    json.begin_object();
    json.key("model").value(prior.name);
    json.key("samples").value(r.samples);
    json.key("equations").value(r.equations);
    json.key("dropped").value(r.dropped);
    json.key("gains").begin_array();
    for (const int a : r.gains) {
      json.value(prior.actuator_name[a].empty() ? std::string("#").append(std::to_string(a))
                                                : prior.actuator_name[a]);
    }
    json.end_array();
    json.key("known_masses").begin_array();
    for (const auto& [body, mass] : options.known_masses) {
      json.begin_object();
      json.key("body").value(body_label(body));
      json.key("mass").value(mass);
      json.end_object();
    }
    json.end_array();
    json.key("residual_rms").value(r.residual_rms);
    json.key("estimate_physical").value(r.estimate_physical);
    json.key("physical_residual_rms").value(r.physical_residual_rms);
    json.key("distance_to_prior").begin_array();
    for (int b = 1; b < prior.nbody; ++b) {
      json.begin_object();
      json.key("body").value(body_label(b));
      json.key("distance").value(r.distance_to_prior[static_cast<std::size_t>(b)]);
      json.end_object();
    }
    json.end_array();
    json.key("qacc_source").value(data.qacc_source);
    json.key("force_source").value(data.force_source);
    json.key("base").begin_array();
    for (int k = 0; k < r.base.rank; ++k) {
      json.begin_object();
      json.key("name").value(r.base.names[static_cast<std::size_t>(k)]);
      json.key("prior").value(r.prior[k]);
      json.key("estimate").value(r.estimate[k]);
      json.key("standard_error").value(r.standard_error[k]);
      json.key("physical").value(r.physical_estimate[k]);
      json.end_object();
    }
    json.end_array();
    json.key("unexcited").begin_array();
    for (const std::string& name : r.unexcited) json.value(name);
    json.end_array();
    json.key("not_physical");
    if (r.not_physical.empty()) {
      json.value(std::numeric_limits<double>::quiet_NaN());  // written as null
    } else {
      json.value(r.not_physical);
    }
    json.end_object();
    json.newline();
  } else {
    std::printf("prior %s (%s), data %s: %d samples, %d equations\n", prior.name.c_str(),
                prior_path.c_str(), data_path.c_str(), r.samples, r.equations);
    std::printf("qacc from %s; joint forces from %s\n", data.qacc_source.c_str(),
                data.force_source.c_str());
    if (!r.gains.empty()) {
      std::printf(
          "%d gains estimated from ctrl; %d equations dropped where their force may clamp\n",
          static_cast<int>(r.gains.size()), r.dropped);
    }
    std::printf("\n");
    std::printf(
        "%d base parameters (SI units: kg, kg m, kg m^2, N m s/rad; gains per unit ctrl):\n",
        r.base.rank);
    std::printf("  %14s %14s %14s  %s\n", "prior", "estimate", "std. error", "combination");
    for (int k = 0; k < r.base.rank; ++k) {
      std::printf("  %14s %14s %14s  %s\n", num(r.prior[k], "%.8g").c_str(),
                  num(r.estimate[k], "%.8g").c_str(), num(r.standard_error[k], "%.3g").c_str(),
                  r.base.names[static_cast<std::size_t>(k)].c_str());
    }
    std::printf("\nresidual: rms %s (N m or N)\n", num(r.residual_rms, "%.3g").c_str());
    for (const auto& [body, mass] : options.known_masses) {
      std::printf("known: %s's mass %s kg (centre of mass and inertia per kg as the prior's)\n",
                  body_label(body).c_str(), num(mass, "%.8g").c_str());
    }
    if (r.estimate_physical) {
      std::printf(
          "physical: the least-squares estimate is a rigid-body model's (every body's "
          "pseudo-inertia positive definite)\n");
    } else {
      std::printf(
          "physical: the least-squares estimate is NOT a rigid-body model's; the nearest "
          "physical fit raises the residual rms from %s to %s (by %s)\n",
          num(r.residual_rms, "%.8g").c_str(), num(r.physical_residual_rms, "%.8g").c_str(),
          num(r.physical_residual_rms - r.residual_rms, "%.2g").c_str());
      std::printf("  %14s %14s %14s  %s\n", "estimate", "physical", "moved (SE)", "combination");
      for (int k = 0; k < r.base.rank; ++k) {
        const double moved = r.physical_estimate[k] - r.estimate[k];
        if (std::abs(moved) <= 1e-9 * std::max(1.0, std::abs(r.estimate[k]))) continue;
        std::printf(
            "  %14s %14s %14s  %s\n", num(r.estimate[k], "%.8g").c_str(),
            num(r.physical_estimate[k], "%.8g").c_str(),
            r.standard_error[k] > 0 ? num(moved / r.standard_error[k], "%.3g").c_str() : "-",
            r.base.names[static_cast<std::size_t>(k)].c_str());
      }
    }
    std::printf(
        "closest to the prior among the physical fits: geodesic distance of each body's "
        "pseudo-inertia from the prior's\n");
    for (int b = 1; b < prior.nbody; ++b) {
      if (!(prior.body_mass[b] > 0)) continue;
      std::printf("  %-16s %s\n", body_label(b).c_str(),
                  num(r.distance_to_prior[static_cast<std::size_t>(b)], "%.4g").c_str());
    }
  }
  for (const std::string& name : r.unexcited) {
    std::fprintf(stderr, "lever identify: warning: the data barely excites %s\n", name.c_str());
  }
  if (!r.not_physical.empty()) {
    std::fprintf(stderr, "lever identify: the identified parameters are not a physical model: %s\n",
                 r.not_physical.c_str());
  }
  if (args.has("write-model")) {
    if (!r.not_physical.empty()) {
      std::fprintf(stderr, "lever identify: no model written\n");
    } else {
      identify::write_model(prior_path, identify::identified_model(prior, r),
                            args.get("write-model"));
    }
  }
  return r.unexcited.empty() && r.not_physical.empty() ? kOk : kFindings;
}

}  // namespace lever::cli
