// The friction loop's restart point (checkpoints, stops): the mixing history's float pairs packed
// into doubles, and whether a restart point fits the solve it is handed to. See solver.hpp.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>

#include "gfmd/contact/anderson.hpp"
#include "gfmd/contact/solver.hpp"
#include "solver_detail.hpp"

namespace gfmd {

double pack_floats(float x, float y) {
  std::uint32_t bits[2];
  std::memcpy(&bits[0], &x, 4);
  std::memcpy(&bits[1], &y, 4);
  const std::uint64_t u = (static_cast<std::uint64_t>(bits[1]) << 32) | bits[0];
  double d;
  std::memcpy(&d, &u, 8);
  return d;
}

void unpack_floats(double packed, float& x, float& y) {
  std::uint64_t u;
  std::memcpy(&u, &packed, 8);
  const auto lo = static_cast<std::uint32_t>(u & 0xffffffffu), hi = static_cast<std::uint32_t>(u >> 32);
  std::memcpy(&x, &lo, 4);
  std::memcpy(&y, &hi, 4);
}

namespace contact_detail {

// Why a restart point does not fit this solve ("" when it does): n points held here, the
// Anderson depth and the configured slip derivative.
std::string restart_mismatch(const FrictionRestart& r, std::size_t n, int depth,
                             const std::optional<SlipDerivative>& fixed) {
  if (r.support.size() != n) return "its fields are not on this grid";
  if (r.have_z && (r.zx.size() != n || r.zy.size() != n)) return "its splitting variable is not on this grid";
  if (r.mixer != (depth > 0)) return "it was made with another solver.anderson";
  if (r.mixer) {
    // The history may have been deepened (deepened_history) before the restart point was made.
    const auto m = static_cast<std::size_t>(std::lround(std::sqrt(static_cast<double>(r.mixer_gram.size()))));
    if (m * m != r.mixer_gram.size() || !history_depth_fits(depth, static_cast<int>(m)) ||
        r.mixer_slots.size() > m || r.df.size() != r.mixer_slots.size() ||
        r.dx.size() != r.mixer_slots.size())
      return "its mixing history was made with another solver.anderson";
    for (const RealField* fld : {&r.xprev_x, &r.xprev_y, &r.fprev_x, &r.fprev_y})
      if (fld->size() != n) return "its mixing history is not on this grid";
    for (std::size_t k = 0; k < r.df.size(); ++k)
      if (r.df[k].size() != n || r.dx[k].size() != n) return "its mixing history is not on this grid";
  }
  if (fixed && r.derivative != *fixed) return "it was made with another friction.slip_derivative";
  if (r.outer < 0 || r.iterations < 0 || r.tangential_iterations < 0) return "its counts are negative";
  return "";
}

std::string adhesive_restart_mismatch(const AdhesiveRestart& r, std::size_t n, int depth) {
  if (r.repulsion.size() != n || r.kept.size() != n) return "its fields are not on this grid";
  if (r.mixer != (depth > 0)) return "it was made with another solver.anderson";
  if (r.mixer) {
    const auto m = static_cast<std::size_t>(depth);
    if (r.mixer_gram.size() != m * m || r.mixer_slots.size() > m || r.df.size() != r.mixer_slots.size() ||
        r.dx.size() != r.mixer_slots.size())
      return "its mixing history was made with another solver.anderson";
    for (const std::int32_t sl : r.mixer_slots)
      if (sl < 0 || static_cast<std::size_t>(sl) >= m)
        return "its mixing history was made with another solver.anderson";
    if (r.xprev.size() != n || r.fprev.size() != n) return "its mixing history is not on this grid";
    for (std::size_t k = 0; k < r.df.size(); ++k)
      if (r.df[k].size() != n || r.dx[k].size() != n) return "its mixing history is not on this grid";
  }
  if (r.step < 0 || r.used < 0 || r.pre_iterations < 0 || r.iterations < 0 || r.adhesion_steps < 0 ||
      r.viscoelastic_steps < 0)
    return "its counts are negative";
  return "";
}

}  // namespace contact_detail

}  // namespace gfmd
