// Resume: a solve stopped part-way and resumed from its checkpoint goes on where it stopped
// (the friction loop's restart point: the mixing history, the step control, the splitting
// variable, the frictionless reference's result), so that it takes the uninterrupted solve's
// steps and ends with its bits.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "gfmd/case/config.hpp"
#include "gfmd/case/outputs.hpp"
#include "gfmd/case/run.hpp"
#include "gfmd/case/run_dir.hpp"
#include "gfmd/core/error.hpp"

using namespace gfmd;
namespace fs = std::filesystem;

namespace {
// The thin-layer case of issue 41 (examples/fig2e_rough_layer_sweep.toml at p = 0.1 E*) on a
// 64^2 grid: about 90 inner iterations in 37 friction steps of the full-slip map.
const char* kThinLayer = R"(
[grid]
nx = 64
lx = 2.0
[elastic]
poisson = 0.49
thickness = 0.1
[indenter]
type = "selfaffine"
hurst = 0.8
lambda_long = 1.0
lambda_short = 0.125
rms_height = 0.01
seed = 0
[load]
pressure = 0.1
[friction]
coefficient = 1.0
)";

struct Resumed {
  CaseResult fresh, resumed;
  CheckpointProgress before;
};

// The case solved uninterrupted, then again stopped at friction step `stop_at` (of the
// sliding solve) and resumed from the checkpoint it left.
Resumed stop_and_resume(const Config& cfg, int stop_at, const std::string& tag) {
  Resumed out;
  out.fresh = run_case(cfg);
  EXPECT_TRUE(out.fresh.info.converged) << out.fresh.info.status;
  const fs::path dir = fs::temp_directory_path() / ("gfmd_resume41_" + tag + std::to_string(getpid()));
  fs::create_directories(dir);
  const std::string ck = (dir / "checkpoint.bin").string();
  RunOptions o;
  int outer = 0;
  o.progress = [&outer](const Progress& p) { outer = std::max(outer, p.outer); };
  o.stop_request = [&outer, stop_at] { return outer >= stop_at; };
  o.checkpoint_path = ck;
  EXPECT_THROW(run_case(cfg, o), Interrupted);
  ContactFields warm;
  EXPECT_TRUE(read_checkpoint(ck, cfg, warm, &out.before));
  EXPECT_TRUE(out.before.state && out.before.state->friction && out.before.state->reference);
  // A checkpoint of the older format, or a damaged one, is not used.
  {
    std::ifstream in(ck, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ContactFields f;
    std::string old = bytes;
    old[7] = '2';
    std::ofstream(dir / "old.bin", std::ios::binary) << old;
    EXPECT_FALSE(read_checkpoint((dir / "old.bin").string(), cfg, f));
    std::ofstream(dir / "short.bin", std::ios::binary) << bytes.substr(0, bytes.size() - 8);
    EXPECT_FALSE(read_checkpoint((dir / "short.bin").string(), cfg, f));
  }
  RunOptions r;
  r.warm_start = &warm;
  r.resumed = out.before;
  out.resumed = run_case(cfg, r);
  fs::remove_all(dir);
  return out;
}

void expect_same_solve(const Resumed& x) {
  const CaseResult& a = x.fresh;
  const CaseResult& b = x.resumed;
  ASSERT_TRUE(b.info.converged) << b.info.status;
  std::printf(
      "resume: fresh %d iterations (%d friction steps), stopped after %lld, total %d (%.3f of fresh)\n",
      a.info.iterations, a.info.outer_iterations, static_cast<long long>(x.before.iterations),
      b.info.iterations, static_cast<double>(b.info.iterations) / a.info.iterations);
  // The work: every session's iterations of the sliding solve against the uninterrupted one's.
  EXPECT_GT(x.before.iterations, a.reference->info.iterations);
  EXPECT_LE(b.info.iterations, 1.2 * a.info.iterations);
  // The uninterrupted solve's steps and bits.
  EXPECT_EQ(b.info.outer_iterations, a.info.outer_iterations);
  EXPECT_EQ(b.info.tangential_iterations, a.info.tangential_iterations);
  EXPECT_EQ(b.info.slip_derivative, a.info.slip_derivative);
  EXPECT_NEAR(b.observables.friction_coefficient, a.observables.friction_coefficient, 1e-8);
  EXPECT_EQ(b.observables.friction_coefficient, a.observables.friction_coefficient);
  EXPECT_TRUE(b.fields.pressure == a.fields.pressure);
  EXPECT_TRUE(b.fields.tx == a.fields.tx);
  EXPECT_TRUE(b.fields.ty == a.fields.ty);
  // The frictionless reference is the checkpoint's, not solved again.
  ASSERT_TRUE(b.reference.has_value());
  EXPECT_EQ(b.reference->info.iterations, a.reference->info.iterations);
  EXPECT_EQ(b.reference->observables.relative_contact_area, a.reference->observables.relative_contact_area);
  // The earlier sessions' work splits into the reference's and the sliding solve's, the latter
  // within the whole run's `iterations` (summary.json's resumed block says both).
  EXPECT_EQ(b.resumed.iterations, x.before.iterations);
  EXPECT_EQ(b.resumed.reference_iterations, a.reference->info.iterations);
  EXPECT_LE(b.resumed.iterations - b.resumed.reference_iterations, b.info.iterations);
  const nlohmann::json j = gfmd::summary_json(b);
  EXPECT_EQ(j["resumed"]["frictionless_iterations_before"].get<std::int64_t>(), a.reference->info.iterations);
}
}  // namespace

