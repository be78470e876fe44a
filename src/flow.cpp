// Steady thin-film Reynolds flow (SPEC §6); see include/gfmd/flow.hpp for the
// discretisation. Linear solves by HYPRE (Struct PFMG-PCG or IJ BoomerAMG-PCG).
#ifndef OMPI_SKIP_MPICXX
#define OMPI_SKIP_MPICXX 1
#endif
#ifndef MPICH_SKIP_MPICXX
#define MPICH_SKIP_MPICXX 1
#endif

#include "gfmd/flow.hpp"

#include <HYPRE.h>
#include <HYPRE_IJ_mv.h>
#include <HYPRE_krylov.h>
#include <HYPRE_parcsr_ls.h>
#include <HYPRE_struct_ls.h>
#include <HYPRE_struct_mv.h>
#include <HYPRE_utilities.h>
#include <mpi.h>

#if defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(leak_sanitizer)
#define GFMD_LSAN 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__) && !defined(GFMD_LSAN)
#define GFMD_LSAN 1
#endif
#ifdef GFMD_LSAN
#include <sanitizer/lsan_interface.h>
#endif

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <mutex>
#include <numbers>
#include <string>
#include <vector>

#include "gfmd/error.hpp"
#include "gfmd/reduce.hpp"

namespace gfmd {

namespace {

// ---------------------------------------------------------------------------------------
// MPI / HYPRE set-up: once per process, lazily.

// OpenMPI keeps (and never frees) bookkeeping from MPI_Init; under LeakSanitizer those
// allocations are excluded so that sanitizer runs report only our own leaks.
struct LeakCheckPause {
#ifdef GFMD_LSAN
  LeakCheckPause() { __lsan_disable(); }
  ~LeakCheckPause() { __lsan_enable(); }
#endif
};

bool g_mpi_initialised_here = false;
std::once_flag g_hypre_once;
std::mutex g_hypre_mutex;  // HYPRE is not thread-safe: one solve at a time

void finalize_hypre_and_mpi() {
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (finalized) return;
  [[maybe_unused]] const LeakCheckPause pause;
  HYPRE_Finalize();
  if (g_mpi_initialised_here) MPI_Finalize();
}

void ensure_hypre() {
  std::call_once(g_hypre_once, [] {
    [[maybe_unused]] const LeakCheckPause pause;
    int finalized = 0;
    MPI_Finalized(&finalized);
    if (finalized) throw SolveError("flow: MPI has already been finalised; HYPRE cannot be used");
    int initialised = 0;
    MPI_Initialized(&initialised);
    if (!initialised) {
      int provided = 0;
      if (MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &provided) != MPI_SUCCESS)
        throw SolveError("flow: MPI_Init_thread failed");
      g_mpi_initialised_here = true;
    }
    HYPRE_Init();
    std::atexit(finalize_hypre_and_mpi);
  });
}

void hypre_check(HYPRE_Int ierr, const char* what) {
  // A convergence failure is judged from the residual by the caller.
  if ((ierr & ~static_cast<HYPRE_Int>(HYPRE_ERROR_CONV)) != 0) {
    char msg[256] = {0};
    HYPRE_DescribeError(ierr, msg);
    HYPRE_ClearAllErrors();
    throw SolveError(std::string("flow: HYPRE ") + what + " failed: " + msg);
  }
  if (ierr != 0) HYPRE_ClearAllErrors();
}

// ---------------------------------------------------------------------------------------
// Union-find over a periodic lattice that also tracks windings: every node stores its
// unwrapped lattice offset from its parent, so that closing a loop around the torus is
// detected (the two paths give positions that differ by a nonzero lattice period).

class WrapUnionFind {
 public:
  explicit WrapUnionFind(std::size_t n) : parent_(n), size_(n, 1), ox_(n, 0), oy_(n, 0), wrap_(n, 0) {
    for (std::size_t i = 0; i < n; ++i) parent_[i] = static_cast<std::int32_t>(i);
  }

  // Root of i and the offset of i relative to the root (with path compression).
  std::int32_t find(std::int32_t i, std::int64_t& ox, std::int64_t& oy) {
    path_.clear();
    std::int32_t r = i;
    while (parent_[r] != r) {
      path_.push_back(r);
      r = parent_[r];
    }
    // Walk back from the node nearest to the root, accumulating offsets.
    std::int64_t ax = 0, ay = 0;
    for (auto it = path_.rbegin(); it != path_.rend(); ++it) {
      ax += ox_[*it];
      ay += oy_[*it];
      ox_[*it] = ax;
      oy_[*it] = ay;
      parent_[*it] = r;
    }
    ox = (i == r) ? 0 : ox_[i];
    oy = (i == r) ? 0 : oy_[i];
    return r;
  }

  // Joins i and j, where j sits at unwrapped position pos(i) + (sx, sy).
  void unite(std::int32_t i, std::int32_t j, int sx, int sy) {
    std::int64_t oix, oiy, ojx, ojy;
    const std::int32_t ri = find(i, oix, oiy);
    const std::int32_t rj = find(j, ojx, ojy);
    const std::int64_t dx = oix + sx - ojx, dy = oiy + sy - ojy;  // pos(rj) - pos(ri)
    if (ri == rj) {
      if (dx != 0) wrap_[ri] |= 1;
      if (dy != 0) wrap_[ri] |= 2;
      return;
    }
    if (size_[ri] >= size_[rj]) {
      parent_[rj] = ri;
      ox_[rj] = dx;
      oy_[rj] = dy;
      size_[ri] += size_[rj];
      wrap_[ri] |= wrap_[rj];
    } else {
      parent_[ri] = rj;
      ox_[ri] = -dx;
      oy_[ri] = -dy;
      size_[rj] += size_[ri];
      wrap_[rj] |= wrap_[ri];
    }
  }

