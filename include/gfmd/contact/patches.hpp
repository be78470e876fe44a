// Contact patches: the connected components of the contact area on the periodic grid, their
// areas, perimeters and whether they wrap around the cell (percolate).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "gfmd/core/fields.hpp"
#include "gfmd/core/grid.hpp"

namespace gfmd {

struct PatchStats {
  // Connected contact patches: cells in contact joined through their faces (4-neighbour
  // connectivity), across the periodic boundaries too.
  std::size_t count = 0;
  // Per patch, sorted by area descending (ties: the patch whose first cell in row-major
  // order comes first); the three lists have the same order.
  std::vector<std::size_t> cells;  // number of cells
  std::vector<double> areas;       // cells * dx * dy
  // Length of the faces between the patch's cells and cells out of contact: dy for a face
  // between x-neighbours, dx for one between y-neighbours (periodic neighbours included).
  std::vector<double> perimeters;
  double largest_area = 0.0;
  double contact_area = 0.0;  // total: sum of areas
  // Patches that reach their own periodic image (wrap around the cell) along x or y; a patch
  // that winds diagonally (e.g. a staircase closing on itself after one cell in x and one in
  // y) wraps along both.
  std::size_t percolating = 0;
  bool percolates_x = false, percolates_y = false;
};

// Patch statistics of a contact mask (contact[i] != 0: point i = iy * nx + ix is in contact).
// Serial breadth-first labelling that tracks the unwrapped position of every cell: O(N),
// deterministic. Throws ParameterError("grid") for nx or ny < 1 and ("contact") when the mask
// does not have grid.size() entries.
PatchStats contact_patches(const Grid& g, const std::vector<unsigned char>& contact);

// The same, also giving the label of every cell: -1 out of contact, else the patch's index in
// the lists of PatchStats (0: the largest patch).
PatchStats contact_patches(const Grid& g, const std::vector<unsigned char>& contact,
                           std::vector<std::int32_t>& labels);

// The contact criterion of the solver's observables (relative_contact_area, contact extents):
// pressure > 0. One entry per pressure value.
std::vector<unsigned char> contact_mask(const ContactFields& f);

}  // namespace gfmd
