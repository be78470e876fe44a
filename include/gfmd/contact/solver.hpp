// Steady-state contact solve between a rigid indenter and the elastic body.
//
// Unknowns: the pressure p(r) >= 0 the indenter exerts on the body and, when sliding
// with friction, the tangential traction tau(r) = mu_c p(r) s(r) on the body, where
// s is the unit slip direction of the body under the indenter (see friction below).
// Displacements follow from the compliance: u = C * (tau_x, tau_y, -p).
//
// Interaction (SPEC §4): harmonic overlap repulsion p = k max(0, -g), with gap
// g = g0 - delta - u_z, g0 = max(h) - h the separation at first touch and delta the
// approach of the indenter. Written as a complementarity problem with the augmented
// compliance C_zz + 1/k, it is solved by the Polonsky-Keer constrained conjugate
// gradient method (load or approach control); k = inf is the hard wall.
//
// Friction (SPEC §4-5): the slip velocity of the body relative to the indenter is
// -v0 (e_s + (e_s.grad) u) (the indenter moves along +e_s over the body); the Coulomb
// traction on the body opposes it: tau = mu_c p s, s = (e_s + (e_s.grad)u)/|...|, or
// regularised near stick (FrictionParams::regularization: tau = mu_c p v / eps where the
// slip speed |v| < eps), where the exact law makes the slip direction ill-conditioned.
// The non-conservative traction enters as a fixed point: for a given tau the normal
// problem is the same convex problem with g0 replaced by g0 - w, w = C_z. tau (the
// normal displacement friction causes); then tau is rebuilt from the new p and u.
// Every outer step solves the normal problem to a tolerance tied to the outer residual.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "gfmd/contact/anderson.hpp"
#include "gfmd/contact/cohesive_law.hpp"
#include "gfmd/contact/friction_law.hpp"
#include "gfmd/contact/interaction.hpp"
#include "gfmd/core/fft.hpp"
#include "gfmd/core/fields.hpp"
#include "gfmd/elastic/elastic.hpp"
#include "gfmd/surface/topography.hpp"

