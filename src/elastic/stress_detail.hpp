// Helpers shared by the stress files (private to the elastic part).
#pragma once

#include <cstddef>

#include "gfmd/elastic/stress.hpp"

namespace gfmd::stress_detail {

inline void require_size(const RealField& f, std::size_t n, const char* what) {
  if (f.size() != n)
    throw std::invalid_argument(std::string("stress: field '") + what + "' has the wrong size");
}

inline bool present(const RealField& f, std::size_t n, const char* what) {
  if (f.empty()) return false;
  require_size(f, n, what);
  return true;
}

inline StressField make_stress(std::size_t n) {
  StressField s;
  for (RealField* p : {&s.xx, &s.yy, &s.zz, &s.xy, &s.xz, &s.yz}) p->assign(n, 0.0);
  return s;
}

// ---- plane-strain response ------------------------------------------------------------

}  // namespace gfmd::stress_detail
