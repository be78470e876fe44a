// Steady thin-film Reynolds flow (SPEC §6); see include/gfmd/flow/flow.hpp for the
// discretisation. Linear solves by our algebraic multigrid (gfmd/amg.hpp) under CG, or HYPRE.
#include "gfmd/flow/flow.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <memory>
#include <mutex>
#include <numbers>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "connectivity.hpp"
#include "gfmd/core/backend.hpp"
#include "gfmd/core/buffer.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/reduce.hpp"
#include "gfmd/flow/amg.hpp"
#include "reynolds_system.hpp"
namespace gfmd {

using namespace flow_detail;

namespace {

std::vector<FlowResult> solve_flow_impl(const Grid& grid, const double* gap,
                                        const std::vector<double>& angles, const FlowOptions& opt) {
  const FlowSolver which = opt.solver;
  check_grid(grid, "flow");
  // (A process of a distributed run that holds no rows has no gap to point to.)
  if (gap == nullptr && grid.local_size() > 0) throw InputError("flow", "gap field is null");
  if (angles.empty()) throw InputError("flow", "no flow direction given");
  for (double a : angles)
    if (!std::isfinite(a)) throw InputError("flow", "angle must be finite");
  if (!(opt.tolerance > 0.0) || !(opt.tolerance < 1.0))
    throw InputError("flow", "tolerance must be in (0, 1)");
  if (opt.max_iterations < 1) throw InputError("flow", "max_iterations must be >= 1");
  if (opt.amg_iterations_before_fallback < 1)
    throw InputError("flow", "amg_iterations_before_fallback must be >= 1");
  if (!(opt.closed_face_conductance >= 0.0) || !(opt.closed_face_conductance < 1.0))
    throw InputError("flow", "closed_face_conductance must be in [0, 1)");
  if (grid.is_slab()) return solve_flow_slabs(grid, gap, angles, opt);
  const int nx = grid.nx, ny = grid.ny;
  const std::size_t n = grid.size();

  // Every block of the solve comes from the heap, grown once for all of them and advised
  // for transparent huge pages, and is given back when the solve ends: the many grid-sized
  // temporaries (operator, reduction, multigrid set-up, HYPRE's) would otherwise each be
  // mapped and faulted in afresh, 4 KiB at a time (2048^2: seconds in the kernel).
  const HeapAllocationScope heap_only(512 * n);
  double gmax = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(gap[i])) throw InputError("flow", "non-finite gap at index " + std::to_string(i));
    gmax = std::max(gmax, gap[i]);
  }

  const double dx = grid.dx(), dy = grid.dy();
  const double wx = dy / dx, wy = dx / dy;

  std::vector<FlowResult> results = results_with_gap_means(grid, gap, angles);
  if (!(gmax > 0.0)) {  // everything closed: no flow
    for (FlowResult& res : results) {
      res.qx.assign(n, 0.0);
      res.qy.assign(n, 0.0);
    }
    return results;
  }

  // Normalised face conductances (kn = (g / gmax)^3 of the cells, physical k = kscale * kn),
  // weighted by the face length over the centre distance.
  const double kscale = gmax * gmax * gmax;
  LinearSystem sys;
  sys.nx = nx;
  sys.ny = ny;
  sys.make_tables();
  sys.kx.resize(n);
  sys.ky.resize(n);
  auto kcell = [&](std::size_t i) {
    const double g = std::max(gap[i], 0.0) / gmax;
    return g * g * g;
  };
  const double kcut = opt.closed_face_conductance;
  auto harmonic = [kcut](double ki, double kj) {
    const double kf = (ki > 0.0 && kj > 0.0) ? 2.0 * ki * kj / (ki + kj) : 0.0;
    return kf >= kcut ? kf : 0.0;
  };
  // Also counted: faces between two open cells that the cut-off (or underflow of
  // (g / g_max)^3) closed.
  std::vector<std::size_t> cut_in_row(static_cast<std::size_t>(ny), 0);
  for_rows(ny, [&](int iy) {
    const int iyn = (iy + 1 == ny) ? 0 : iy + 1;
    std::size_t cut = 0;
    for (int ix = 0; ix < nx; ++ix) {
      const int ixe = (ix + 1 == nx) ? 0 : ix + 1;
      const std::size_t i = static_cast<std::size_t>(iy) * nx + ix;
      const std::size_t ie = static_cast<std::size_t>(iy) * nx + ixe,
                        in = static_cast<std::size_t>(iyn) * nx + ix;
      const double ki = kcell(i);
      sys.kx[i] = wx * harmonic(ki, kcell(ie));
      sys.ky[i] = wy * harmonic(ki, kcell(in));
      cut += static_cast<std::size_t>(gap[i] > 0.0 && gap[ie] > 0.0 && sys.kx[i] == 0.0);
      cut += static_cast<std::size_t>(gap[i] > 0.0 && gap[in] > 0.0 && sys.ky[i] == 0.0);
    }
    cut_in_row[iy] = cut;
  });
  std::size_t faces_cut = 0;
  for (std::size_t c : cut_in_row) faces_cut += c;