namespace gfmd {

struct FrictionParams {
  double coefficient = 0.0;  // mu_c (a speed-dependent law's kinetic coefficient mu_k)
  // The law (contact/friction_law.hpp): Coulomb's constant mu_c, or a coefficient that
  // depends on the slip speed, mu_c * f(|v|); every law gives tau = mu(|v|) p v/|v| in slip.
  FrictionLaw law;
  double direction_deg = 0.0;  // sliding direction of the indenter, degrees from +x
  // Regularised Coulomb law near stick: where the slip speed |v_slip|/v0 falls below this
  // value, the traction is mu_c p v_slip / regularization (it vanishes with the slip
  // instead of jumping); above it the law is exact Coulomb. 0: exact Coulomb everywhere.
  double regularization = 0.0;
  // Creepage xi: the rigid part of the slip velocity is xi v0 e_s (1 = sliding; small xi =
  // tractive rolling, with stick where the traction stays inside the friction disc).
  double creepage = 1.0;
  // Lateral creepage eta: a rigid slip eta v0 e_perp across the rolling direction, e_perp =
  // e_s turned by +90 degrees (Kalker's lateral creepage; 0 = none).
  double lateral_creepage = 0.0;
  // How (e_s.grad) u is discretised in the slip velocity; unset = automatic: second-order
  // upwind for rolling; for sliding (xi = 1, eta = 0) spectral while every contact point
  // slips, second-order upwind once the solve meets stick (docs/solver.md; the solve's
  // choice is SolveInfo::slip_derivative).
  std::optional<SlipDerivative> slip_derivative;
  // Step gamma / E* of the stick-slip (Douglas-Rachford) iteration of the exact law; 0 picks
  // it from the body's in-plane compliance.
  double stick_step = 0.0;
  // Anderson depth on the splitting variable of the stick-slip iteration (safeguarded:
  // an extrapolated step is kept only where it lowers the splitting residual), with its own
  // relaxation and inner tolerances (docs/solver.md); 0: plain Douglas-Rachford.
  int stick_acceleration = 0;
  [[nodiscard]] bool regularized() const { return regularization > 0; }
  [[nodiscard]] bool rolling() const { return creepage != 1.0 || lateral_creepage != 0.0; }
  [[nodiscard]] SlipDerivative derivative() const {
    return slip_derivative.value_or(rolling() ? SlipDerivative::Upwind2 : SlipDerivative::Spectral);
  }
  // The rigid slip xi e_s + eta e_perp for the unit vector e_s = (ex, ey).
  [[nodiscard]] std::array<double, 2> rigid_slip(double ex, double ey) const {
    return {creepage * ex - lateral_creepage * ey, creepage * ey + lateral_creepage * ex};
  }
};

enum class LoadMode { Force, Pressure, Approach };
struct LoadParams {
  LoadMode mode = LoadMode::Force;
  double value = 0.0;  // force, mean pressure, or approach
};

enum class ViscoMethod { Auto, ActiveSet, Splitting };
// The viscoelastic active set's GMRES restart length (its Krylov basis holds one more vector on
// the contact's points), and its memory per grid point with half the grid in contact, as the
// case's memory estimate allows for (the basis and the set's indices there, three work fields).
inline constexpr int kActiveSetKrylov = 50;
inline constexpr double kActiveSetBytesPerPoint =
    0.5 * ((kActiveSetKrylov + 1) * 8.0 + 8.0) + 3.0 * 8.0 + 1.0;

struct SolverParams {
  double tolerance = 1e-8;                  // gap residual, relative pressure change, relative tau change
  int max_iterations = 20000;               // total inner (conjugate-gradient) iterations
  int max_outer = 2000;                     // friction fixed-point steps
  int max_tangential = 20000;               // stick-slip steps per friction step (exact law)
  int anderson = 10;                        // Anderson mixing depth of the friction fixed point (0: none)
  double mixing = 0.5;                      // relaxation of the friction fixed point, in (0, 1]
  Planner fft_planner = Planner::Estimate;  // FFTW planner of the solver's transforms
  // A sliding viscoelastic body's normal problem (solver.viscoelastic_method; docs/solver.md,
  // "Viscoelastic bodies"): the active set with GMRES on the non-symmetric operator, or the
  // splitting into a symmetric part and a held rest; Auto: the active set without friction, the
  // splitting in the friction loop (measured). With a hardness cap the splitting runs always.
  ViscoMethod visco_method = ViscoMethod::Auto;
};

// The first physics of this problem the cuda backend does not compute, as {key, why}
// (ContactSolver refuses "cuda" with it; solver.backend = "auto" then chooses the cores);
// {} where the device computes it all.
std::pair<std::string, std::string> device_lacks(const InteractionParams& inter, const FrictionParams& fric,
                                                 bool viscoelastic, bool elastic_indenter = false);

struct SolveInfo {
  bool converged = false;
  std::string status;             // "converged", "not converged: ...", ...
  int iterations = 0;             // inner conjugate-gradient iterations in all (the viscoelastic
                                  // active set: its operator products, FFT pairs)
  int outer_iterations = 0;       // friction fixed-point steps
  int tangential_iterations = 0;  // stick-slip (Douglas-Rachford) steps of the exact law, in all
  std::size_t stick_points = 0;   // contact points that stick
  // The friction loop's mixing history at its end: solver.anderson, or deeper where the fixed
  // point stalled (deepened_history, docs/solver.md); 0 without friction or mixing.
  int history_depth = 0;
  // Adhesion: the cohesive-set steps (majorize-minimize over the set where the gap is below
  // the range; each a repulsive solve) the solve took; 0 without adhesion.
  int adhesion_steps = 0;
  // The adhesive solve found that its load has no state (a tensile load beyond the pull-off, or
  // a load and pull beyond the cap): the friction loop ends there.
  bool no_state = false;
  // Adhesion: the energy of the solution (per the solve's own discretisation, so that along a
  // load path d(energy)/d(approach) = normal_force): the elastic energy 1/2 sum p_net C p_net dA,
  // the adhesive energy sum phi(g) dA (phi = -w + the cell law's integral over the gap: -w in
  // contact, 0 beyond the range) and the harmonic repulsion's 1/2 sum p_rep^2/k dA (0 for the
  // hard wall); energy is their sum. 0 without adhesion.
  double elastic_energy = 0.0, adhesive_energy = 0.0, energy = 0.0;
  // A viscoelastic body (elastic.viscoelastic): the splitting steps (each a Polonsky-Keer solve
  // on the storage part of the response; viscoelastic.cpp) and the hysteresis force from the
  // spectrum of the final tractions t = (tau_x, tau_y, -p), sum over q of (q.e_s) Im(E0/E(omega))
  // t~* C(q) t~ dA/N (C the elastic compliance): the power the body dissipates per sliding speed
  // (its balance with the work the tractions do on the body is a test). 0 for an elastic body.
  int viscoelastic_steps = 0;
  double hysteresis_dissipation = 0.0;
  // The slip derivative the solution was computed with (FrictionParams::slip_derivative, or
  // the automatic choice: upwind2 where the solve met stick, else spectral for sliding).
  SlipDerivative slip_derivative = SlipDerivative::Spectral;
  double residual = 0.0;        // independent force-balance residual of the final state
  double residual_bound = 0.0;  // converged needs residual <= max(1e-5, 1e3 * tolerance)
  double pk_error = 0.0;        // last relative pressure change
  double friction_error = 0.0;
  double approach = 0.0;   // delta
  double stiffness = 0.0;  // k_if used (inf for hard wall)
  double wall_time_s = 0.0;
  std::uint64_t transforms = 0;  // real 2D FFTs (forward + inverse) the solve executed
  double fft_seconds = 0.0;      // wall time of those transforms alone (not timed on a device)
  std::size_t device_bytes = 0;  // device memory the solve held at its end (CUDA backend; 0 on the host)
};

// What the friction steps of a failed solve show, for its message: a limit cycle (its period
// in friction steps and the relative amplitude of the tangential force), a slow drift (where the
// damping gave up, damped_out: a floor, with the change's least value and, where small, the
// tolerance that accepts the state; else one that wants more steps, solver.max_outer),
// or no pattern, judged from the last 60 steps of the traction change and of the tangential
// force along the sliding direction (one value per step; the change's least over all of them).
std::string friction_history_evidence(const std::vector<double>& change, const std::vector<double>& force,
                                      bool damped_out = true);

// The mixing history a stalled friction fixed point goes on with, before it damps: twice the
// one it has (solver.anderson), once, up to kDeepHistory. A stall in the stick-slip phase is
// Anderson's short history failing to capture the (non-smooth) map: on the thin nu = 0.49 layer
// with mu_c = 2 at p = 0.316 E* (512^2) depth 10 damps itself out ("oscillating") where depth 20
// converges in 246 friction steps; damping only slows a stall down (docs/solver.md). Returns
// `depth` where there is nothing to deepen (no mixing, or already that deep). Host and device
// alike; a restart point's history has one of the two depths (history_depth_fits).
inline constexpr int kDeepHistory = 20;
inline int deepened_history(int configured, int depth) {
  if (configured <= 0 || depth != configured || configured >= kDeepHistory) return depth;
  return std::min(2 * configured, kDeepHistory);
}
// The friction loop's relaxation after a stall that the longer history did not cure (host and
// device alike): half the last, where a limit cycle of the slip field calms down; 0 (give up,
// "oscillating") once that falls below kMinMixing without steady progress. Steady progress, the
// best change of the last kProgressWindow friction steps (`change`, one per step) below
// kProgressGain times the best before them, is a slow fixed point, not a cycle, which damping
// only slows further: a steep tresca cap at an adhesive contact's edge (mu_c = 5, 256^2) gave
// up at 235 steps with its change still halving every ~40; the relaxation goes back to
// `configured` (solver.mixing) and the loop goes on, to solver.max_outer at most.
inline constexpr double kMinMixing = 0.04, kProgressGain = 0.5;
inline constexpr std::size_t kProgressWindow = 100;
inline double damped_mixing(double omega, double configured, const std::vector<double>& change) {
  if (0.5 * omega >= kMinMixing) return 0.5 * omega;
  if (change.size() <= kProgressWindow) return 0.0;
  const auto split = change.end() - static_cast<std::ptrdiff_t>(kProgressWindow);
  const double before = *std::min_element(change.begin(), split);
  const double recent = *std::min_element(split, change.end());
  return recent < kProgressGain * before ? configured : 0.0;
}
// Whether a mixing history of `depth` can belong to a solve with solver.anderson = configured.
inline bool history_depth_fits(int configured, int depth) {
  return depth == configured || (configured > 0 && depth == deepened_history(configured, configured));
}

// adhesive_fraction and adhesive_potential, the cohesive law on a cell: contact/cohesive_law.hpp.

class DeviceSolve;  // the CUDA backend's solve (contact/device_solve.hpp)

// The friction loop's step control (stall test, hand-over, the automatic derivative's turns)
// as plain numbers.
struct FrictionStepsState {
  bool stick_mode = false;
  int turn = 0;
  int near_stick = 0;
  double best = std::numeric_limits<double>::infinity();
  int since_best = 0;
};

// The restart point of a friction solve: the friction loop at the start of a friction step,
// everything the later steps read, so that a solve resumed from it (ContactSolver::solve's
// `resume`) takes the uninterrupted solve's steps and gives its bits. The pressure at the
// start of the step and the traction iterate are the ContactFields that go with it (a
// checkpoint's three fields). Per-point data are fields over the points held here (grid
// layout: a slab under mpirun), so that a checkpoint gathers them and a resume on another
// number of processes scatters them.
struct FrictionRestart {
  // The same on every process.
  std::int32_t outer = 0;       // friction steps done
  std::int32_t iterations = 0;  // inner iterations done by then (SolveInfo::iterations)
  std::int32_t tangential_iterations = 0;
  double error = 1.0;         // the last friction change
  double mixing = 0.5;        // the relaxation now (halved at each stall)
  double stick_points = 0.0;  // contact points that stuck in the last stick-slip solve
  bool tangential_ok = false;
  bool have_slip = false;
  bool have_z = false;  // the splitting variable (zx, zy) is set
  SlipDerivative derivative = SlipDerivative::Spectral;
  FrictionStepsState steps;
  std::int32_t adhesion_steps = 0;             // with adhesion: the adhesive steps done by then
  double gw_mean_ref = 0.0, g_mean_ref = 0.0;  // the normal solve's references
  // The last normal solve.
  std::int32_t pk_iterations = 0;
  double pk_error = 1.0, pk_delta = 0.0;
  bool pk_converged = false;
  std::vector<double> history_change, history_force;  // per friction step (failure messages)
  // Anderson mixing of the traction (mixer: present; depth: solver.anderson).
  bool mixer = false;
  bool mixer_have_prev = false;
  std::vector<std::int32_t> mixer_slots;  // ring slots in use, oldest first
  std::vector<double> mixer_gram;         // depth x depth
  // Per point held here.
  RealField zx, zy;  // the splitting variable (have_z)
  // -1 outside the mixing's support, else the friction step at whose end the point joined
  // it (0: the warm start's traction): the support's order is (step, grid index).
  RealField support;
  // The mixer's last iterate and residual (x and y components), on the support (0 elsewhere).
  RealField xprev_x, xprev_y, fprev_x, fprev_y;
  // Per slot of mixer_slots: the residual and iterate differences, the x and y components
  // as two floats packed into each double (pack_floats).
  std::vector<RealField> df, dx;
};
// The restart point of a frictionless adhesive solve: its adhesive steps at the start of the step
// in progress, everything the later steps read, so that a solve resumed from it (solve's
// `adhesive_resume`) takes the uninterrupted solve's steps and gives its bits. The traction a
// and the net pressure are the ContactFields that go with it (the checkpoint's adhesion and
// pressure); the repulsive pressure the step starts from is kept here, since p_rep - a + a need
// not give p_rep's bits. Per-point data: fields over the points held here, as FrictionRestart's.
struct AdhesiveRestart {
  // The same on every process.
  std::int32_t step = 0;            // adhesive steps done in the solve's loop
  std::int32_t used = 0;            // their CG iterations
  std::int32_t pre_iterations = 0;  // the first-touch solve's (a tensile load's cold start)
  std::int32_t iterations = 0;      // the solve's inner iterations by then (ContactSolver's count)
  std::int32_t adhesion_steps = 0;  // SolveInfo::adhesion_steps by then (the first-touch ones too)
  std::int32_t viscoelastic_steps = 0;
  double change = 1.0;  // the traction's last relative change
  // Plastic saturation under load control: the last approach found (the next bracket's start).
  bool capped_found = false, capped_acted = false;
  double capped_delta = 0.0;
  double gw_mean_ref = 0.0, g_mean_ref = 0.0;  // the normal solve's references
  AndersonGuard::State guard;
  // The traction's Anderson mixing (solver.anderson > 0).
  bool mixer = false;
  bool mixer_have_prev = false;
  std::vector<std::int32_t> mixer_slots;  // ring slots in use, oldest first
  std::vector<double> mixer_gram;         // depth x depth
  // Per point held here.
  RealField repulsion;            // the repulsive pressure at the step's start
  RealField kept;                 // the safeguard's kept image (empty before its first mixing)
  RealField xprev, fprev;         // the mixer's last iterate and residual
  std::vector<RealField> df, dx;  // per slot of mixer_slots: the differences (floats, held exactly)
};

// Two floats in the bits of one double, and back (FrictionRestart::df, dx).
double pack_floats(float x, float y);
void unpack_floats(double packed, float& x, float& y);

struct Progress {
  int iteration;
  int outer;
  double error;
};

class ContactSolver {
 public:
  // Under the "cuda" backend (core/backend.hpp) the solve runs on the GPU: the problem is
  // uploaded here (an InputError if no device is usable or the grid does not fit there).
  ContactSolver(const ElasticBody& body, const Topography& topo, const InteractionParams& inter,
                const FrictionParams& fric, const SolverParams& solver);
  ~ContactSolver();
  ContactSolver(const ContactSolver&) = delete;
  ContactSolver& operator=(const ContactSolver&) = delete;