  std::int32_t root(std::int32_t i) {
    std::int64_t a, b;
    return find(i, a, b);
  }
  [[nodiscard]] bool wraps(std::int32_t root, int axis) const { return (wrap_[root] >> axis) & 1; }
  [[nodiscard]] bool any_wraps(int axis) const {
    for (std::size_t i = 0; i < parent_.size(); ++i)
      if (parent_[i] == static_cast<std::int32_t>(i) && ((wrap_[i] >> axis) & 1)) return true;
    return false;
  }

 private:
  std::vector<std::int32_t> parent_, size_;
  std::vector<std::int64_t> ox_, oy_;
  std::vector<unsigned char> wrap_;
  std::vector<std::int32_t> path_;
};

void check_grid(const Grid& grid, const char* where) {
  if (grid.nx < 1 || grid.ny < 1) throw InputError(where, "grid must have nx, ny >= 1");
  if (grid.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max() / 2))
    throw InputError(where, "grid too large");
  if (!(grid.lx > 0.0) || !(grid.ly > 0.0) || !std::isfinite(grid.lx) || !std::isfinite(grid.ly))
    throw InputError(where, "cell sizes lx, ly must be positive and finite");
}

bool is_pow2(int n) { return n > 0 && (n & (n - 1)) == 0; }

// Unites neighbouring cells across open faces (open_x[i]: face between i and its +x
// neighbour, open_y[i]: between i and its +y neighbour).
template <class OpenX, class OpenY>
void unite_open_faces(WrapUnionFind& uf, const Grid& grid, OpenX&& open_x, OpenY&& open_y) {
  const int nx = grid.nx, ny = grid.ny;
  for (int iy = 0; iy < ny; ++iy) {
    const int iyn = (iy + 1 == ny) ? 0 : iy + 1;
    for (int ix = 0; ix < nx; ++ix) {
      const int ixe = (ix + 1 == nx) ? 0 : ix + 1;
      const auto i = static_cast<std::int32_t>(iy * nx + ix);
      if (open_x(static_cast<std::size_t>(i))) uf.unite(i, iy * nx + ixe, 1, 0);
      if (open_y(static_cast<std::size_t>(i))) uf.unite(i, iyn * nx + ix, 0, 1);
    }
  }
}

// ---------------------------------------------------------------------------------------
// The reduced SPD system.

struct LinearSystem {
  int nx = 0, ny = 0;
  std::vector<double> diag;           // diagonal (pinned/isolated rows: identity scaled)
  std::vector<double> west;           // coupling to the -x neighbour (0 across closed or pinned)
  std::vector<double> south;          // coupling to the -y neighbour
  std::vector<unsigned char> pinned;  // not an unknown (gauge cell or no net flow): identity row
};

// Solution for one right-hand side; the set-up time is that of the preconditioner,
// counted for the first right-hand side only (the others reuse it).
struct LinearSolution {
  bool converged = false;
  double setup_s = 0.0, solve_s = 0.0;
  int iterations = 0;
  double residual = 0.0;
  std::vector<double> x;
};

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// PCG for one right-hand side: the preconditioner set-up runs for the first one only;
// both phases are timed.
template <class Setup, class Solve>
void timed_pcg(bool first, LinearSolution& sol, Setup&& setup, Solve&& solve) {
  if (first) {
    const auto t0 = std::chrono::steady_clock::now();
    setup();
    sol.setup_s = seconds_since(t0);
  }
  const auto t1 = std::chrono::steady_clock::now();
  solve();
  sol.solve_s = seconds_since(t1);
}

// Fills the outcome of a solve whose solution is already in sol.x, from HYPRE's
// iteration count and final relative residual.
void finish(LinearSolution& sol, HYPRE_Int its, HYPRE_Real res, const FlowOptions& opt) {
  sol.iterations = its;
  sol.residual = res;
  bool finite = std::isfinite(res);
  for (double v : sol.x) finite = finite && std::isfinite(v);
  sol.converged = finite && res <= opt.tolerance;
}

