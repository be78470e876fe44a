// Steady thin-film (Reynolds) flow through the gap between the indenter and the deformed
// surface (SPEC §6).
//
// Physics. The local conductivity is k = g^3 (g = gap; g <= 0 counts as contact, k = 0).
// The pressure solves div(k grad P) = 0 on the periodic nx x ny cell with an imposed mean
// gradient of magnitude G along the unit direction d = (cos a, sin a):
// P(r) = -G d.r + P~(r), P~ periodic. The current density is q = -k grad P (per unit
// width), so a positive G drives a positive mean current along d. The fluid pressure
// does not act back on the solid.
//
// Discretisation (finite volumes, cell-centred). Cell (ix, iy) is centred on the grid
// node x = ix*dx, y = iy*dy and carries k_i = g_i^3 and P~_i. Neighbouring cells i, j
// (4-neighbours, periodic) are joined by a face of conductance
//     k_f = 2 k_i k_j / (k_i + k_j)            (harmonic mean; 0 if k_i or k_j is 0).
// The current density through the face between i and its +x neighbour j is
//     qx_f = -k_f (P~_j - P~_i - G d_x dx) / dx            (the face carries qx_f * dy),
// and through the face between i and its +y neighbour j
//     qy_f = -k_f (P~_j - P~_i - G d_y dy) / dy            (the face carries qy_f * dx),
// i.e. -k_f times the difference quotient of the full pressure P. Mass conservation in
// every cell (sum of outgoing face currents = 0) gives the periodic 5-point system
//     sum_f w_f k_f (P~_i - P~_j(f)) = G sum_f w_f k_f s_f h_f d_f ,
// with w = dy/dx (x faces), dx/dy (y faces), s_f = +1 for the -x/-y face and -1 for the
// +x/+y face, h_f = dx or dy. For stripes this reproduces exactly the arithmetic mean of
// g^3 for stripes along the flow and the harmonic mean of g^3 for stripes across it.
//
// Singularity. The matrix is singular: constants on each connected component of cells
// joined by open faces (k_f > 0) are in its null space, and cells whose four faces are
// closed are fully decoupled. Components are found by union-find (with windings). A
// component that wraps around the periodic cell in no direction (trapped pocket, isolated
// open cell) carries no current (its total pressure is constant): its cells are not
// unknowns and their currents are set to exactly zero. Each wrapping component has one
// pinned cell (P~ = 0, its couplings moved to the right-hand side, where they vanish):
// the pinned equation is implied by the others (the sum of a component's equations is
// identically zero), so the fluxes are unaffected; the pressure gauge is arbitrary per
// component. The system of the remaining unknowns is symmetric positive definite.
//
// Linear solver (default): our algebraic multigrid (gfmd/amg.hpp, OpenMP) under PCG, to
// the relative residual ||b - A x||_2 / ||b||_2 <= tolerance of the system above.
// * Red-black reduction: when nx and ny are even, a cell with ix + iy odd couples only to
//   cells with ix + iy even, so the odd ("black") unknowns are eliminated exactly and the
//   solve runs on the even ones (half the unknowns, nine couplings each: the Schur
//   complement, formed without cancellation); the black values follow from their own
//   equations afterwards. Other grids are solved on all unknowns.
// * Ruge-Stueben AMG (BoomerAMG's classical settings), a symmetric V(1,1)-cycle: 11-12 PCG
//   iterations at 1e-8 for rough gaps with 5-40 % closed cells at 2048^2, and for
//   conductances spread over many decades.
// * Fallback: if it has not converged after FlowOptions::amg_iterations_before_fallback
//   iterations, the system is solved again with HYPRE's BoomerAMG (IJ/ParCSR interface,
//   Ruge-Stueben coarsening, classical modified interpolation, forward/backward
//   Gauss-Seidel) under HYPRE's PCG; FlowResult::solver says which solver answered.
// The operator does not depend on the direction of the imposed gradient: several
// directions share one assembly and one set-up. The conductances are normalised by
// max(k) before assembly (the solution does not depend on that scale). Results do not
// depend on the number of threads (fixed blocks and orders everywhere). HYPRE is serial
// (Debian's build has no OpenMP); MPI is initialised lazily the first time HYPRE is needed
// (MPI_Init_thread as a singleton; no mpirun needed) unless the program already did, and
// MPI_Finalize is then registered with atexit; each HYPRE solve runs on MPI_COMM_SELF,
// serialised by a mutex.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "gfmd/core/fft.hpp"
#include "gfmd/core/grid.hpp"