// Sliding: the full-slip map with Anderson mixing, stopped at about 70 % of its steps.
TEST(Resume, ThinLayerSlidingGoesOnWhereItStopped) {
  const Config cfg = parse_config(kThinLayer, "thin.toml");
  const Resumed x = stop_and_resume(cfg, 26, "slide");
  EXPECT_GE(x.fresh.info.iterations, 50);
  expect_same_solve(x);
}

// Tractive rolling (creepage 0.3): the stick-slip splitting from the start (its splitting
// variable, upwind2), with stick.
TEST(Resume, ThinLayerWithStickGoesOnWhereItStopped) {
  const Config cfg = parse_config(kThinLayer, "thin.toml", {"friction.creepage=0.3"});
  const Resumed x = stop_and_resume(cfg, 19, "stick");
  EXPECT_GT(x.fresh.info.tangential_iterations, 0);
  EXPECT_GT(x.fresh.info.stick_points, 0u);
  expect_same_solve(x);
}

namespace {
// examples/adhesive_sliding_sphere.toml on 64^2: a sphere sliding with adhesion under a uniform
// shear (tresca), the frictionless adhesive reference first.
// force_control: the load a force instead of the example's approach.
Config adhesive_sliding(const std::vector<std::string>& sets = {}, bool force_control = false) {
  std::vector<std::string> all = {"grid.nx=64"};
  all.insert(all.end(), sets.begin(), sets.end());
  const std::string path = std::string(GFMD_SOURCE_DIR) + "/examples/adhesive_sliding_sphere.toml";
  std::ifstream in(path);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (force_control) {
    const std::size_t at = text.find("\napproach = ");
    if (at != std::string::npos) text.replace(at, std::string("\napproach = ").size(), "\nforce = ");
  }
  return parse_config(text, path, all);
}
}  // namespace

