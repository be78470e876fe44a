// The self-affine surface of the paper authors' GFMD code (contMech, published with the paper:
// github.com/sintharic/Data-Coupling-2023-07, SRC-GFMD/gfmdSheet.cpp addSelfAffine), drawn
// from the same seed with the same random sequence and the same assignment of phases to wave
// vectors, so that a user can regenerate the realisation the paper's figures were computed on
// (indenter.generator = "contmech"; indenter.seed is their randSeed, 4711 in the paper).
//
// What their code does, and so what this does (our own implementation of those facts):
// - Random numbers: glibc's rand() after srand(seed) (the additive-feedback generator
//   r_i = r_{i-3} + r_{i-31} mod 2^32 of random(3), output r_i >> 1), each divided by
//   RAND_MAX = 2^31 - 1; the first 100 are discarded.
// - Modes: a "just large enough" grid NX x NY, NX = floor(0.1 + 2 lx/lambda_short) (NY alike),
//   is walked in its r2c order with x the full axis and y the half axis: K = 1 .. NX (NY/2+1) - 1,
//   IQX = K / (NY/2+1) folded to min(IQX, NX - IQX), IQY = K % (NY/2+1). Every mode with
//   q = sqrt(IQX^2 (2 pi/lx)^2 + IQY^2 (2 pi/ly)^2) <= 2 pi/lambda_short takes one number U
//   (in this order) and the Fourier coefficient A(q) exp(2 pi i U), A = (q lambda_long/2 pi)^(-1-H)
//   for q >= 2 pi/lambda_long (relative margin 1e-9), 0 below (no roll-off). A mode whose
//   unfolded IQX exceeds NX/2 is the negative kx = -IQX. On the self-conjugate rows (IQY = 0
//   or ny/2) a negative kx is the conjugate of the positive one already drawn, and the real
//   modes (kx = 0 or nx/2 there) are +-A: +A where 2 pi U <= pi. (So the mode kx = NX/2,
//   ky = 0, met only as -NX/2, copies the conjugate of +NX/2, which is never drawn, and stays
//   zero while its power counts in the normalisation: kept, as the published surfaces have it.)
// - Normalisation: the whole spectrum is scaled once so that its Fourier variance
//   sum_q |h~(q)|^2 (every in-band mode, weight 2 off the self-conjugate rows) equals
//   rms_height^2, or (rms_gradient) so that sum_q (IQX^2 + IQY^2) (2 pi/lx)^2 |h~|^2 equals
//   rms_gradient^2 (their code uses the x spacing for y too: the same thing on a square cell).
// - Heights: the unnormalised synthesis sum_q h~(q) exp(+i q.r) on the (x, y) grid. Their
//   rigid sheet touches the elastic one with its lowest points (gap = its height minus the
//   body's displacement), so the indenter height of SPEC §3 (towards the body) is minus theirs;
//   their shift to a zero minimum is left out (our surfaces keep a zero mean; only max(h) - h
//   enters the gap).
// Validation (tests/test_topography.cpp): the peak-to-valley heights their code printed for
// the paper's four seeds at 2048^2 (params.out of the published runs).
#pragma once

#include <cstdint>

#include "gfmd/surface/topography.hpp"

namespace gfmd {

// glibc's rand() as a value: the same sequence as srand(seed); rand() on glibc (TYPE_3, the
// default state of 128 bytes). seed 0 acts as 1, as in glibc.
class GlibcRand {
 public:
  explicit GlibcRand(std::uint32_t seed);
  // The next rand(): 0 .. 2^31 - 1.
  std::int32_t next();
  static constexpr std::int32_t kRandMax = 2147483647;

 private:
  std::uint32_t r_[34] = {};
  int front_ = 3, rear_ = 0;  // indices into the 31-word state (as glibc's fptr, rptr)
};

// Largest seed the contmech generator takes (their randSeed is an int).
inline constexpr std::uint64_t kContmechMaxSeed = 2147483647;

// The surface described above; params as for make_selfaffine (checked with
// check_selfaffine, which also refuses a roll-off and a seed above kContmechMaxSeed for this
// generator). Every process of a slab grid computes the whole spectrum (16 bytes per mode of
// the cell's half spectrum) and keeps its rows.
Topography make_selfaffine_contmech(const Grid& grid, const SelfAffineParams& params);

}  // namespace gfmd