  // Connected components over open faces; windings give the percolation flags.
  // (Geometric flags, g > 0, are recomputed below where faces were cut.)
  // A component that winds around the cell in no direction (a trapped pocket, an isolated
  // cell) carries no flow: its total pressure is constant. Such "still" cells are not
  // unknowns (their currents are zero); neither is one gauge cell (the root, P~ = 0) of
  // every winding component.
  sys.pinned.resize(n);
  std::vector<unsigned char>& pinned = sys.pinned;
  Buffer<unsigned char> still(n);
  bool wraps_x = false, wraps_y = false;
  {
    WrapUnionFind uf(n);
    unite_open_faces(
        uf, grid, [&](std::size_t i) { return sys.kx[i] > 0.0; },
        [&](std::size_t i) { return sys.ky[i] > 0.0; });
    std::tie(wraps_x, wraps_y) = uf.windings();
    parallel_for(static_cast<std::ptrdiff_t>(n), [&](std::ptrdiff_t ii) {
      const auto i = static_cast<std::size_t>(ii);
      const std::int32_t r = uf.root(static_cast<std::int32_t>(i));
      still[i] = !(uf.wraps(r, 0) || uf.wraps(r, 1));
      pinned[i] = still[i] || r == static_cast<std::int32_t>(i);
    });
  }
  // Cutting faces only removes windings: the geometric flags differ only where a direction
  // lost its winding.
  if (faces_cut > 0 && !(wraps_x && wraps_y)) {
    const auto [gx, gy] = open_windings(grid, gap);
    wraps_x = gx;
    wraps_y = gy;
  }

  // Right-hand side of direction d = (cos a, sin a): the divergence of the imposed current,
  // G d_x dx through x faces and G d_y dy through y faces (times the conductance).
  const RhsFn make_rhs = [&](std::size_t k, Buffer<double>& b) {
    const double a = angles[k] * std::numbers::pi / 180.0;
    const double dxd = std::cos(a), dyd = std::sin(a);
    b.resize(n);
    for_rows(ny, [&](int iy) {
      const int iys = (iy == 0) ? ny - 1 : iy - 1;
      for (int ix = 0; ix < nx; ++ix) {
        const int ixw = (ix == 0) ? nx - 1 : ix - 1;
        const std::size_t i = static_cast<std::size_t>(iy) * nx + ix;
        if (pinned[i]) {
          b[i] = 0.0;
          continue;
        }
        const std::size_t iw = static_cast<std::size_t>(iy) * nx + ixw;
        const std::size_t is = static_cast<std::size_t>(iys) * nx + ix;
        b[i] = dxd * dx * (sys.kx[iw] - sys.kx[i]) + dyd * dy * (sys.ky[is] - sys.ky[i]);
      }
    });
  };

  // Back end: our algebraic multigrid (OpenMP, on the red-black reduced system), with
  // HYPRE's BoomerAMG (serial) as the fallback if it does not converge within its
  // iteration budget; or BoomerAMG alone when asked for. One set-up serves all directions.
  std::vector<LinearSolution> sols;
  std::string failure, solver = "amg";
  double wasted_s = 0.0;  // a failed AMG attempt, counted into the set-up time
  if (which != FlowSolver::BoomerAMG) {
    const int budget = which == FlowSolver::Amg
                           ? opt.max_iterations
                           : std::min(opt.max_iterations, opt.amg_iterations_before_fallback);
    const auto t0 = std::chrono::steady_clock::now();
    try {
      sols = solve_native(sys, angles.size(), make_rhs, opt, budget);
      for (const LinearSolution& sol : sols)
        if (!sol.converged && failure.empty()) failure = shortfall("AMG-PCG", sol);
    } catch (const Interrupted&) {
      throw;
    } catch (const SolveError& e) {
      failure = e.what();
    }
    if (!failure.empty() && which == FlowSolver::Amg)
      throw SolveError("flow: linear solve did not converge to " + sci(opt.tolerance) + ": " + failure);
    wasted_s = failure.empty() ? 0.0 : seconds_since(t0);
  }
  if (which == FlowSolver::BoomerAMG || !failure.empty()) {
    solver = failure.empty() ? "boomeramg" : "boomeramg (fallback)";
    if (opt.stop_request && opt.stop_request()) throw Interrupted("flow solve interrupted before BoomerAMG");
    sols = solve_boomeramg(sys, angles.size(), make_rhs, opt);
    for (const LinearSolution& sol : sols)
      if (!sol.converged) {
        if (!failure.empty()) failure += "; then ";
        failure += shortfall("BoomerAMG-PCG", sol);
        throw SolveError("flow: linear solve did not converge to " + sci(opt.tolerance) + ": " + failure);
      }
    sols.front().setup_s += wasted_s;
  }