// One PCG solve per right-hand side, all with the same operator and preconditioner.
std::vector<LinearSolution> solve_struct(const LinearSystem& sys, const std::vector<std::vector<double>>& rhs,
                                         const FlowOptions& opt) {
  const MPI_Comm comm = MPI_COMM_SELF;
  HYPRE_Int ilower[2] = {0, 0};
  HYPRE_Int iupper[2] = {sys.nx - 1, sys.ny - 1};
  HYPRE_Int period[2] = {sys.nx, sys.ny};

  HYPRE_StructGrid sgrid = nullptr;
  HYPRE_StructStencil stencil = nullptr;
  HYPRE_StructMatrix A = nullptr;
  HYPRE_StructVector b = nullptr, x = nullptr;
  HYPRE_StructSolver pcg = nullptr, pfmg = nullptr;
  struct Cleanup {
    HYPRE_StructGrid& g;
    HYPRE_StructStencil& s;
    HYPRE_StructMatrix& A;
    HYPRE_StructVector &b, &x;
    HYPRE_StructSolver &pcg, &pfmg;
    ~Cleanup() {
      if (pfmg) HYPRE_StructPFMGDestroy(pfmg);
      if (pcg) HYPRE_StructPCGDestroy(pcg);
      if (x) HYPRE_StructVectorDestroy(x);
      if (b) HYPRE_StructVectorDestroy(b);
      if (A) HYPRE_StructMatrixDestroy(A);
      if (s) HYPRE_StructStencilDestroy(s);
      if (g) HYPRE_StructGridDestroy(g);
      HYPRE_ClearAllErrors();
    }
  } cleanup{sgrid, stencil, A, b, x, pcg, pfmg};

  hypre_check(HYPRE_StructGridCreate(comm, 2, &sgrid), "StructGridCreate");
  hypre_check(HYPRE_StructGridSetExtents(sgrid, ilower, iupper), "StructGridSetExtents");
  hypre_check(HYPRE_StructGridSetPeriodic(sgrid, period), "StructGridSetPeriodic");
  hypre_check(HYPRE_StructGridAssemble(sgrid), "StructGridAssemble");

  // Full 5-point storage (PFMG's red/black smoother needs it): centre, west, east, south,
  // north; the east/north couplings are the west/south ones of the neighbour.
  const int nx = sys.nx, ny = sys.ny;
  const std::size_t n = sys.diag.size();
  HYPRE_Int offsets[5][2] = {{0, 0}, {-1, 0}, {1, 0}, {0, -1}, {0, 1}};
  hypre_check(HYPRE_StructStencilCreate(2, 5, &stencil), "StructStencilCreate");
  for (HYPRE_Int e = 0; e < 5; ++e)
    hypre_check(HYPRE_StructStencilSetElement(stencil, e, offsets[e]), "StencilSet");

  hypre_check(HYPRE_StructMatrixCreate(comm, sgrid, stencil, &A), "StructMatrixCreate");
  hypre_check(HYPRE_StructMatrixSetSymmetric(A, 0), "StructMatrixSetSymmetric");
  hypre_check(HYPRE_StructMatrixInitialize(A), "StructMatrixInitialize");
  {
    std::vector<double> east(n), north(n);
#pragma omp parallel for schedule(static)
    for (int iy = 0; iy < ny; ++iy) {
      const int iyn = (iy + 1 == ny) ? 0 : iy + 1;
      for (int ix = 0; ix < nx; ++ix) {
        const int ixe = (ix + 1 == nx) ? 0 : ix + 1;
        const std::size_t i = static_cast<std::size_t>(iy) * nx + ix;
        east[i] = sys.west[static_cast<std::size_t>(iy) * nx + ixe];
        north[i] = sys.south[static_cast<std::size_t>(iyn) * nx + ix];
      }
    }
    const std::array<const std::vector<double>*, 5> coeffs = {&sys.diag, &sys.west, &east, &sys.south,
                                                              &north};
    for (HYPRE_Int e = 0; e < 5; ++e) {
      HYPRE_Int entry = e;
      hypre_check(HYPRE_StructMatrixSetBoxValues(A, ilower, iupper, 1, &entry,
                                                 const_cast<double*>(coeffs[e]->data())),
                  "StructMatrixSetBoxValues");
    }
  }
  hypre_check(HYPRE_StructMatrixAssemble(A), "StructMatrixAssemble");

  std::vector<double> zero(n, 0.0);
  hypre_check(HYPRE_StructVectorCreate(comm, sgrid, &b), "StructVectorCreate");
  hypre_check(HYPRE_StructVectorInitialize(b), "StructVectorInitialize");
  hypre_check(HYPRE_StructVectorCreate(comm, sgrid, &x), "StructVectorCreate");
  hypre_check(HYPRE_StructVectorInitialize(x), "StructVectorInitialize");

  hypre_check(HYPRE_StructPCGCreate(comm, &pcg), "StructPCGCreate");
  HYPRE_StructPCGSetTol(pcg, opt.tolerance);
  HYPRE_StructPCGSetAbsoluteTol(pcg, 0.0);
  HYPRE_StructPCGSetMaxIter(pcg, opt.max_iterations);
  HYPRE_StructPCGSetTwoNorm(pcg, 1);
  HYPRE_StructPCGSetRelChange(pcg, 0);
  HYPRE_StructPCGSetPrintLevel(pcg, 0);
  HYPRE_StructPCGSetLogging(pcg, 1);

  hypre_check(HYPRE_StructPFMGCreate(comm, &pfmg), "StructPFMGCreate");
  HYPRE_StructPFMGSetMaxIter(pfmg, 1);
  HYPRE_StructPFMGSetPrintLevel(pfmg, 0);
  HYPRE_StructPFMGSetTol(pfmg, 0.0);
  HYPRE_StructPFMGSetZeroGuess(pfmg);
  HYPRE_StructPFMGSetRAPType(pfmg, 0);    // Galerkin coarse operators
  HYPRE_StructPFMGSetRelaxType(pfmg, 2);  // symmetric red/black Gauss-Seidel
  HYPRE_StructPFMGSetNumPreRelax(pfmg, 1);
  HYPRE_StructPFMGSetNumPostRelax(pfmg, 1);
  HYPRE_StructPFMGSetSkipRelax(pfmg, 0);

  HYPRE_StructPFMGSetLogging(pfmg, 0);
  hypre_check(HYPRE_StructPCGSetPrecond(pcg, HYPRE_StructPFMGSolve, HYPRE_StructPFMGSetup, pfmg),
              "SetPrecond");

  std::vector<LinearSolution> out;
  for (std::size_t k = 0; k < rhs.size(); ++k) {
    hypre_check(HYPRE_StructVectorSetBoxValues(b, ilower, iupper, const_cast<double*>(rhs[k].data())),
                "SetBoxValues");
    hypre_check(HYPRE_StructVectorAssemble(b), "StructVectorAssemble");
    hypre_check(HYPRE_StructVectorSetBoxValues(x, ilower, iupper, zero.data()), "SetBoxValues");
    hypre_check(HYPRE_StructVectorAssemble(x), "StructVectorAssemble");
    LinearSolution sol;
    timed_pcg(
        k == 0, sol, [&] { hypre_check(HYPRE_StructPCGSetup(pcg, A, b, x), "StructPCGSetup"); },
        [&] { hypre_check(HYPRE_StructPCGSolve(pcg, A, b, x), "StructPCGSolve"); });
    HYPRE_Int its = 0;
    HYPRE_Real res = 0.0;
    HYPRE_StructPCGGetNumIterations(pcg, &its);
    HYPRE_StructPCGGetFinalRelativeResidualNorm(pcg, &res);
    sol.x.assign(n, 0.0);
    hypre_check(HYPRE_StructVectorGetBoxValues(x, ilower, iupper, sol.x.data()), "GetBoxValues");
    finish(sol, its, res, opt);
    out.push_back(std::move(sol));
  }
  return out;
}

