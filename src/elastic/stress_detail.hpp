// Helpers shared by the stress files (private to the elastic part).
#pragma once

#include <cmath>
#include <cstddef>
#include <limits>

#include "gfmd/core/error.hpp"
#include "gfmd/core/mpi.hpp"
#include "gfmd/elastic/stress.hpp"

namespace gfmd::stress_detail {

inline void require_size(const RealField& f, std::size_t n, const char* what) {
  if (f.size() != n)
    throw std::invalid_argument(std::string("stress: field '") + what + "' has the wrong size");
}

// Whether an optional field is given (sized for the rows held here). On a slab every process
// must take the same branch (the transforms that follow are collectives), so the processes
// agree: a process that holds no rows learns it from the others.
inline bool present(const RealField& f, const Grid& g, const char* what) {
  const bool here = !f.empty();
  if (here) require_size(f, g.local_size(), what);
  return g.is_slab() ? mpi::any_bits(here ? 1u : 0u) != 0 : here;
}

inline StressField make_stress(std::size_t n) {
  StressField s;
  for (RealField* p : {&s.xx, &s.yy, &s.zz, &s.xy, &s.xz, &s.yz}) p->assign(n, 0.0);
  return s;
}

// A plane below the surface that the body has: finite, >= 0, not below a layer's base.
inline void check_depth(const ElasticParams& el, double depth) {
  if (!(depth >= 0.0) || !std::isfinite(depth))
    throw ParameterError("depth", "must be a finite number >= 0 (depth below the surface)");
  if (depth > el.depth_of_base() * (1.0 + 1e-12))
    throw ParameterError("depth", "is below the rigid base of the layer (depth > thickness)");
}

}  // namespace gfmd::stress_detail