  // Solves for the given load. `fields` may hold a previous solution of the same grid
  // (warm start: pressure and tractions are used); it is overwritten with the new one.
  // While the solve runs (progress, checkpoints, an exception) only pressure, tx and ty
  // are valid; ux, uy, uz and gap are empty until the end.
  SolveInfo solve(const LoadParams& load, ContactFields& fields) { return solve(load, fields, nullptr); }

  void set_progress(std::function<void(const Progress&)> cb) { progress_ = std::move(cb); }
  // Polled every iteration: returning true stops the solve with gfmd::Interrupted, the
  // fields holding the last pressure and tractions (a valid warm start).
  void set_stop_request(std::function<bool()> cb) { stop_ = std::move(cb); }
  // Iterations done so far by the running (or last) solve.
  [[nodiscard]] int iterations_done() const { return total_it_; }
  // A friction solve resumed from a restart point (restart_point() of an interrupted solve of
  // the same problem, on this grid): `fields` hold its pressure and traction. The solve then
  // goes on from there, with the interrupted solve's steps and bits. nullptr: solve().
  // A frictionless adhesive solve resumed from its restart point (adhesive_restart_point() of an
  // interrupted solve of the same problem): `fields` hold its net pressure and adhesive traction.
  SolveInfo solve(const LoadParams& load, ContactFields& fields, const FrictionRestart* resume,
                  const AdhesiveRestart* adhesive_resume = nullptr);
  // The restart point, while a checkpoint is written (the checkpoint callback) and after an
  // interruption (until the next solve): the friction loop at the start of the step it was in,
  // its pressure and traction in `fields` (pressure, tx, ty) and the rest in `state`. nullptr
  // for a frictionless solve, a solve on the device, or between the friction steps' polls.
  struct RestartPoint {
    ContactFields fields;
    FrictionRestart state;
  };
  [[nodiscard]] const RestartPoint* restart_point() const { return restart_.get(); }
  // The same for a frictionless adhesive solve stopped inside its adhesive steps (after the
  // first-touch solve of a tensile load): its net pressure and traction in `fields` (pressure,
  // adhesion; tx = ty = 0), the rest in `state`. nullptr otherwise.
  struct AdhesiveRestartPoint {
    ContactFields fields;
    AdhesiveRestart state;
  };
  [[nodiscard]] const AdhesiveRestartPoint* adhesive_restart_point() const { return adh_restart_.get(); }
  // The final state of a converged solve given by its pressure and tractions (p, tx, ty in
  // fields) and its info (a checkpoint's frictionless reference): the displacements, the gap
  // and the residual check as solve() makes them. false on the device (not available there).
  bool finish(ContactFields& fields, SolveInfo& info);
  // Called with the current state every `interval_s` seconds (checkpoints).
  void set_checkpoint(std::function<void(const ContactFields&)> cb, double interval_s) {
    checkpoint_ = std::move(cb);
    checkpoint_interval_s_ = interval_s;
  }