std::vector<LinearSolution> solve_amg(const LinearSystem& sys,
                                      const std::vector<std::vector<double>>& rhs_list,
                                      const FlowOptions& opt) {
  const MPI_Comm comm = MPI_COMM_SELF;
  const int nx = sys.nx, ny = sys.ny;
  const std::size_t ncell = sys.diag.size();

  // Only the free cells are unknowns: pinned and isolated cells (P~ = 0) are dropped,
  // together with their couplings (which are zero in the reduced system anyway).
  std::vector<HYPRE_BigInt> index(ncell, -1);
  HYPRE_BigInt m = 0;
  for (std::size_t i = 0; i < ncell; ++i)
    if (!sys.pinned[i]) index[i] = m++;
  if (m == 0) {
    LinearSolution sol;
    sol.x.assign(ncell, 0.0);
    sol.converged = true;
    return std::vector<LinearSolution>(rhs_list.size(), sol);
  }
  const auto n = m;

  HYPRE_IJMatrix A = nullptr;
  HYPRE_IJVector b = nullptr, x = nullptr;
  HYPRE_Solver pcg = nullptr, amg = nullptr;
  struct Cleanup {
    HYPRE_IJMatrix& A;
    HYPRE_IJVector &b, &x;
    HYPRE_Solver &pcg, &amg;
    ~Cleanup() {
      if (amg) HYPRE_BoomerAMGDestroy(amg);
      if (pcg) HYPRE_ParCSRPCGDestroy(pcg);
      if (x) HYPRE_IJVectorDestroy(x);
      if (b) HYPRE_IJVectorDestroy(b);
      if (A) HYPRE_IJMatrixDestroy(A);
      HYPRE_ClearAllErrors();
    }
  } cleanup{A, b, x, pcg, amg};

  // Rows in CSR form; duplicate neighbours (nx or ny <= 2) are merged, couplings of a
  // cell to itself (nx or ny == 1) go to the diagonal.
  std::vector<HYPRE_Int> ncols(static_cast<std::size_t>(n));
  std::vector<HYPRE_BigInt> rows(static_cast<std::size_t>(n)), cols;
  std::vector<double> vals, rhs(static_cast<std::size_t>(n));  // rhs: reduced right-hand side
  cols.reserve(static_cast<std::size_t>(n) * 5);
  vals.reserve(static_cast<std::size_t>(n) * 5);
  for (int iy = 0; iy < ny; ++iy) {
    const int iyn = (iy + 1 == ny) ? 0 : iy + 1;
    const int iys = (iy == 0) ? ny - 1 : iy - 1;
    for (int ix = 0; ix < nx; ++ix) {
      const std::size_t i = static_cast<std::size_t>(iy) * nx + ix;
      if (index[i] < 0) continue;
      const int ixe = (ix + 1 == nx) ? 0 : ix + 1;
      const int ixw = (ix == 0) ? nx - 1 : ix - 1;
      const std::array<std::size_t, 5> c = {
          i, static_cast<std::size_t>(iy) * nx + ixw, static_cast<std::size_t>(iy) * nx + ixe,
          static_cast<std::size_t>(iys) * nx + ix, static_cast<std::size_t>(iyn) * nx + ix};
      const std::array<double, 5> v = {sys.diag[i], sys.west[i], sys.west[c[2]], sys.south[i],
                                       sys.south[c[4]]};
      const std::size_t start = cols.size();
      for (int e = 0; e < 5; ++e) {
        if (e > 0 && (v[e] == 0.0 || index[c[e]] < 0)) continue;
        const HYPRE_BigInt col = index[c[e]];
        std::size_t k = start;
        while (k < cols.size() && cols[k] != col) ++k;
        if (k == cols.size()) {
          cols.push_back(col);
          vals.push_back(v[e]);
        } else {
          vals[k] += v[e];
        }
      }
      const HYPRE_BigInt r = index[i];
      rows[r] = r;
      ncols[r] = static_cast<HYPRE_Int>(cols.size() - start);
    }
  }
  hypre_check(HYPRE_IJMatrixCreate(comm, 0, n - 1, 0, n - 1, &A), "IJMatrixCreate");
  hypre_check(HYPRE_IJMatrixSetObjectType(A, HYPRE_PARCSR), "IJMatrixSetObjectType");
  {
    std::vector<HYPRE_Int> offd(static_cast<std::size_t>(n), 0);
    hypre_check(HYPRE_IJMatrixSetDiagOffdSizes(A, ncols.data(), offd.data()), "IJMatrixSetDiagOffdSizes");
  }
  hypre_check(HYPRE_IJMatrixSetMaxOffProcElmts(A, 0), "IJMatrixSetMaxOffProcElmts");
  hypre_check(HYPRE_IJMatrixInitialize(A), "IJMatrixInitialize");
  hypre_check(HYPRE_IJMatrixSetValues(A, static_cast<HYPRE_Int>(n), ncols.data(), rows.data(), cols.data(),
                                      vals.data()),
              "IJMatrixSetValues");
  hypre_check(HYPRE_IJMatrixAssemble(A), "IJMatrixAssemble");
  HYPRE_ParCSRMatrix parA = nullptr;
  hypre_check(HYPRE_IJMatrixGetObject(A, reinterpret_cast<void**>(&parA)), "IJMatrixGetObject");

  std::vector<double> zero(static_cast<std::size_t>(n), 0.0);
  hypre_check(HYPRE_IJVectorCreate(comm, 0, n - 1, &b), "IJVectorCreate");
  hypre_check(HYPRE_IJVectorSetObjectType(b, HYPRE_PARCSR), "IJVectorSetObjectType");
  hypre_check(HYPRE_IJVectorInitialize(b), "IJVectorInitialize");
  hypre_check(HYPRE_IJVectorSetValues(b, static_cast<HYPRE_Int>(n), rows.data(), zero.data()),
              "IJVectorSetValues");
  hypre_check(HYPRE_IJVectorAssemble(b), "IJVectorAssemble");
  hypre_check(HYPRE_IJVectorCreate(comm, 0, n - 1, &x), "IJVectorCreate");
  hypre_check(HYPRE_IJVectorSetObjectType(x, HYPRE_PARCSR), "IJVectorSetObjectType");
  hypre_check(HYPRE_IJVectorInitialize(x), "IJVectorInitialize");
  hypre_check(HYPRE_IJVectorSetValues(x, static_cast<HYPRE_Int>(n), rows.data(), zero.data()),
              "IJVectorSetValues");
  hypre_check(HYPRE_IJVectorAssemble(x), "IJVectorAssemble");
  HYPRE_ParVector parb = nullptr, parx = nullptr;
  hypre_check(HYPRE_IJVectorGetObject(b, reinterpret_cast<void**>(&parb)), "IJVectorGetObject");
  hypre_check(HYPRE_IJVectorGetObject(x, reinterpret_cast<void**>(&parx)), "IJVectorGetObject");

  hypre_check(HYPRE_ParCSRPCGCreate(comm, &pcg), "ParCSRPCGCreate");
  HYPRE_PCGSetTol(pcg, opt.tolerance);
  HYPRE_PCGSetAbsoluteTol(pcg, 0.0);
  HYPRE_PCGSetMaxIter(pcg, opt.max_iterations);
  HYPRE_PCGSetTwoNorm(pcg, 1);
  HYPRE_PCGSetRelChange(pcg, 0);
  HYPRE_PCGSetPrintLevel(pcg, 0);
  HYPRE_PCGSetLogging(pcg, 1);

  // Ruge-Stueben coarsening with classical (modified) interpolation: on the 2048^2
  // benchmark gap (bench/bench_flow) its set-up takes about 60 % of that of HMIS +
  // extended+i interpolation at nearly the same iteration count (12 against 11).
  hypre_check(HYPRE_BoomerAMGCreate(&amg), "BoomerAMGCreate");
  HYPRE_BoomerAMGSetPrintLevel(amg, 0);
  HYPRE_BoomerAMGSetMaxIter(amg, 1);
  HYPRE_BoomerAMGSetTol(amg, 0.0);
  HYPRE_BoomerAMGSetCoarsenType(amg, 6);  // Falgout (Ruge-Stueben on one process)
  HYPRE_BoomerAMGSetInterpType(amg, 0);   // classical modified
  HYPRE_BoomerAMGSetPMaxElmts(amg, 4);
  HYPRE_BoomerAMGSetStrongThreshold(amg, 0.25);
  // One forward Gauss-Seidel sweep on the way down and one backward sweep on the way up:
  // a symmetric V-cycle (as PCG needs) at half the smoothing cost of symmetric sweeps at
  // both ends (2048^2 benchmark: 14 instead of 13 iterations, PCG 3.0 s instead of 4.7 s).
  HYPRE_BoomerAMGSetCycleRelaxType(amg, 3, 1);  // down: hybrid forward Gauss-Seidel
  HYPRE_BoomerAMGSetCycleRelaxType(amg, 4, 2);  // up: hybrid backward Gauss-Seidel
  HYPRE_BoomerAMGSetCycleRelaxType(amg, 9, 3);  // coarsest: Gaussian elimination
  HYPRE_BoomerAMGSetNumSweeps(amg, 1);
  hypre_check(HYPRE_PCGSetPrecond(pcg, reinterpret_cast<HYPRE_PtrToSolverFcn>(HYPRE_BoomerAMGSolve),
                                  reinterpret_cast<HYPRE_PtrToSolverFcn>(HYPRE_BoomerAMGSetup), amg),
              "PCGSetPrecond");

  std::vector<LinearSolution> out;
  std::vector<double> xr(static_cast<std::size_t>(n));
  for (std::size_t k = 0; k < rhs_list.size(); ++k) {
    for (std::size_t i = 0; i < ncell; ++i)
      if (index[i] >= 0) rhs[static_cast<std::size_t>(index[i])] = rhs_list[k][i];
    hypre_check(HYPRE_IJVectorSetValues(b, static_cast<HYPRE_Int>(n), rows.data(), rhs.data()),
                "IJVectorSetValues");
    hypre_check(HYPRE_IJVectorSetValues(x, static_cast<HYPRE_Int>(n), rows.data(), zero.data()),
                "IJVectorSetValues");
    LinearSolution sol;
    timed_pcg(
        k == 0, sol, [&] { hypre_check(HYPRE_ParCSRPCGSetup(pcg, parA, parb, parx), "ParCSRPCGSetup"); },
        [&] { hypre_check(HYPRE_ParCSRPCGSolve(pcg, parA, parb, parx), "ParCSRPCGSolve"); });
    HYPRE_Int its = 0;
    HYPRE_Real res = 0.0;
    HYPRE_PCGGetNumIterations(pcg, &its);
    HYPRE_PCGGetFinalRelativeResidualNorm(pcg, &res);
    hypre_check(HYPRE_IJVectorGetValues(x, static_cast<HYPRE_Int>(n), rows.data(), xr.data()),
                "IJVectorGetValues");
    sol.x.assign(ncell, 0.0);
    for (std::size_t i = 0; i < ncell; ++i)
      if (index[i] >= 0) sol.x[i] = xr[static_cast<std::size_t>(index[i])];
    finish(sol, its, res, opt);
    out.push_back(std::move(sol));
  }
  return out;
}