namespace gfmd {

// Linear solver of the flow: Auto (ours, BoomerAMG if it does not converge in time), Amg
// (ours only; SolveError if it does not converge within max_iterations) or BoomerAMG
// (HYPRE's only).
enum class FlowSolver { Auto, Amg, BoomerAMG };

// "auto", "amg", "boomeramg" (config key flow.solver, gfmd flow --solver); false if the
// name is none of these. flow_solver_name is the inverse.
bool parse_flow_solver(const std::string& name, FlowSolver& out);
std::string flow_solver_name(FlowSolver solver);

struct FlowOptions {
  double tolerance = 1e-10;   // relative residual ||b - A x|| / ||b|| of the linear solve
  int max_iterations = 1000;  // PCG iterations
  FlowSolver solver = FlowSolver::Auto;
  // PCG iterations of our AMG after which the automatic choice gives up and solves with
  // HYPRE's BoomerAMG instead (typical counts are 10-20).
  int amg_iterations_before_fallback = 200;
  // Faces whose conductance is below this fraction of the largest possible one (that of
  // two cells with the largest gap, g_max^3) count as closed in the linear solve: their
  // current is below what double precision resolves next to the open channels, and
  // regions joined to the rest through such faces only make the system too ill-conditioned
  // for any preconditioned CG (condition numbers beyond 1e15 break it down). 1e-12 is a
  // gap below about 1e-4 g_max on both sides of the face. 0 keeps every open face. The
  // percolation flag does not depend on it (it is geometric: g > 0).
  double closed_face_conductance = 1e-12;
  // Polled between set-up and solve stages and every PCG iteration of our AMG (HYPRE's solve
  // runs to its end); true throws gfmd::Interrupted.
  std::function<bool()> stop_request;
};

struct FlowResult {
  double angle_deg = 0.0;  // direction of the imposed gradient, degrees from +x
  // K_eff = <q . d> / G: mean current density per unit imposed gradient (length^3).
  double conductivity = 0.0;
  double conductivity_transverse = 0.0;  // <q . d_perp> / G, d_perp = (-sin a, cos a)
  double flow_factor = 0.0;              // K_eff / <g>^3; 0 if <g> == 0
  double mean_gap = 0.0;                 // <max(g, 0)>
  double mean_gap_cubed = 0.0;           // <max(g, 0)^3>
  // Open cells (g > 0) form a cluster that wraps around the periodic cell along x if
  // |cos a| >= |sin a|, else along y.
  bool percolates = false;
  // Faces between two open cells treated as closed in the solve (FlowOptions::
  // closed_face_conductance, or (g / g_max)^3 underflowing): of order 1e-4 of the faces,
  // next to contact edges on rough contact gaps.
  std::size_t faces_cut = 0;
  // Discrete flux conservation check: the total current through every column of
  // x-faces (cross-section perpendicular to x) and through every row of y-faces.
  // Reported is max(max_col |F_col - <F_col>| / ly, max_row |F_row - <F_row>| / lx) / S,
  // S = max(|<F_col>| / ly, |<F_row>| / lx) (the larger mean current density), so that a
  // component with (nearly) zero mean flow is judged relative to the main flow; in a
  // direction that does not percolate S also adds <g>^3 (the current of a uniform film of
  // the mean gap), so that round-off currents are not judged against themselves;
  // 0 if there is no flow at all.
  double conservation_error = 0.0;
  int iterations = 0;  // PCG iterations of the linear solve (0 if nothing to solve)
  // Final relative residual: recomputed from the solution of the full system (ours),
  // reported by HYPRE's PCG (BoomerAMG).
  double residual = 0.0;
  // Wall time of the set-up (reduction and multigrid hierarchy, including a failed first
  // attempt before a fallback) and of the solve of this direction (PCG, recovery of the
  // eliminated unknowns).
  double setup_s = 0.0;
  double solve_s = 0.0;
  // Linear solver that produced the result: "amg" (ours), "boomeramg" (HYPRE, asked for)
  // or "boomeramg (fallback)" (after ours did not converge); "none" if nothing was solved.
  std::string solver = "none";
  // Current density at the cell centres (average of the two x faces / two y faces of
  // the cell) for a unit gradient G = 1, per unit width; row-major, x fastest.
  RealField qx, qy;
};

// Solves the flow problem for the gap field gap[grid.size()] (row-major, x fastest) and
// a unit imposed gradient along angle_deg (degrees from +x). On a slab grid (a distributed
// run, core/mpi.hpp) every process calls it with its rows of the gap (grid.local_size()
// values): the system is assembled on the slabs and solved by HYPRE's BoomerAMG over all
// processes whatever opt.solver says (src/flow/flow_slabs.cpp); the currents are the slab's,
// every figure is the whole cell's.
// Throws InputError("flow", ...) for an empty grid, a null gap, non-positive cell sizes,
// non-finite gaps, a non-finite angle, tolerance outside (0, 1), max_iterations < 1 or
// amg_iterations_before_fallback < 1; SolveError if neither solver reaches opt.tolerance
// within opt.max_iterations (or HYPRE fails). Safe to call from several threads (the
// HYPRE part is serialised).
FlowResult solve_flow(const Grid& grid, const double* gap, double angle_deg, const FlowOptions& opt = {});

// The same for several directions at once: the operator and its preconditioner are set
// up once (FlowResult::setup_s is nonzero for the first direction only) and each
// direction is one more PCG solve. Throws as above, and for an empty angle list.
std::vector<FlowResult> solve_flow(const Grid& grid, const double* gap, const std::vector<double>& angles_deg,
                                   const FlowOptions& opt = {});

// Bruggeman effective-medium combination of conductivities in 2D (equal area fractions):
// the K >= 0 solving sum_i (K_i - K) / (K_i + K) = 0. K = 0 when at least half of the
// K_i are zero (the 2D EMA percolation threshold). Two values give sqrt(K_1 K_2).
// Throws InputError("bruggeman_2d", ...) for an empty list or negative / non-finite values.
double bruggeman_2d(const std::vector<double>& k);

// True if the open cells (gap > 0) contain a 4-connected cluster that wraps around the
// periodic cell along axis 0 (x) or 1 (y). Throws InputError("percolates", ...) for a bad
// axis or grid.
bool percolates(const Grid& grid, const double* gap, int axis);

}  // namespace gfmd
