// Algebraic multigrid (classical Ruge-Stueben) for sparse symmetric positive definite
// M-matrix-like systems, and conjugate gradients preconditioned by it: the linear solver
// of the Reynolds flow (gfmd/flow.hpp).
//
// Method (Ruge & Stueben 1987; the choices follow HYPRE's BoomerAMG with Ruge-Stueben
// coarsening and classical modified interpolation, which the flow solver used before):
// * strength: j is a strong neighbour of i if -a_ij >= theta max_k(-a_ik) (theta = 0.25);
// * coarse points: the Ruge-Stueben first pass (a maximal set of points that many others
//   depend on strongly, picked greedily), run in fixed blocks of rows side by side with
//   the strong couplings inside each block, then the second pass that makes sure two
//   strongly connected fine points share a coarse point;
// * interpolation to a fine point i from its strong coarse neighbours C_i: classical
//   ("modified") weights, strong fine neighbours distributed over C_i by their own negative
//   couplings, weak and positive couplings lumped into the diagonal; at most
//   max_interpolation weights per row (the largest, rescaled to keep the row sum);
// * coarse operators: Galerkin products P^T A P;
// * V(1,1)-cycle: Gauss-Seidel forward before the coarse correction and backward after it,
//   a dense Cholesky factorisation on the coarsest level: a symmetric positive definite
//   preconditioner. Gauss-Seidel runs in an even number of fixed blocks of rows, the even
//   blocks side by side, then the odd ones (a level whose blocks of one colour couple to
//   each other is relaxed in one sequential sweep).
// Set-up and cycle are shared among the OpenMP threads; the blocks, the chunks, the orders
// and the sums do not depend on the thread count, so neither do the results.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "gfmd/core/buffer.hpp"

namespace gfmd {

// Square sparse matrix in compressed rows. Row i holds entries ptr[i] .. ptr[i+1]-1; the
// diagonal must be present (a positive number) and stored first in its row.
struct CsrMatrix {
  std::size_t n = 0;
  Buffer<std::size_t> ptr;  // n + 1
  Buffer<std::int32_t> col;
  Buffer<double> val;

  [[nodiscard]] std::size_t nnz() const { return col.size(); }
  // y = A x (rows shared among the threads).
  void multiply(const double* x, double* y) const;
};

struct AmgOptions {
  double strength = 0.25;          // theta of the strength of connection
  int max_interpolation = 4;       // weights kept per interpolated row
  std::size_t max_coarsest = 400;  // coarsening stops at or below this many unknowns
  int max_levels = 30;
};

class AlgebraicMultigrid {
 public:
  // Builds the hierarchy. Throws InputError("amg", ...) for an ill-formed matrix (sizes,
  // column indices, diagonal not first) and SolveError for a non-positive or non-finite
  // diagonal or a non-finite entry.
  explicit AlgebraicMultigrid(CsrMatrix a, const AmgOptions& opt = {});
  ~AlgebraicMultigrid();
  AlgebraicMultigrid(const AlgebraicMultigrid&) = delete;
  AlgebraicMultigrid& operator=(const AlgebraicMultigrid&) = delete;

  [[nodiscard]] std::size_t size() const;  // unknowns of the finest level
  [[nodiscard]] int levels() const;        // including the finest and the coarsest
  [[nodiscard]] std::size_t level_size(int level) const;
  [[nodiscard]] std::size_t level_nnz(int level) const;
  // Sum of the entries of all level operators over those of the finest one.
  [[nodiscard]] double operator_complexity() const;
  [[nodiscard]] const CsrMatrix& matrix() const;  // the finest operator

  // z = M r: one V(1,1)-cycle from a zero initial guess. Not reentrant (work arrays).
  void precondition(const double* r, double* z) const;

  // For tests: the operator of a level, and the interpolation from level + 1 to level
  // (fine = P coarse, overwriting fine).
  [[nodiscard]] const CsrMatrix& level_matrix(int level) const;
  void interpolate(int level, const double* coarse, double* fine) const;

  struct Level;  // one level of the hierarchy (defined in amg.cpp)

 private:
  std::vector<std::unique_ptr<Level>> levels_;
  std::vector<double> chol_;  // dense Cholesky factor of the coarsest operator (lower)
  void cycle(std::size_t l, const double* b, double* x) const;
  void coarse_solve(const double* b, double* x) const;
};

struct CgOutcome {
  bool converged = false;
  int iterations = 0;
  double residual = 0.0;  // ||b - A x||_2 / reference, recomputed from x at the end
};

// Conjugate gradients on A x = b (A the finest operator of mg) preconditioned by one
// V-cycle per iteration, from x = 0, until the recursively updated residual satisfies
// ||r||_2 <= tolerance * reference_norm (reference_norm <= 0: ||b||_2) or max_iterations
// are done. A zero b gives x = 0. A breakdown (non-positive curvature, non-finite numbers)
// ends the iteration unconverged. Deterministic for any thread count. stop_request (may be
// empty) is polled every iteration; true throws gfmd::Interrupted.
CgOutcome amg_pcg(const AlgebraicMultigrid& mg, const double* b, double* x, double tolerance,
                  int max_iterations, double reference_norm = 0.0,
                  const std::function<bool()>& stop_request = {});

}  // namespace gfmd