std::vector<FlowResult> solve_flow_impl(const Grid& grid, const double* gap,
                                        const std::vector<double>& angles, const FlowOptions& opt,
                                        detail::FlowSolver which) {
  check_grid(grid, "flow");
  if (gap == nullptr) throw InputError("flow", "gap field is null");
  if (angles.empty()) throw InputError("flow", "no flow direction given");
  for (double a : angles)
    if (!std::isfinite(a)) throw InputError("flow", "angle must be finite");
  if (!(opt.tolerance > 0.0) || !(opt.tolerance < 1.0))
    throw InputError("flow", "tolerance must be in (0, 1)");
  if (opt.max_iterations < 1) throw InputError("flow", "max_iterations must be >= 1");
  const int nx = grid.nx, ny = grid.ny;
  const std::size_t n = grid.size();
  const bool struct_ok = is_pow2(nx) && is_pow2(ny) && nx >= 4 && ny >= 4;
  if (which == detail::FlowSolver::StructPFMG && !struct_ok)
    throw InputError("flow", "the Struct PFMG solver needs nx, ny powers of two >= 4");

  double gmax = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(gap[i])) throw InputError("flow", "non-finite gap at index " + std::to_string(i));
    gmax = std::max(gmax, gap[i]);
  }

  const double dx = grid.dx(), dy = grid.dy();
  const double wx = dy / dx, wy = dx / dy;

  std::vector<FlowResult> results(angles.size());
  const double mean_gap =
      grid_sum(grid, [&](std::size_t i) { return std::max(gap[i], 0.0); }) / static_cast<double>(n);
  const double mean_gap_cubed = grid_sum(grid,
                                         [&](std::size_t i) {
                                           const double g = std::max(gap[i], 0.0);
                                           return g * g * g;
                                         }) /
                                static_cast<double>(n);
  for (std::size_t k = 0; k < angles.size(); ++k) {
    FlowResult& res = results[k];
    res.angle_deg = angles[k];
    res.qx.assign(n, 0.0);
    res.qy.assign(n, 0.0);
    res.mean_gap = mean_gap;
    res.mean_gap_cubed = mean_gap_cubed;
  }
  if (!(gmax > 0.0)) return results;  // everything closed: no flow

  // Normalised cell and face conductances: kn = (g / gmax)^3, physical k = kscale * kn.
  const double kscale = gmax * gmax * gmax;
  std::vector<double> kn(n), kfx(n), kfy(n);
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const double g = std::max(gap[i], 0.0) / gmax;
    kn[i] = g * g * g;
  }
  auto harmonic = [](double ki, double kj) {
    return (ki > 0.0 && kj > 0.0) ? 2.0 * ki * kj / (ki + kj) : 0.0;
  };