// Adhesion with friction: the restart point holds the adhesive traction at the start of the
// friction step (each step's adhesive solve starts from it with a fresh mixer), and the
// reference's traction goes with its pressure: the uninterrupted solve's bits.
TEST(Resume, AdhesiveSlidingGoesOnWhereItStopped) {
  const Config cfg = adhesive_sliding();
  const Resumed x = stop_and_resume(cfg, 12, "adhesive");
  ASSERT_TRUE(x.before.state && x.before.state->adhesive);
  EXPECT_GE(x.fresh.info.outer_iterations, 14);  // the stop (step 12) inside the solve
  expect_same_solve(x);
  EXPECT_TRUE(x.resumed.fields.adhesion == x.fresh.fields.adhesion);
  EXPECT_EQ(x.resumed.observables.adhesive_force, x.fresh.observables.adhesive_force);
  // The restart point counts the adhesive steps done before it.
  EXPECT_GT(x.fresh.info.adhesion_steps, 0);
  EXPECT_EQ(x.resumed.info.adhesion_steps, x.fresh.info.adhesion_steps);
}

// A frictionless adhesive solve stopped inside its steps: the checkpoint holds the net pressure
// and the adhesive traction (not the repulsive pressure the steps work on) and the restart point
// of the step in progress (its repulsive pressure, the traction's mixing history and safeguard,
// the counts), so that the resumed solve takes the uninterrupted solve's steps and ends with its
// bits. Under approach control on the tensile branch; under a tensile load (load control: the
// first-touch solve, done before the restart point, is not done again); on a sliding viscoelastic
// body; with plastic saturation under load control (its bracket's start).
TEST(Resume, FrictionlessAdhesiveSolveGoesOnWhereItStopped) {
  const std::vector<std::vector<std::string>> cases = {
      {"load.approach=-0.004"},
      {"load.force=-0.001"},
      {"load.approach=-0.004", "elastic.viscoelastic=\"sls\"", "elastic.high_frequency_modulus=10",
       "elastic.relaxation_time=1", "friction.velocity=0.02"},
      {"load.force=0.01", "interaction.hardness=0.15"}};
  int with_history = 0;  // stopped with a mixing history to go on with
  for (const auto& sets : cases) {
    SCOPED_TRACE(sets.back());
    std::vector<std::string> all = {"friction.coefficient=0"};
    all.insert(all.end(), sets.begin(), sets.end());
    const bool force = sets.front().rfind("load.force", 0) == 0;
    const Config cfg = adhesive_sliding(all, force);
    const bool tensile = sets.back().rfind("interaction.hardness", 0) != 0;  // the capped case presses
    const CaseResult fresh = run_case(cfg);
    ASSERT_TRUE(fresh.info.converged) << fresh.info.status;
    if (tensile) {
      ASSERT_LT(fresh.observables.normal_force, 0.0);
    }
    const fs::path dir = fs::temp_directory_path() / ("gfmd_resume_adh" + std::to_string(getpid()));
    fs::create_directories(dir);
    const std::string ck = (dir / "checkpoint.bin").string();
    RunOptions o;
    // Stopped halfway through its CG iterations: the request is polled once per iteration
    // that has not converged (progress reports come only every 50).
    int polls = 0;
    o.stop_request = [&polls, &fresh] { return ++polls >= fresh.info.iterations / 2; };
    o.checkpoint_path = ck;
    EXPECT_THROW(run_case(cfg, o), Interrupted) << fresh.info.iterations << " iterations";
    ContactFields warm;
    CheckpointProgress before;
    ASSERT_TRUE(read_checkpoint(ck, cfg, warm, &before));
    ASSERT_TRUE(before.state && before.state->adhesive && before.state->adhesive_restart);
    EXPECT_EQ(before.state->adhesion.size(), cfg.grid.size());
    EXPECT_GT(before.state->adhesive_restart->step, 0);
    if (!before.state->adhesive_restart->mixer_slots.empty()) ++with_history;
    double pull = 0;
    for (const double a : before.state->adhesion) pull += a;
    EXPECT_GT(pull, 0.0) << "the traction of the interrupted steps";
    // Net, not repulsive: tensile where the cohesive zone pulls.
    EXPECT_LT(*std::min_element(warm.pressure.begin(), warm.pressure.end()), 0.0);
    if (!tensile) {
      EXPECT_TRUE(before.state->adhesive_restart->capped_found);
    }
    // The same file written again from what was read is the same file (the state round-trips).
    write_checkpoint((dir / "again.bin").string(), cfg, warm, before);
    {
      std::ifstream x(ck, std::ios::binary), y(dir / "again.bin", std::ios::binary);
      const std::string a((std::istreambuf_iterator<char>(x)), std::istreambuf_iterator<char>());
      const std::string b((std::istreambuf_iterator<char>(y)), std::istreambuf_iterator<char>());
      EXPECT_TRUE(a == b);
    }
    RunOptions r;
    r.warm_start = &warm;
    r.resumed = before;
    const CaseResult resumed = run_case(cfg, r);
    fs::remove_all(dir);
    ASSERT_TRUE(resumed.info.converged) << resumed.info.status;
    EXPECT_EQ(resumed.info.adhesion_steps, fresh.info.adhesion_steps);
    EXPECT_TRUE(resumed.fields.pressure == fresh.fields.pressure);
    EXPECT_TRUE(resumed.fields.adhesion == fresh.fields.adhesion);
    EXPECT_EQ(resumed.observables.normal_force, fresh.observables.normal_force);
    EXPECT_EQ(resumed.info.approach, fresh.info.approach);
    // Every session's work counted: at least the uninterrupted solve's.
    EXPECT_GE(resumed.info.iterations, fresh.info.iterations);
  }
  EXPECT_GE(with_history, 2);
}

