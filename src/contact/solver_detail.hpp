// Shared pieces of the contact solver's parts (private to the contact part): constants of
// the stick-slip iteration, checks and the per-point sums of a friction step.
#pragma once

#include <array>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>

#include "gfmd/contact/solver.hpp"
#include "gfmd/core/error.hpp"

namespace gfmd::contact_detail {

using Clock = std::chrono::steady_clock;
// Stick-slip (Douglas-Rachford) iteration of the exact law, chosen by measurement (see
// docs/solver.md): step gamma = 1/rho(A), over-relaxation 1.6, no Anderson mixing by default
// (it saves iterations but not time: its two passes over 2 N entries cost about what the
// step's four transforms do); each stick-slip solve within a friction step stops at 1e-2 of
// the friction change.
inline constexpr double kStickStepFactor = 1.0;
// A friction law whose bound falls with the speed: the step is raised to kFallingStepHeadroom
// times its steepest fall at the largest pressure once it is below kFallingStepMargin times it
// (friction.cpp). Just outside the disc the resolvent's radial slope is -fall/(gamma - fall):
// gamma >= 2 fall keeps it within [-1, 0] (non-expansive), 3 fall at -1/2. Measured on tractive
// rolling with the velocity law (examples/rolling_static_peak.toml, v_c = 0.1): at 64^2 any
// step above the fall converges to one state (3e-14 apart), but at 128^2 the coupled friction
// loop kept changing by 2e-2 for 47 friction steps with 1.5 x the fall and converged in 97
// iterations with 4 x (friction.stick_step = 1).
inline constexpr double kFallingStepMargin = 2.0;
inline constexpr double kFallingStepHeadroom = 3.0;
inline constexpr double kTangentialRelaxation = 1.6;
inline constexpr double kTangentialTolFactor = 1e-2;
// With friction.stick_acceleration > 0 (Anderson mixing of z, safeguarded): relaxation 1.4,
// stick-slip solves to 3e-3 of the friction change and, in the stick-slip phase, normal
// solves to 0.3 of it (0.1 otherwise); measured on the thin layer (docs/solver.md).
inline constexpr double kAcceleratedRelaxation = 1.4;
inline constexpr double kAcceleratedTangentialTolFactor = 3e-3;
inline constexpr double kAcceleratedNormalTolFactor = 0.3;
// The full-slip map hands over to the stick-slip solve once contact points slip slower than
// kNearStickSpeed v0 in kNearStickSteps successive friction steps, from friction step
// kNearStickFirst on (the first steps start from a traction the pressure has not met yet).
inline constexpr double kNearStickSpeed = 0.03;
inline constexpr int kNearStickSteps = 2;
inline constexpr int kNearStickFirst = 4;

inline void require_finite(double v, const char* what, int it) {
  if (!std::isfinite(v)) {
    std::ostringstream os;
    os << "solve diverged: " << what << " is not finite at iteration " << it;
    throw SolveError(os.str());
  }
}
// A point joins the Anderson support of the friction iteration when it is not in it yet
// and the iterate (fx, fy) or its image (x, y) is non-zero there.
inline bool joins_support(unsigned char in_supp, double x, double y, double fx, double fy) {
  return !in_supp && (x != 0.0 || y != 0.0 || fx != 0.0 || fy != 0.0);
}

// Sums of a friction step at a point with new traction (x, y) and previous (fx, fy): the
// change |new - old|_1, the size |new|_1, and whether the point joins the Anderson support.
template <std::size_t N>
inline void add_change(std::array<double, N>& acc, unsigned char in_supp, double x, double y, double fx,
                       double fy) {
  acc[0] += std::abs(x - fx) + std::abs(y - fy);
  acc[1] += std::abs(x) + std::abs(y);
  if (joins_support(in_supp, x, y, fx, fy)) acc[2] += 1.0;
}

// The friction loop's step control, one for the host and the device solve: the stall test
// (the best change must improve by 10 % within 20 steps; slow but steady progress, stiff slip
// feedback near stick, is not a stall, a limit cycle is), the hand-over from the full-slip
// map to the stick-slip splitting, and the turns of the automatic slip derivative of a
// sliding solve (docs/solver.md): spectral until the hand-over, upwind2 from there; spectral
// again where that upwind2 solve converges with no point stuck; upwind2 for good if the
// spectral continuation meets stick after all.
class FrictionSteps {
 public:
  enum class Next { Go, HandOver, Damp };
  // stick_mode: the splitting from the start (rolling); automatic: the slip derivative is the
  // automatic one of a sliding solve.
  FrictionSteps(bool stick_mode, bool automatic)
      : stick_mode_(stick_mode), turn_(automatic ? Turn::Spectral : Turn::None) {}
  [[nodiscard]] bool stick_mode() const { return stick_mode_; }
  // The state as plain numbers (FrictionRestart) and back; restore refuses a turn it does
  // not know.
  [[nodiscard]] FrictionStepsState state() const {
    return {stick_mode_, static_cast<int>(turn_), near_stick_, best_, since_best_};
  }
  void restore(const FrictionStepsState& s) {
    if (s.turn < 0 || s.turn > static_cast<int>(Turn::UpwindFinal))
      throw std::invalid_argument("FrictionSteps: unknown state");
    stick_mode_ = s.stick_mode;
    turn_ = static_cast<Turn>(s.turn);
    near_stick_ = s.near_stick;
    best_ = s.best;
    since_best_ = s.since_best;
  }
  // Whether the automatic derivative is upwind2 now (after a hand-over or a settle_upwind()).
  [[nodiscard]] bool upwind() const { return turn_ == Turn::Upwind || turn_ == Turn::UpwindFinal; }
  // After a full-slip step in which `slow` contact points slipped slower than kNearStickSpeed v0.
  void full_slip_step(double slow) { near_stick_ = slow > 0 ? near_stick_ + 1 : 0; }
  // After friction step `outer` (from 0) with change err. HandOver: the exact law's full-slip
  // map meets stick or stalls; go on with the splitting and a fresh history (and upwind2 where
  // upwind() says so). Damp: stalled; damp harder. The test restarts after either.
  Next after(double err, int outer, bool exact_law) {
    if (err < kStallGain * best_) {
      best_ = err;
      since_best_ = 0;
    } else {
      ++since_best_;
    }
    const bool stalled = since_best_ >= kStallSteps;
    const bool meets_stick = near_stick_ >= kNearStickSteps && outer + 1 >= kNearStickFirst;
    if (exact_law && !stick_mode_ && (meets_stick || stalled)) {
      stick_mode_ = true;
      if (turn_ == Turn::Spectral) turn_ = Turn::Upwind;
      restart(std::numeric_limits<double>::infinity());
      return Next::HandOver;
    }
    if (stalled) {
      restart(err);
      return Next::Damp;
    }
    return Next::Go;
  }
  // Converged (done) with the automatic derivative turned to upwind2 and no point stuck: turn
  // back to spectral (true; the stall test restarts).
  bool turns_back(bool done, double stick_points) {
    if (!(done && turn_ == Turn::Upwind && stick_points == 0)) return false;
    turn_ = Turn::SpectralAgain;
    restart(std::numeric_limits<double>::infinity());
    return true;
  }
  // The spectral continuation meets stick: upwind2 for good (true).
  bool settles_upwind(double stick_points) {
    if (!(turn_ == Turn::SpectralAgain && stick_points > 0)) return false;
    turn_ = Turn::UpwindFinal;
    return true;
  }