#pragma omp parallel for schedule(static)
  for (int iy = 0; iy < ny; ++iy) {
    const int iyn = (iy + 1 == ny) ? 0 : iy + 1;
    for (int ix = 0; ix < nx; ++ix) {
      const int ixe = (ix + 1 == nx) ? 0 : ix + 1;
      const std::size_t i = static_cast<std::size_t>(iy) * nx + ix;
      kfx[i] = harmonic(kn[i], kn[static_cast<std::size_t>(iy) * nx + ixe]);
      kfy[i] = harmonic(kn[i], kn[static_cast<std::size_t>(iyn) * nx + ix]);
    }
  }

  // Connected components over open faces; windings give the percolation flags.
  // A component that winds around the cell in no direction (a trapped pocket, an isolated
  // cell) carries no flow: its total pressure is constant. Such "still" cells are not
  // unknowns (their currents are zero); neither is one gauge cell (the root, P~ = 0) of
  // every winding component.
  WrapUnionFind uf(n);
  unite_open_faces(
      uf, grid, [&](std::size_t i) { return kfx[i] > 0.0; }, [&](std::size_t i) { return kfy[i] > 0.0; });
  const bool wraps_x = uf.any_wraps(0), wraps_y = uf.any_wraps(1);
  std::vector<unsigned char> pinned(n), still(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::int32_t r = uf.root(static_cast<std::int32_t>(i));
    still[i] = !(uf.wraps(r, 0) || uf.wraps(r, 1));
    pinned[i] = still[i] || r == static_cast<std::int32_t>(i);
  }

  // Operator (independent of the direction; G = 1).
  LinearSystem sys;
  sys.nx = nx;
  sys.ny = ny;
  sys.diag.assign(n, 0.0);
  sys.west.assign(n, 0.0);
  sys.south.assign(n, 0.0);
  sys.pinned = pinned;
  const double identity = 2.0 * (wx + wy);