// A checkpoint that is not used says why: missing, another grid, another case (the keys that
// differ, with both values), another format, truncated. gfmd run --resume prints the reason.
TEST(Resume, AnUnusableCheckpointSaysWhy) {
  const Config cfg = parse_config(kThinLayer, "thin.toml");
  const fs::path dir = fs::temp_directory_path() / ("gfmd_resume_why" + std::to_string(getpid()));
  fs::create_directories(dir);
  const std::string ck = (dir / "checkpoint.bin").string();
  ContactFields f;
  std::string why;
  EXPECT_FALSE(read_checkpoint(ck, cfg, f, nullptr, &why));
  EXPECT_EQ(why, "there is no checkpoint");
  ContactFields w;
  w.pressure.assign(cfg.grid.size(), 0.0);
  w.tx = w.pressure;
  w.ty = w.pressure;
  write_checkpoint(ck, cfg, w);
  EXPECT_TRUE(read_checkpoint(ck, cfg, f, nullptr, &why));
  const Config other = parse_config(kThinLayer, "thin.toml", {"friction.coefficient=0.5"});
  EXPECT_FALSE(read_checkpoint(ck, other, f, nullptr, &why));
  EXPECT_NE(why.find("another case: friction.coefficient (1.0 in the checkpoint, now 0.5)"),
            std::string::npos)
      << why;
  const Config finer = parse_config(kThinLayer, "thin.toml", {"grid.nx=32"});
  EXPECT_FALSE(read_checkpoint(ck, finer, f, nullptr, &why));
  EXPECT_NE(why.find("written for a "), std::string::npos) << why;
  {
    std::ifstream in(ck, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::ofstream(dir / "short.bin", std::ios::binary) << bytes.substr(0, bytes.size() - 8);
    bytes[7] = '2';
    std::ofstream(dir / "old.bin", std::ios::binary) << bytes;
  }
  EXPECT_FALSE(read_checkpoint((dir / "short.bin").string(), cfg, f, nullptr, &why));
  EXPECT_EQ(why, "the checkpoint is damaged or incomplete");
  EXPECT_FALSE(read_checkpoint((dir / "old.bin").string(), cfg, f, nullptr, &why));
  EXPECT_NE(why.find("another version of gfmd"), std::string::npos) << why;
  fs::remove_all(dir);
}