  [[nodiscard]] const FFT& fft() const { return fft_; }
  [[nodiscard]] const RealField& initial_gap() const { return g0_; }
  [[nodiscard]] double stiffness() const { return k_; }
  [[nodiscard]] double sliding_angle() const { return fric_.direction_deg; }
  // True when the solves run on a CUDA device.
  [[nodiscard]] bool on_device() const { return device_ != nullptr; }
  // Adhesion: whether the fields' pressure is now the repulsive one, p + a (during the adhesive
  // steps, and after an interruption in them), not the net pressure.
  [[nodiscard]] bool pressure_is_repulsive() const { return adh_.repulsive; }

 private:
  struct PKResult {
    int iterations;
    double error;
    double delta;
    bool converged;
  };
  // w_zero: w is zero everywhere (not read then).
  PKResult solve_normal(const LoadParams& load, const RealField& w, bool w_zero, RealField& p, double tol,
                        int max_it);
  // Polonsky-Keer itself (solve_normal without a cap, or with a cap under approach control).
  PKResult solve_normal_pk(const LoadParams& load, const RealField& w, bool w_zero, RealField& p, double tol,
                           int max_it);
  // A capped pressure under load control: the approach whose capped solution carries the load,
  // found by safeguarded regula falsi (Illinois) over approach-controlled solves, each started
  // from the last (normal.cpp).
  // The adhesive normal problem (adhesion.cpp): with the adhesive traction a held fixed, the
  // repulsive problem (w = C_zz a) is convex; a is then rebuilt from the new gap by the cell
  // integral of the cohesive law (adhesive_fraction), Anderson-mixed, until it settles.
  // f.pressure holds the net pressure (repulsion minus adhesion), f.adhesion the traction.
  // In the friction loop: w_extra, the friction's normal displacement C_z.tau, held fixed, and
  // a budget of max_it CG iterations (-1: solver.max_iterations). The result's `converged` is
  // the whole adhesive solve's (info.converged, info.status).
  // Frictionless at the top (restartable): it keeps a restart point for checkpoints and stops,
  // and `resume` goes on from one.
  PKResult solve_adhesive(const LoadParams& load, ContactFields& f, double tol, SolveInfo& info,
                          const RealField* w_extra = nullptr, int max_it = -1, bool restartable = false,
                          const AdhesiveRestart* resume = nullptr);
  // The adhesive steps' mixing (its safeguard and history) into a restart point and back.
  void save_adhesive_mixing(AdhesiveRestart& st) const;
  void restore_adhesive_mixing(const AdhesiveRestart& st);
  // A viscoelastic body (viscoelastic.cpp): the response C_zz E0/E(omega) split into a
  // symmetric part (czz_n_, each mode's elastic compliance at its storage modulus) that the
  // Polonsky-Keer solve takes and the rest, whose displacement from the last pressure is held
  // fixed (w) during that solve; Anderson-mixed over the pressure until it settles.
  PKResult solve_viscoelastic(const LoadParams& load, ContactFields& f, double tol, SolveInfo& info);
  // The splitting itself, with an extra normal displacement w_extra held fixed (the friction's,
  // C_z.tau; null: none), within max_it CG iterations: counts its steps into `steps`, sets
  // `status` ("converged" or why not); the result's iterations are all its CG iterations (the
  // active set's products where uses_active_set() hands the solve to it).
  PKResult solve_normal_viscoelastic(const LoadParams& load, const RealField* w_extra, RealField& p,
                                     double tol, int max_it, int& steps, std::string& status);
  // The same problem on the non-symmetric operator c C_zz itself: a primal-dual active set whose
  // linear solves on the contact set are restarted GMRES (viscoelastic_active_set.cpp); `steps`
  // counts the set's updates, the result's iterations the operator products.
  [[nodiscard]] bool uses_active_set() const;
  PKResult solve_normal_active_set(const LoadParams& load, const RealField* w_extra, RealField& p, double tol,
                                   int max_it, int& steps, std::string& status);
  // The hysteresis force of SolveInfo::hysteresis_dissipation from the tractions of f (the
  // pressure alone unless `friction`).
  double hysteresis_dissipation(const ContactFields& f, bool friction);
  // spread = |g_x| dx + |g_y| dy, the gap's range over each cell (gx: scratch).
  void gap_spread(const RealField& gap, RealField& gx, RealField& spread);
  PKResult solve_normal_capped_load(const LoadParams& load, const RealField& w, bool w_zero, RealField& p,
                                    double tol, int max_it);
  void apply_compliance(const RealField& in, RealField& out, double scale = 1.0);  // scale C_zz in
  // The body's whole normal response to a normal traction: C_zz in, or on a sliding viscoelastic
  // body c C_zz in (the symmetric part and the rest together; complex per mode).
  void apply_normal_response(const RealField& in, RealField& out);
  // The repulsive normal solve of the body under an extra displacement w held fixed: Polonsky-Keer,
  // or on a sliding viscoelastic body its splitting (counting its steps into info).
  PKResult solve_repulsive(const LoadParams& load, const RealField& w, RealField& p, double tol, int max_it,
                           SolveInfo& info);
  void update_displacements(ContactFields& f);  // u from (tau, -p)
  // Coulomb tractions of the current slip into (tx, ty); returns, over the grid,
  // sum |(tx, ty) - (f.tx, f.ty)|_1, sum |(tx, ty)|_1, the number of points outside the
  // Anderson support (in_supp == 0) where either traction is non-zero and the number of
  // contact points slipping slower than kNearStickSpeed v0 (evidence of stick).
  std::array<double, 4> slip_tractions(const ContactFields& f, RealField& tx, RealField& ty,
                                       const std::vector<unsigned char>& in_supp);
  struct TangentialResult {
    int iterations;
    double error;
    bool converged;
  };
  // The set-valued Coulomb law for the pressure p held fixed: tau = P_K(tau + gamma v(tau)),
  // K the discs |tau| <= mu_c p, v = xi e_s + (e_s.grad) u_t the slip velocity, solved by
  // Douglas-Rachford splitting between the projection and the (linear, skew) slip operator,
  // whose resolvent is one spectral pass. The splitting variable z (= tau + gamma v at the
  // solution) is kept between calls of one solve (warm start); (tx, ty) receives P_K(z).
  // The splitting step gamma for the slip derivative `deriv`: friction.stick_step E*, or
  // automatic.
  [[nodiscard]] double stick_step(SlipDerivative deriv) const;
  // Makes `deriv` the solve's slip derivative: its symbol table and its splitting step.
  void use_derivative(SlipDerivative deriv);
  // p is the net pressure (its slip through the coupling); the law's bound reads the repulsion,
  // p + adhesion where an adhesive traction is given (the compressive part; else p itself).
  TangentialResult solve_tangential(const RealField& p, const RealField* adhesion, RealField& tx,
                                    RealField& ty, double tol, int max_it);
  // w = C_z.tau, the normal displacement of the tangential tractions; leaves their spectra in
  // s2_/s3_ (slip_tractions reads them; transform_tractions puts them back after a pass that
  // used s2_/s3_, the adhesive solve's gap spread).
  void friction_normal_displacement(const RealField& tx, const RealField& ty, RealField& w);
  void transform_tractions(const RealField& tx, const RealField& ty);
  double residual(const ContactFields& f, double delta);
  // The gap of the final state (from u_z), its independent residual and the verdict on it.
  void check_final_state(SolveInfo& info, ContactFields& f, double delta);
  SolveInfo solve_on_device(const LoadParams& load, ContactFields& f);