#pragma omp parallel for schedule(static)
  for (int iy = 0; iy < ny; ++iy) {
    const int iys = (iy == 0) ? ny - 1 : iy - 1;
    for (int ix = 0; ix < nx; ++ix) {
      const int ixw = (ix == 0) ? nx - 1 : ix - 1;
      const std::size_t i = static_cast<std::size_t>(iy) * nx + ix;
      const std::size_t iw = static_cast<std::size_t>(iy) * nx + ixw;
      const std::size_t is = static_cast<std::size_t>(iys) * nx + ix;
      const double d = wx * (kfx[i] + kfx[iw]) + wy * (kfy[i] + kfy[is]);
      if (pinned[i]) {
        sys.diag[i] = d > 0.0 ? d : identity;
        continue;  // couplings stay zero, rhs 0
      }
      sys.diag[i] = d;
      // Couplings to a pinned neighbour vanish (symmetric elimination); those stored at
      // the +x/+y neighbour of a pinned cell are that neighbour's west/south entries.
      sys.west[i] = pinned[iw] ? 0.0 : -wx * kfx[iw];
      sys.south[i] = pinned[is] ? 0.0 : -wy * kfy[is];
    }
  }
  // Right-hand sides, one per direction d = (cos a, sin a).
  std::vector<std::vector<double>> rhs(angles.size(), std::vector<double>(n, 0.0));
  for (std::size_t k = 0; k < angles.size(); ++k) {
    const double a = angles[k] * std::numbers::pi / 180.0;
    const double dxd = std::cos(a), dyd = std::sin(a);
    std::vector<double>& b = rhs[k];
#pragma omp parallel for schedule(static)
    for (int iy = 0; iy < ny; ++iy) {
      const int iys = (iy == 0) ? ny - 1 : iy - 1;
      for (int ix = 0; ix < nx; ++ix) {
        const int ixw = (ix == 0) ? nx - 1 : ix - 1;
        const std::size_t i = static_cast<std::size_t>(iy) * nx + ix;
        if (pinned[i]) continue;
        const std::size_t iw = static_cast<std::size_t>(iy) * nx + ixw;
        const std::size_t is = static_cast<std::size_t>(iys) * nx + ix;
        b[i] = dxd * dy * (kfx[iw] - kfx[i]) + dyd * dx * (kfy[is] - kfy[i]);
      }
    }
  }

  // Back end. PFMG's operator-dependent interpolation breaks down (the preconditioner
  // stops being positive definite) on fields with closed faces, so the structured solver
  // is used only when every face is open; everything else goes to BoomerAMG, which is
  // also the fallback if the structured solve fails. One set-up serves all directions.
  bool all_open = true;
  for (std::size_t i = 0; i < n && all_open; ++i) all_open = kfx[i] > 0.0 && kfy[i] > 0.0;
  const bool use_struct =
      which == detail::FlowSolver::StructPFMG || (which == detail::FlowSolver::Auto && struct_ok && all_open);
  // From here on every block comes from the heap (HYPRE's set-up makes many short-lived
  // grid-sized allocations); the scope ends after the last of them is freed, when the
  // free heap pages go back to the system. The results' fields were allocated above.
  const HeapAllocationScope heap_only(512 * n);
  std::vector<LinearSolution> sols;
  {
    ensure_hypre();
    std::lock_guard<std::mutex> lock(g_hypre_mutex);
    std::string failure;
    if (use_struct) {
      try {
        sols = solve_struct(sys, rhs, opt);
        for (const LinearSolution& sol : sols)
          if (!sol.converged && failure.empty())
            failure = "Struct PFMG-PCG reached relative residual " + std::to_string(sol.residual) +
                      " after " + std::to_string(sol.iterations) + " iterations";
      } catch (const SolveError& e) {
        failure = e.what();
      }
      if (!failure.empty() && which == detail::FlowSolver::StructPFMG)
        throw SolveError(failure.rfind("flow: ", 0) == 0 ? failure : "flow: " + failure);
    }
    if (!use_struct || !failure.empty()) {
      sols = solve_amg(sys, rhs, opt);
      for (const LinearSolution& sol : sols)
        if (!sol.converged) {
          if (!failure.empty()) failure += "; then ";
          failure += "BoomerAMG-PCG reached relative residual " + std::to_string(sol.residual) + " after " +
                     std::to_string(sol.iterations) + " iterations";
          throw SolveError("flow: linear solve did not converge to " + std::to_string(opt.tolerance) + ": " +
                           failure);
        }
    }
  }

  std::vector<double> qxf(n), qyf(n);
  for (std::size_t k = 0; k < angles.size(); ++k) {
    FlowResult& res = results[k];
    const double a = angles[k] * std::numbers::pi / 180.0;
    const double dxd = std::cos(a), dyd = std::sin(a);
    res.percolates = std::abs(dxd) >= std::abs(dyd) ? wraps_x : wraps_y;
    res.iterations = sols[k].iterations;
    res.residual = sols[k].residual;
    res.setup_s = sols[k].setup_s;
    res.solve_s = sols[k].solve_s;
    const std::vector<double>& P = sols[k].x;

    // Face current densities (physical units, G = 1) and cell-centred averages.
#pragma omp parallel for schedule(static)
    for (int iy = 0; iy < ny; ++iy) {
      const int iyn = (iy + 1 == ny) ? 0 : iy + 1;
      for (int ix = 0; ix < nx; ++ix) {
        const int ixe = (ix + 1 == nx) ? 0 : ix + 1;
        const std::size_t i = static_cast<std::size_t>(iy) * nx + ix;
        const std::size_t ie = static_cast<std::size_t>(iy) * nx + ixe;
        const std::size_t in = static_cast<std::size_t>(iyn) * nx + ix;
        qxf[i] = (kfx[i] > 0.0 && !still[i]) ? -kscale * kfx[i] * (P[ie] - P[i] - dxd * dx) / dx : 0.0;
        qyf[i] = (kfy[i] > 0.0 && !still[i]) ? -kscale * kfy[i] * (P[in] - P[i] - dyd * dy) / dy : 0.0;
      }
    }
#pragma omp parallel for schedule(static)
    for (int iy = 0; iy < ny; ++iy) {
      const int iys = (iy == 0) ? ny - 1 : iy - 1;
      for (int ix = 0; ix < nx; ++ix) {
        const int ixw = (ix == 0) ? nx - 1 : ix - 1;
        const std::size_t i = static_cast<std::size_t>(iy) * nx + ix;
        res.qx[i] = 0.5 * (qxf[i] + qxf[static_cast<std::size_t>(iy) * nx + ixw]);
        res.qy[i] = 0.5 * (qyf[i] + qyf[static_cast<std::size_t>(iys) * nx + ix]);
      }
    }
    const double mqx = grid_sum(grid, [&](std::size_t i) { return qxf[i]; }) / static_cast<double>(n);
    const double mqy = grid_sum(grid, [&](std::size_t i) { return qyf[i]; }) / static_cast<double>(n);
    res.conductivity = mqx * dxd + mqy * dyd;
    res.conductivity_transverse = -mqx * dyd + mqy * dxd;
    res.flow_factor =
        res.mean_gap > 0.0 ? res.conductivity / (res.mean_gap * res.mean_gap * res.mean_gap) : 0.0;

    // Conservation: total current through every column of x faces / row of y faces,
    // expressed as mean current densities (divide by the cross-section length).
    std::vector<double> col(static_cast<std::size_t>(nx), 0.0), row(static_cast<std::size_t>(ny), 0.0);
    for (int iy = 0; iy < ny; ++iy) {
      double r = 0.0;
      for (int ix = 0; ix < nx; ++ix) {
        const std::size_t i = static_cast<std::size_t>(iy) * nx + ix;
        col[ix] += qxf[i];
        r += qyf[i];
      }
      row[iy] = r;
    }
    for (double& c : col) c /= ny;  // = column total / ly
    for (double& r : row) r /= nx;  // = row total / lx
    const double scale = std::max(std::abs(mqx), std::abs(mqy));
    double dev = 0.0;
    for (double c : col) dev = std::max(dev, std::abs(c - mqx));
    for (double r : row) dev = std::max(dev, std::abs(r - mqy));
    res.conservation_error = scale > 0.0 ? dev / scale : 0.0;
  }
  return results;
}

}  // namespace

