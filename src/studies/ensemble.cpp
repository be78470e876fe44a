// Seed ensembles of a self-affine case with flow. See include/gfmd/studies/ensemble.hpp.
#include "gfmd/studies/ensemble.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <set>

#include "gfmd/case/outputs.hpp"
#include "gfmd/case/run.hpp"
#include "gfmd/case/run_dir.hpp"
#include "gfmd/case/run_directory.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/files.hpp"
#include "gfmd/core/mpi.hpp"
#include "gfmd/flow/flow.hpp"
#include "gfmd/version.hpp"

namespace gfmd {

namespace fs = std::filesystem;

Config check_ensemble(const std::string& case_path, const EnsembleOptions& opts) {
  if (opts.first_seed < 0 || opts.last_seed < opts.first_seed)
    throw InputError("--seeds", "expected 0 <= FIRST <= LAST");
  if (opts.last_seed - opts.first_seed >= kMaxEnsembleSeeds)
    throw InputError("--seeds", "at most " + std::to_string(kMaxEnsembleSeeds) + " seeds per ensemble");
  const Config probe = load_config(case_path, opts.overrides);
  if (probe.indenter.type != "selfaffine")
    throw InputError(case_path, "an ensemble needs a selfaffine indenter");
  return probe;
}

nlohmann::json run_ensemble(const std::string& case_path, const std::string& dir,
                            const EnsembleOptions& opts) {
  const Config probe = check_ensemble(case_path, opts);
  const bool pairs = probe.friction.coefficient > 0;
  nlohmann::json j;
  j["seeds"] = nlohmann::json::array();
  // Rank 0 holds the directory: new seeds go to its staging area and are published with
  // ensemble.json at the end; published seeds of the same input are reused where they are, and
  // an interrupted or failed attempt leaves its finished seeds in the staging area for the next.
  std::optional<RunDirectory> rd;
  on_root([&] {
    OutputDirOptions as_ensemble = opts.directory;
    as_ensemble.kind = "ensemble";
    rd.emplace(dir, as_ensemble, /*keep_staging=*/true);
    rd->begin();
  });
  const std::string stage = rd ? rd->staging() : std::string();
  std::set<std::string> reused_names;
  std::vector<double> kx, ky, kx0, ky0, ac, ac0, mus;
  try {
    for (int seed = opts.first_seed; seed <= opts.last_seed; ++seed) {
      for (int variant = 0; variant < (pairs ? 2 : 1); ++variant) {
        std::vector<std::string> ss = opts.overrides;
        ss.push_back("indenter.seed=" + std::to_string(seed));
        ss.push_back("flow.direction=\"both\"");
        if (variant == 1) {  // frictionless: no coefficient, and no law (whose keys go with it)
          ss.push_back("friction.law=\"coulomb\"");
          ss.push_back("friction.coefficient=0");
        }
        const Config c = reparse_config(probe, ss);  // the text the ensemble started from
        const std::string name = (variant ? "frictionless_seed_" : "seed_") + std::to_string(seed);
        if (mpi::from_root(mpi::root() && opts.stop_request && opts.stop_request() ? 1 : 0) == 1)
          throw Interrupted("interrupted before " + name);
        const std::string published = (fs::path(dir) / name).string();
        std::string d = (fs::path(stage) / name).string();
        double x = 0, y = 0, a = 0, mu = 0;
        // A seed finished earlier with the same input is read back (as sweep points are); under
        // mpirun rank 0 reads it and hands the figures on.
        std::string found;
        if (mpi::root()) {
          if (!finished_summary(d, c) && finished_summary(published, c)) {
            d = published;
            reused_names.insert(name);
          }
          if (const auto old = finished_summary(d, c)) {
            std::ifstream fj(fs::path(d) / "flow.json");
            try {
              const nlohmann::json fl = nlohmann::json::parse(fj);
              found = nlohmann::json::array({fl.at("conductivity_x").get<double>(),
                                             fl.at("conductivity_y").get<double>(),
                                             old->at("relative_contact_area").get<double>(),
                                             old->value("friction_coefficient", 0.0)})
                          .dump();
            } catch (const std::exception&) {
              found.clear();  // incomplete: solve again
            }
          }
          if (found.empty()) {
            reused_names.erase(name);
            d = (fs::path(stage) / name).string();
          }
        }
        found = mpi::from_root(found);
        const bool reused = !found.empty();
        if (reused) {
          const nlohmann::json v = nlohmann::json::parse(found);
          x = v[0];
          y = v[1];
          a = v[2];
          mu = v[3];
        } else {
          RunOptions ro;
          ro.keep_stress_fields = outputs_need_stress_fields(c);
          ro.whole_solution = false;  // no warm start: rank 0 gathers only what the outputs write
          ro.stop_request = opts.stop_request;
          const CaseResult r = run_case(c, ro);
          if (!r.info.converged) throw SolveError("seed " + std::to_string(seed) + ": " + r.info.status);
          on_root([&] {
            make_gfmd_directory(d);
            clear_run_outputs(d);
            write_outputs(r, d);
          });
          x = r.leakage->json["conductivity_x"];
          y = r.leakage->json["conductivity_y"];
          a = r.observables.relative_contact_area;
          mu = c.friction.coefficient > 0 ? r.observables.friction_coefficient : 0.0;
        }
        (variant ? kx0 : kx).push_back(x);
        (variant ? ky0 : ky).push_back(y);
        (variant ? ac0 : ac).push_back(a);
        if (variant == 0 && c.friction.coefficient > 0) mus.push_back(mu);
        // mu_c: the variant's Coulomb coefficient; friction_coefficient: the solved mu, as in
        // the seed's summary.json.
        j["seeds"].push_back({{"seed", seed},
                              {"mu_c", c.friction.coefficient},
                              {"friction_coefficient", mu},
                              {"relative_contact_area", a},
                              {"conductivity_x", x},
                              {"conductivity_y", y}});
        if (opts.on_seed) {
          char line[160];
          std::snprintf(line, sizeof line, "seed %d%s: a_c = %.4f, K_x = %.4e, K_y = %.4e%s", seed,
                        variant ? " (frictionless)" : "", a, x, y, reused ? " (finished earlier)" : "");
          opts.on_seed(line);
        }
      }
    }
  } catch (const SolveError& e) {  // Interrupted too
    on_root([&] { (void)rd->interrupt(e.what(), /*keep_staging=*/true); });
    throw;
  }
  // Mean and sample standard deviation; with the Bruggeman combination for conductivities.
  const auto spread = [](const std::vector<double>& v) {
    double m = 0, m2 = 0;
    for (double x : v) m += x;
    m /= std::max<std::size_t>(v.size(), 1);
    for (double x : v) m2 += (x - m) * (x - m);
    return nlohmann::json{{"mean", m}, {"std", v.size() > 1 ? std::sqrt(m2 / (v.size() - 1)) : 0.0}};
  };
  const auto stats = [&spread](const std::vector<double>& v) {
    nlohmann::json j = spread(v);
    j["bruggeman"] = bruggeman_2d(v);
    return j;
  };
  j["conductivity_x"] = stats(kx);
  j["conductivity_y"] = stats(ky);
  j["relative_contact_area"] = stats(ac);
  if (!mus.empty()) j["friction_coefficient"] = spread(mus);
  if (pairs) {
    j["frictionless"] = {{"conductivity_x", stats(kx0)},
                         {"conductivity_y", stats(ky0)},
                         {"relative_contact_area", stats(ac0)}};
    const double bx = j["conductivity_x"]["bruggeman"], by = j["conductivity_y"]["bruggeman"];
    const double bx0 = j["frictionless"]["conductivity_x"]["bruggeman"],
                 by0 = j["frictionless"]["conductivity_y"]["bruggeman"];
    j["relative_change_x"] = bx0 > 0 ? bx / bx0 - 1 : 0.0;
    j["relative_change_y"] = by0 > 0 ? by / by0 - 1 : 0.0;
    std::vector<double> rx, ry;
    for (std::size_t i = 0; i < kx.size(); ++i) {
      if (kx0[i] > 0) rx.push_back(kx[i] / kx0[i] - 1);
      if (ky0[i] > 0) ry.push_back(ky[i] / ky0[i] - 1);
    }
    j["relative_change_x_per_seed"] = spread(rx);
    j["relative_change_y_per_seed"] = spread(ry);
  }
  j["input"] = probe.to_json();
  j["version"] = kVersion;
  j["git_commit"] = kGitCommit;
  on_root([&] {
    write_text_atomic((fs::path(stage) / "ensemble.json").string(), j.dump(2) + "\n");
    if (opts.before_publish) opts.before_publish(stage);
    if (opts.stop_request && opts.stop_request()) {
      (void)rd->interrupt("interrupted while drawing the maps", /*keep_staging=*/true);
      throw Interrupted("interrupted while drawing the maps");
    }
    rd->publish([&](const std::string& n) { return is_gfmd_output_name(n) && reused_names.count(n) == 0; });
  });
  return j;
}

}  // namespace gfmd
