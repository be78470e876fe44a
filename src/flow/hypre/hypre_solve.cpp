// The Reynolds system solved by HYPRE's BoomerAMG under PCG (built with GFMD_WITH_HYPRE).
#ifndef OMPI_SKIP_MPICXX
#define OMPI_SKIP_MPICXX 1
#endif
#ifndef MPICH_SKIP_MPICXX
#define MPICH_SKIP_MPICXX 1
#endif

#include <HYPRE.h>
#include <HYPRE_IJ_mv.h>
#include <HYPRE_krylov.h>
#include <HYPRE_parcsr_ls.h>
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

#include <cstdlib>
#include <mutex>
#include <string>

#include "gfmd/core/error.hpp"
#include "reynolds_system.hpp"

namespace gfmd::flow_detail {

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

// Fills the outcome of a solve whose solution is already in sol.x, from HYPRE's
// iteration count and final relative residual.
void finish(LinearSolution& sol, HYPRE_Int its, HYPRE_Real res, const FlowOptions& opt) {
  sol.iterations = its;
  sol.residual = res;
  sol.converged = finite(sol) && res <= opt.tolerance;
}

// The HYPRE objects of one solve, destroyed with it.
struct Handles {
  HYPRE_IJMatrix A = nullptr;
  HYPRE_IJVector b = nullptr, x = nullptr;
  HYPRE_Solver pcg = nullptr, amg = nullptr;
  Handles() = default;
  Handles(const Handles&) = delete;
  Handles& operator=(const Handles&) = delete;
  ~Handles() {
    if (amg) HYPRE_BoomerAMGDestroy(amg);
    if (pcg) HYPRE_ParCSRPCGDestroy(pcg);
    if (x) HYPRE_IJVectorDestroy(x);
    if (b) HYPRE_IJVectorDestroy(b);
    if (A) HYPRE_IJMatrixDestroy(A);
    HYPRE_ClearAllErrors();
  }
};

// An IJ vector of the rows [first, last] held here, set to `values` (n of them).
void make_vector(MPI_Comm comm, HYPRE_BigInt first, HYPRE_BigInt last, std::size_t n,
                 const HYPRE_BigInt* rows, double* values, HYPRE_IJVector& v) {
  hypre_check(HYPRE_IJVectorCreate(comm, first, last, &v), "IJVectorCreate");
  hypre_check(HYPRE_IJVectorSetObjectType(v, HYPRE_PARCSR), "IJVectorSetObjectType");
  hypre_check(HYPRE_IJVectorInitialize(v), "IJVectorInitialize");
  if (n > 0)
    hypre_check(HYPRE_IJVectorSetValues(v, static_cast<HYPRE_Int>(n), rows, values), "IJVectorSetValues");
  hypre_check(HYPRE_IJVectorAssemble(v), "IJVectorAssemble");
}

// One right-hand side through the configured PCG (its set-up with the first): b = rhs, x
// from zero; the solution's values (the n rows held here) into xout, the iteration count and
// relative residual into sol.
void pcg_solve(Handles& h, HYPRE_ParCSRMatrix parA, std::size_t n, const HYPRE_BigInt* rows, double* rhs,
               double* zero, bool first, double* xout, LinearSolution& sol) {
  HYPRE_ParVector parb = nullptr, parx = nullptr;
  hypre_check(HYPRE_IJVectorGetObject(h.b, reinterpret_cast<void**>(&parb)), "IJVectorGetObject");
  hypre_check(HYPRE_IJVectorGetObject(h.x, reinterpret_cast<void**>(&parx)), "IJVectorGetObject");
  if (n > 0) {
    hypre_check(HYPRE_IJVectorSetValues(h.b, static_cast<HYPRE_Int>(n), rows, rhs), "IJVectorSetValues");
    hypre_check(HYPRE_IJVectorSetValues(h.x, static_cast<HYPRE_Int>(n), rows, zero), "IJVectorSetValues");
  }
  timed_pcg(
      first, sol, [&] { hypre_check(HYPRE_ParCSRPCGSetup(h.pcg, parA, parb, parx), "ParCSRPCGSetup"); },
      [&] { hypre_check(HYPRE_ParCSRPCGSolve(h.pcg, parA, parb, parx), "ParCSRPCGSolve"); });
  HYPRE_Int its = 0;
  HYPRE_Real res = 0.0;
  HYPRE_PCGGetNumIterations(h.pcg, &its);
  HYPRE_PCGGetFinalRelativeResidualNorm(h.pcg, &res);
  sol.iterations = its;
  sol.residual = res;
  if (n > 0)
    hypre_check(HYPRE_IJVectorGetValues(h.x, static_cast<HYPRE_Int>(n), rows, xout), "IJVectorGetValues");
}

// PCG preconditioned by one BoomerAMG V-cycle, the settings of every HYPRE solve here.
void configure_pcg(MPI_Comm comm, const FlowOptions& opt, HYPRE_Solver& pcg, HYPRE_Solver& amg) {
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
}

std::vector<LinearSolution> boomeramg(const LinearSystem& sys, std::size_t nrhs, const RhsFn& make_rhs,
                                      const FlowOptions& opt) {
  const MPI_Comm comm = MPI_COMM_SELF;
  const std::size_t ncell = sys.size();

  // Only the free cells are unknowns: pinned and isolated cells (P~ = 0) are dropped,
  // together with their couplings (which are zero in the reduced system anyway).
  ReducedSystem u(sys, false);
  if (u.size() == 0) return no_unknowns(ncell, nrhs);
  const auto n = static_cast<HYPRE_BigInt>(u.size());
  const CsrMatrix a = u.take_matrix();

  Handles h;
  HYPRE_IJMatrix& A = h.A;
  HYPRE_IJVector &b = h.b, &x = h.x;
  HYPRE_Solver &pcg = h.pcg, &amg = h.amg;

  std::vector<HYPRE_Int> ncols(static_cast<std::size_t>(n));
  std::vector<HYPRE_BigInt> rows(static_cast<std::size_t>(n)), cols(a.col.begin(), a.col.end());
  const Buffer<double>& vals = a.val;
  Buffer<double> rhs;  // right-hand side of the unknowns
  for (std::size_t r = 0; r < a.n; ++r) {
    rows[r] = static_cast<HYPRE_BigInt>(r);
    ncols[r] = static_cast<HYPRE_Int>(a.ptr[r + 1] - a.ptr[r]);
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
                                      const_cast<double*>(vals.data())),
              "IJMatrixSetValues");
  hypre_check(HYPRE_IJMatrixAssemble(A), "IJMatrixAssemble");
  HYPRE_ParCSRMatrix parA = nullptr;
  hypre_check(HYPRE_IJMatrixGetObject(A, reinterpret_cast<void**>(&parA)), "IJMatrixGetObject");

