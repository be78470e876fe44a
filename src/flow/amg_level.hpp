// Internals of the algebraic multigrid (private to the flow part): the level structure and
// the set-up steps (amg_setup.cpp) that amg.cpp's constructor strings together.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "gfmd/core/buffer.hpp"
#include "gfmd/flow/amg.hpp"

namespace gfmd::amg_detail {

// Loops over fewer rows than this run on one thread (a fork/join costs more).
inline constexpr std::size_t kParallelMin = std::size_t{1} << 13;
// Gauss-Seidel runs in at most kMaxBlocks blocks of at least kBlockRows rows: a function
// of the level size only, so that the results do not depend on the number of threads.
inline constexpr std::size_t kBlockRows = std::size_t{1} << 13;
inline constexpr std::size_t kMaxBlocks = 16;
// Coarsest levels up to this size are factorised; larger ones (coarsening stalled) are
// relaxed by kCoarseSweeps symmetric Gauss-Seidel sweeps.
inline constexpr std::size_t kMaxDense = 1500;
inline constexpr int kCoarseSweeps = 8;

// Block of row j among nb blocks [n b / nb, n (b + 1) / nb).
inline std::size_t block_of(std::size_t j, std::size_t n, std::size_t nb) { return ((j + 1) * nb - 1) / n; }

enum : std::uint8_t { kUndecided = 0, kCoarse = 1, kFine = 2 };

using Index = std::int32_t;

// An even number of blocks (or one), a function of the level size only.
inline std::size_t blocks_for(std::size_t n) {
  const std::size_t nb = std::min(n / kBlockRows, kMaxBlocks) & ~std::size_t{1};
  return nb < 2 ? 1 : nb;
}

}  // namespace gfmd::amg_detail

namespace gfmd {

struct AlgebraicMultigrid::Level {
  CsrMatrix a;
  // Interpolation from the next coarser level (rows: this level, columns: coarse) and its
  // transpose, the restriction; empty on the coarsest level.
  Buffer<std::size_t> p_ptr, r_ptr;
  Buffer<amg_detail::Index> p_col, r_col;
  Buffer<double> p_val, r_val;
  Buffer<double> inv_diag;
  std::size_t blocks = 1;  // Gauss-Seidel blocks (even, or 1)
  // Per row: the couplings with a lower column come first (rows are sorted by column
  // after the diagonal), `lower` of them; `interior` if every coupling stays in the
  // row's Gauss-Seidel block.
  Buffer<std::uint32_t> lower;
  Buffer<std::uint8_t> interior;
  mutable Buffer<double> x, b, r;  // work arrays

  [[nodiscard]] std::size_t n() const { return a.n; }
  [[nodiscard]] bool parallel() const { return a.n >= amg_detail::kParallelMin; }
};

}  // namespace gfmd

namespace gfmd::amg_detail {

using Level = AlgebraicMultigrid::Level;

// Strong couplings: -a_ij >= theta max_k(-a_ik), off-diagonal and negative.
std::vector<std::uint8_t> strength(const CsrMatrix& a, double theta);
// The coarse/fine splitting (kCoarse / kFine per row) from the strong couplings.
std::vector<std::uint8_t> split(const CsrMatrix& a, const std::vector<std::uint8_t>& strong);
// The interpolation from the nc coarse points into level f (and its transpose).
void build_interpolation(Level& l, const std::vector<std::uint8_t>& strong,
                         const std::vector<std::uint8_t>& state, int max_interpolation, std::size_t nc);
// The Galerkin coarse operator R A P of level f.
CsrMatrix galerkin(const Level& f, std::size_t nc);
// The diagonal inverse and Gauss-Seidel blocks of a level.
void finish_level(Level& l);
// Per-row lower counts and block-interior flags for the relaxation.
void prepare_relaxation(Level& l);

}  // namespace gfmd::amg_detail