FlowResult solve_flow(const Grid& grid, const double* gap, double angle_deg, const FlowOptions& opt) {
  return std::move(solve_flow_impl(grid, gap, {angle_deg}, opt, detail::FlowSolver::Auto).front());
}

std::vector<FlowResult> solve_flow(const Grid& grid, const double* gap, const std::vector<double>& angles_deg,
                                   const FlowOptions& opt) {
  return solve_flow_impl(grid, gap, angles_deg, opt, detail::FlowSolver::Auto);
}

FlowResult detail::solve_flow(const Grid& grid, const double* gap, double angle_deg, const FlowOptions& opt,
                              FlowSolver solver) {
  return std::move(solve_flow_impl(grid, gap, {angle_deg}, opt, solver).front());
}

std::vector<FlowResult> detail::solve_flow(const Grid& grid, const double* gap,
                                           const std::vector<double>& angles_deg, const FlowOptions& opt,
                                           FlowSolver solver) {
  return solve_flow_impl(grid, gap, angles_deg, opt, solver);
}

double bruggeman_2d(const std::vector<double>& k) {
  if (k.empty()) throw InputError("bruggeman_2d", "empty list of conductivities");
  std::size_t zeros = 0;
  double kmin = std::numeric_limits<double>::infinity(), kmax = 0.0;
  for (double v : k) {
    if (!std::isfinite(v) || v < 0.0)
      throw InputError("bruggeman_2d", "conductivities must be finite and >= 0");
    if (v == 0.0) {
      ++zeros;
    } else {
      kmin = std::min(kmin, v);
      kmax = std::max(kmax, v);
    }
  }
  if (2 * zeros >= k.size()) return 0.0;
  if (kmin == kmax && zeros == 0) return kmax;
  // f(K) = sum (K_i - K)/(K_i + K) decreases strictly from n_pos - n_zero > 0 (K -> 0+)
  // to -n (K -> inf); f(kmax) <= 0. Find a lower bracket, then bisect in log K.
  // Written without the cancellation between terms near +1 and -1: a term with K_i > K
  // is 1 - 2K/(K_i + K), one with K_i <= K is -1 + 2K_i/(K_i + K); the +-1 are counted.
  auto f = [&](double K) {
    long count = 0;
    double s = 0.0;
    for (double v : k) {
      if (v > K) {
        ++count;
        s -= 2.0 * K / (v + K);
      } else {
        --count;
        s += 2.0 * v / (v + K);
      }
    }
    return static_cast<double>(count) + s;
  };
  double hi = kmax, lo = kmin;
  while (f(lo) <= 0.0) lo *= 0.5;  // terminates: f(0+) > 0
  if (f(hi) >= 0.0) return hi;
  for (int it = 0; it < 200; ++it) {
    const double mid = std::sqrt(lo * hi);
    if (!(mid > lo && mid < hi)) break;
    if (f(mid) > 0.0) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  // Final secant step between the brackets for full precision.
  const double flo = f(lo), fhi = f(hi);
  const double K = (flo - fhi) != 0.0 ? lo + (hi - lo) * flo / (flo - fhi) : 0.5 * (lo + hi);
  return std::clamp(K, lo, hi);
}

bool percolates(const Grid& grid, const double* gap, int axis) {
  check_grid(grid, "percolates");
  if (gap == nullptr) throw InputError("percolates", "gap field is null");
  if (axis != 0 && axis != 1) throw InputError("percolates", "axis must be 0 (x) or 1 (y)");
  const int nx = grid.nx, ny = grid.ny;
  WrapUnionFind uf(grid.size());
  unite_open_faces(
      uf, grid,
      [&](std::size_t i) {
        const std::size_t ix = i % nx, iy = i / nx;
        return gap[i] > 0.0 && gap[iy * nx + (ix + 1 == static_cast<std::size_t>(nx) ? 0 : ix + 1)] > 0.0;
      },
      [&](std::size_t i) {
        const std::size_t ix = i % nx, iy = i / nx;
        return gap[i] > 0.0 && gap[(iy + 1 == static_cast<std::size_t>(ny) ? 0 : iy + 1) * nx + ix] > 0.0;
      });
  return uf.any_wraps(axis);
}

}  // namespace gfmd