  Buffer<double> qxf(n), qyf(n);
  for (std::size_t k = 0; k < angles.size(); ++k) {
    FlowResult& res = results[k];
    const double a = angles[k] * std::numbers::pi / 180.0;
    const double dxd = std::cos(a), dyd = std::sin(a);
    take_solve(res, sols[k], dxd, dyd, wraps_x, wraps_y, faces_cut, solver);
    const Buffer<double>& P = sols[k].x;

    // Face current densities (physical units, G = 1) and cell-centred averages.
    for_rows(ny, [&](int iy) {
      const int iyn = (iy + 1 == ny) ? 0 : iy + 1;
      for (int ix = 0; ix < nx; ++ix) {
        const int ixe = (ix + 1 == nx) ? 0 : ix + 1;
        const std::size_t i = static_cast<std::size_t>(iy) * nx + ix;
        const std::size_t ie = static_cast<std::size_t>(iy) * nx + ixe;
        const std::size_t in = static_cast<std::size_t>(iyn) * nx + ix;
        // kx / dy = k_f / dx, ky / dx = k_f / dy.
        qxf[i] = (sys.kx[i] > 0.0 && !still[i]) ? -kscale * sys.kx[i] * (P[ie] - P[i] - dxd * dx) / dy : 0.0;
        qyf[i] = (sys.ky[i] > 0.0 && !still[i]) ? -kscale * sys.ky[i] * (P[in] - P[i] - dyd * dy) / dx : 0.0;
      }
    });
    res.qx.resize(n);
    res.qy.resize(n);
    for_rows(ny, [&](int iy) {
      const int iys = (iy == 0) ? ny - 1 : iy - 1;
      for (int ix = 0; ix < nx; ++ix) {
        const int ixw = (ix == 0) ? nx - 1 : ix - 1;
        const std::size_t i = static_cast<std::size_t>(iy) * nx + ix;
        res.qx[i] = 0.5 * (qxf[i] + qxf[static_cast<std::size_t>(iy) * nx + ixw]);
        res.qy[i] = 0.5 * (qyf[i] + qyf[static_cast<std::size_t>(iys) * nx + ix]);
      }
    });
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
    // Without a path through the cell the current is zero up to round-off: judged against the
    // current of a uniform film of the mean gap instead of against that round-off.
    const double film = res.mean_gap * res.mean_gap * res.mean_gap;
    const double scale = std::max(std::abs(mqx), std::abs(mqy)) + (res.percolates ? 0.0 : film);
    double dev = 0.0;
    for (double c : col) dev = std::max(dev, std::abs(c - mqx));
    for (double r : row) dev = std::max(dev, std::abs(r - mqy));
    res.conservation_error = scale > 0.0 ? dev / scale : 0.0;
  }
  return results;
}

}  // namespace

FlowResult solve_flow(const Grid& grid, const double* gap, double angle_deg, const FlowOptions& opt) {
  return std::move(solve_flow_impl(grid, gap, {angle_deg}, opt).front());
}

std::vector<FlowResult> solve_flow(const Grid& grid, const double* gap, const std::vector<double>& angles_deg,
                                   const FlowOptions& opt) {
  return solve_flow_impl(grid, gap, angles_deg, opt);
}

bool parse_flow_solver(const std::string& name, FlowSolver& out) {
  if (name == "auto") {
    out = FlowSolver::Auto;
  } else if (name == "amg") {
    out = FlowSolver::Amg;
  } else if (name == "boomeramg") {
    out = FlowSolver::BoomerAMG;
  } else {
    return false;
  }
  return true;
}

std::string flow_solver_name(FlowSolver solver) {
  switch (solver) {
    case FlowSolver::Amg:
      return "amg";
    case FlowSolver::BoomerAMG:
      return "boomeramg";
    case FlowSolver::Auto:
      break;
  }
  return "auto";
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

}  // namespace gfmd