  std::vector<double> zero(static_cast<std::size_t>(n), 0.0);
  make_vector(comm, 0, n - 1, static_cast<std::size_t>(n), rows.data(), zero.data(), b);
  make_vector(comm, 0, n - 1, static_cast<std::size_t>(n), rows.data(), zero.data(), x);

  configure_pcg(comm, opt, pcg, amg);

  std::vector<LinearSolution> out;
  Buffer<double> xr(static_cast<std::size_t>(n));
  Buffer<double> full;
  for (std::size_t k = 0; k < nrhs; ++k) {
    make_rhs(k, full);
    u.reduce(full, rhs);
    LinearSolution sol;
    pcg_solve(h, parA, static_cast<std::size_t>(n), rows.data(), rhs.data(), zero.data(), k == 0, xr.data(),
              sol);
    u.expand(full, xr, sol.x);
    finish(sol, sol.iterations, sol.residual, opt);
    out.push_back(std::move(sol));
  }
  return out;
}

// The distributed system: every process its rows, every process one call.
std::vector<LinearSolution> boomeramg_slabs(const SlabSystem& sys, const std::vector<Buffer<double>>& rhs,
                                            const FlowOptions& opt) {
  const MPI_Comm comm = MPI_COMM_WORLD;
  const auto first = static_cast<HYPRE_BigInt>(sys.first),
             last = static_cast<HYPRE_BigInt>(sys.first + sys.count - 1);
  const auto n = static_cast<std::size_t>(sys.count);
  Handles h;
  HYPRE_IJMatrix& A = h.A;
  HYPRE_IJVector &b = h.b, &x = h.x;
  HYPRE_Solver &pcg = h.pcg, &amg = h.amg;
  std::vector<HYPRE_BigInt> rows(n), cols(sys.cols.begin(), sys.cols.end());
  std::vector<HYPRE_Int> ncols(sys.ncols.begin(), sys.ncols.end());
  for (std::size_t r = 0; r < n; ++r) rows[r] = first + static_cast<HYPRE_BigInt>(r);
  hypre_check(HYPRE_IJMatrixCreate(comm, first, last, first, last, &A), "IJMatrixCreate");
  hypre_check(HYPRE_IJMatrixSetObjectType(A, HYPRE_PARCSR), "IJMatrixSetObjectType");
  hypre_check(HYPRE_IJMatrixSetRowSizes(A, ncols.data()), "IJMatrixSetRowSizes");
  hypre_check(HYPRE_IJMatrixInitialize(A), "IJMatrixInitialize");
  if (n > 0)
    hypre_check(HYPRE_IJMatrixAddToValues(A, static_cast<HYPRE_Int>(n), ncols.data(), rows.data(),
                                          cols.data(), sys.vals.data()),
                "IJMatrixAddToValues");
  hypre_check(HYPRE_IJMatrixAssemble(A), "IJMatrixAssemble");
  HYPRE_ParCSRMatrix parA = nullptr;
  hypre_check(HYPRE_IJMatrixGetObject(A, reinterpret_cast<void**>(&parA)), "IJMatrixGetObject");
  std::vector<double> zero(n, 0.0);
  for (HYPRE_IJVector* v : {&b, &x}) make_vector(comm, first, last, n, rows.data(), zero.data(), *v);
  configure_pcg(comm, opt, pcg, amg);
  std::vector<LinearSolution> out;
  for (std::size_t k = 0; k < rhs.size(); ++k) {
    LinearSolution sol;
    sol.x.resize(n);
    pcg_solve(h, parA, n, rows.data(), const_cast<double*>(rhs[k].data()), zero.data(), k == 0, sol.x.data(),
              sol);
    finish(sol, sol.iterations, sol.residual, opt);
    out.push_back(std::move(sol));
  }
  return out;
}

}  // namespace

std::vector<LinearSolution> solve_boomeramg_slabs(const SlabSystem& sys,
                                                  const std::vector<Buffer<double>>& rhs,
                                                  const FlowOptions& opt) {
  ensure_hypre();
  const std::lock_guard<std::mutex> lock(g_hypre_mutex);
  return boomeramg_slabs(sys, rhs, opt);
}

std::vector<LinearSolution> solve_boomeramg(const LinearSystem& sys, std::size_t nrhs, const RhsFn& make_rhs,
                                            const FlowOptions& opt) {
  ensure_hypre();
  const std::lock_guard<std::mutex> lock(g_hypre_mutex);
  return boomeramg(sys, nrhs, make_rhs, opt);
}

}  // namespace gfmd::flow_detail