 private:
  static constexpr double kStallGain = 0.9;
  static constexpr int kStallSteps = 20;
  enum class Turn { None, Spectral, Upwind, SpectralAgain, UpwindFinal };
  void restart(double best) {
    best_ = best;
    since_best_ = 0;
  }
  bool stick_mode_;
  Turn turn_;
  int near_stick_ = 0;  // successive full-slip steps with contact points near stick
  double best_ = std::numeric_limits<double>::infinity();
  int since_best_ = 0;
};

// An outer loop over inner normal solves (adhesion's traction, a viscoelastic body's pressure):
// the relative change sum |new - old| / sum |new| of a step, and its end test: "" to go on,
// else the status ("converged" once the change, the inner solve and its tolerance all meet
// `tol`; or why not). `what` names the iterate in the message.
inline double relative_change(double diff, double size) {
  return size > 0 ? diff / size : (diff > 0 ? 1.0 : 0.0);
}
// The tolerance of an adhesive step's repulsive solve: the traction's last relative change (no
// tighter than the solve's `tol`); host and device alike. The steps' count is set by how fast the
// cohesive zones move, not by the inner accuracy (a rough contact at 512²: about 100 steps
// with the inner solves to a tenth of the change, to the change, or cut at three CG iterations),
// so a tighter inner solve only costs iterations: 3.6x those of the change's at 512², 3.4x at
// 2048² (BENCHMARKS.md, "Adhesion").
inline double adhesive_inner_tolerance(double tol, double change) { return std::max(tol, change); }
// Why a restart point does not fit this solve ("" when it does): n points held here, the
// Anderson depth and the configured slip derivative (solver_restart.cpp).
std::string restart_mismatch(const FrictionRestart& r, std::size_t n, int depth,
                             const std::optional<SlipDerivative>& fixed);
// The same for an adhesive restart point: n points held here, the Anderson depth.
std::string adhesive_restart_mismatch(const AdhesiveRestart& r, std::size_t n, int depth);

// Above this friction.coefficient the tresca law's cap acts as a switch at the contact's edge: a
// failure says so (docs/solver.md, "Adhesion with friction").
constexpr double kTrescaSteepCoefficient = 3.0;
inline constexpr const char* kTrescaSteepHint =
    "; friction.law = \"tresca\" with a large friction.coefficient switches the shear strength on and off "
    "at the contact's edge, whose cells the coupling moves: lower friction.coefficient (e.g. 3), so that "
    "the shear rises continuously there (docs/solver.md, \"Adhesion with friction\")";

// The adhesive steps' texts (adhesion.cpp and device_adhesion.cu alike): a load beyond what the
// adhesion holds under load control, and the failure's likely cause given the cohesive zones'
// width in cells (the cells they pull without contact over the cells they pull partly).
inline constexpr const char* kBeyondPullOff =
    "not converged: the load is below what the adhesion holds at this state (a tensile load beyond the "
    "pull-off under load control); follow the unloading branch under approach control (load.approach, gfmd "
    "curve --approaches ... --unload)";
inline std::string narrow_cohesive_zones(double cells) {
  std::ostringstream os;
  os << "; the cohesive zones are about " << std::setprecision(2) << cells
     << " cells wide: below about 2 their edges are trapped by the grid and the steps may not settle "
        "(refine the grid, or lengthen interaction.range at the same work of adhesion)";
  return os.str();
}
// A failed adhesive solve's status with the zones' width: where they are narrower than 2 cells
// that is the cause, and the iteration limit's advice (more steps) goes, which would not help.
inline void add_cohesive_zones(std::string& status, double cells) {
  constexpr std::string_view more = "; raise solver.max_outer";
  if (cells < 2.0 && status.ends_with(more)) status.erase(status.size() - more.size());
  status += narrow_cohesive_zones(cells);
}

// A viscoelastic splitting that stops with its pressure still changing by more than this per step
// has not stalled slowly: it cycles (with the hard wall, its failure says what settles instead).
inline constexpr double kViscoStallChange = 1e-3;

// The status of an outer fixed point after a step ("" while it goes on). `cycling`: what to do
// when the fixed point cycles, said instead of raising solver.max_outer (which would not help) and
// after the iteration limit; null: none known.
inline std::string outer_status(double change, double tol, bool inner_ok, double inner_tol, int used,
                                int step, const SolverParams& sp, const char* what,
                                const char* cycling = nullptr) {
  if (change <= tol && inner_ok && inner_tol <= tol) return "converged";
  const std::string advice = cycling ? std::string("; ") + cycling : std::string();
  if (used >= sp.max_iterations) return "not converged: iteration limit reached" + advice;
  if (step + 1 < sp.max_outer) return "";
  std::ostringstream os;
  os << "not converged: " << what << " did not settle in solver.max_outer = " << sp.max_outer
     << " steps (relative change " << change << " in the last)"
     << (cycling ? advice : std::string("; raise solver.max_outer"));
  return os.str();
}

}  // namespace gfmd::contact_detail