  const ElasticBody& body_;
  Grid grid_;
  FFT fft_;
  InteractionParams inter_;
  FrictionParams fric_;
  SolverParams sp_;
  double k_;      // interaction stiffness (inf: hard wall)
  double inv_k_;  // 1/k
  RealField g0_;
  double g0_rms_ = 0.0;
  double gw_mean_ref_ = 0.0;      // solve_normal: last mean of g0 - w on the contact set
  double g_mean_ref_ = 0.0;       // solve_normal: last mean of the separation there (load control)
  bool cap_off_ = false;          // solve_normal_pk ignores the cap (solve_normal's uncapped trial)
  bool capped_acted_ = false;     // the last capped load-controlled solve had points at the cap
  double capped_delta_ = 0.0;     // solve_normal_capped_load: the last approach found
  bool capped_found_ = false;     // whether capped_delta_ holds one
  SpecField s1_, s2_, s3_;        // half-spectrum scratch
  RealField cg_g_, cg_t_, cg_r_;  // work arrays of solve_normal
  // Real scratch of the friction step and the displacement update; solve_normal does not
  // keep anything in its work arrays between calls, so these share them.
  RealField& r1_ = cg_t_;
  RealField& r2_ = cg_r_;
  // Adhesion's state between solves (adhesion.cpp; a load path reuses it): the gap's spread over
  // each cell in the last step (the residual reads it), work arrays, the traction's mixer and
  // its row grouping, the spectral gradient's factors i q_x, i q_y per half-spectrum mode.
  struct AdhesionWork {
    // True while the adhesive steps hold the repulsive pressure p + a in the fields (a
    // checkpoint or an interruption then stores p - a, the net pressure a warm start expects).
    bool repulsive = false;
    RealField spread, w, d, gap;
    std::unique_ptr<GuardedAnderson> mixer;
    std::vector<double> qx, qy;
  };
  AdhesionWork adh_;
  // The viscoelastic active set's work arrays (viscoelastic_active_set.cpp), kept between solves.
  struct ActiveSetWork {
    RealField rhs, kp, full;                       // w - g0, the response, a product's input
    std::vector<unsigned char> in;                 // the contact set
    std::vector<std::uint32_t> idx, start, order;  // its points held here, by row
    std::vector<std::vector<double>> basis;        // GMRES's Krylov basis on them
  };
  // A viscoelastic body's state (viscoelastic.cpp): the rest of the response per mode, minus
  // (E0/E(omega) - |E0/E(omega)|) C_zz / N (its displacement enters the normal solve as w), the
  // pressure's mixer, and the active set's work arrays.
  struct ViscoWork {
    std::vector<cplx> rest_n;
    ActiveSetWork active;
    RealField w;
    std::unique_ptr<GuardedAnderson> mixer;
    // Why the last viscoelastic solve under a held displacement (solve_repulsive) did not
    // converge ("" when it did): its callers' failures say it.
    std::string last_failure;
  };
  ViscoWork visco_;
  RealField zx_, zy_, bx_, by_;  // splitting variable and pressure-induced slip of solve_tangential
  bool have_z_ = false;
  double gamma_ = 0.0;  // its step
  // Anderson mixing of z in solve_tangential (friction.stick_acceleration > 0), over every
  // point held here: the two components interleaved, summed by grid row.
  std::unique_ptr<AndersonMixer> zmix_;
  std::vector<std::uint32_t> zmix_start_, zmix_order_;
  std::vector<double> czz_n_;                        // C_zz / (nx ny) per half-spectrum mode, contiguous
  SlipDerivative deriv_ = SlipDerivative::Spectral;  // the slip derivative in use now
  std::vector<cplx> dsym_;  // an upwind slip derivative's symbol per mode (empty: spectral)
  [[nodiscard]] const cplx* slip_symbols() const { return dsym_.empty() ? nullptr : dsym_.data(); }
  // Stop requests and checkpoints; `settle` runs first when either is due (it brings the
  // state up to date), `unsettle` after a checkpoint (it puts the solve's own state back, so
  // that the results do not depend on when checkpoints were written).
  void poll(const ContactFields* f, const std::function<void()>& settle = {},
            const std::function<void()>& unsettle = {});
  std::function<void(const Progress&)> progress_;
  std::function<bool()> stop_;
  std::function<void(const ContactFields&)> checkpoint_;
  // The friction loop's restart point: made by restart_maker_ (set while the loop runs) when
  // a checkpoint or a stop is due.
  std::unique_ptr<RestartPoint> restart_;
  std::unique_ptr<AdhesiveRestartPoint> adh_restart_;  // the adhesive steps' (frictionless)
  std::function<void()> restart_maker_;
  double checkpoint_interval_s_ = 0.0;
  double last_checkpoint_ = 0.0;
  ContactFields* current_ = nullptr;
  int total_it_ = 0;
  std::unique_ptr<DeviceSolve> device_;
};

}  // namespace gfmd
