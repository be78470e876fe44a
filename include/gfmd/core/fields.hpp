// The state of a contact on the grid: pressure, tangential tractions, surface displacements,
// gap and the stick mask. Shared by the solver (which fills it), the stresses and the outputs.
#pragma once

#include <vector>

#include "gfmd/core/fft.hpp"

namespace gfmd {

struct ContactFields {
  RealField pressure, tx, ty, ux, uy, uz, gap;
  // 1 where a contact point sticks (|tau| < mu_c p, zero slip velocity); filled at the end
  // of a solve with the exact Coulomb law, empty otherwise.
  std::vector<unsigned char> stick;
  // Adhesion: the tensile traction the indenter exerts on the body (>= 0; pressure is the net
  // pressure, repulsion minus this); empty without adhesion.
  RealField adhesion;
  // The repulsive part of the pressure at point i: the contact is where it is positive.
  [[nodiscard]] double repulsion(std::size_t i) const {
    return adhesion.empty() ? pressure[i] : pressure[i] + adhesion[i];
  }
  [[nodiscard]] bool in_contact(std::size_t i) const { return repulsion(i) > 0; }
};

}  // namespace gfmd
