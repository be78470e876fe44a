// Micro-benchmarks of the per-iteration kernels (Google Benchmark).
//   ./build/bench_kernels --benchmark_filter=FFT
// "FFTIteration" is the bare-FFT cost the issue compares against: 3 forward + 3 inverse
// real 2D transforms of an N x N grid (the library's: line by line with the estimating
// planner, FFTW's 2D plans with the measuring one); "FFTW2DEstimate" the same through FFTW's
// own 2D estimate plans. "Amg*": the algebraic multigrid of the flow solver
// on an N x N diffusion problem (one PCG iteration = one V-cycle + one product).
#include <benchmark/benchmark.h>
#include <fftw3.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <vector>

#include "gfmd/core/fft.hpp"
#include "gfmd/elastic/elastic.hpp"
#include "gfmd/flow/amg.hpp"

namespace {

// One bare-FFT iteration: 3 forward + 3 inverse real 2D transforms. Arguments: N,
// threads, planner (0 = FFTW_ESTIMATE, the default; 1 = FFTW_MEASURE).
void BM_FFTIteration(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  gfmd::set_threads(static_cast<int>(state.range(1)));
  const gfmd::Grid g{n, n, 1.0, 1.0};
  gfmd::FFT fft(g, state.range(2) == 1 ? gfmd::Planner::Measure : gfmd::Planner::Estimate);
  gfmd::RealField r = fft.real_field(1.0), out = fft.real_field(0.0);
  for (std::size_t i = 0; i < r.size(); ++i) r[i] = static_cast<double>(i % 17);
  gfmd::SpecField s = fft.spec_field();
  // Plain FFTW executes, out of place, as in the solver: no scaling, no copy (the inverse
  // destroys the spectrum, which the next forward transform rewrites).
  for (auto _ : state) {
    for (int k = 0; k < 3; ++k) {
      fft.forward(r.data(), s.data());
      fft.backward_unscaled_destroying(s.data(), out.data());
    }
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["points"] = static_cast<double>(g.size());
}
BENCHMARK(BM_FFTIteration)
    ->ArgsProduct({{256, 512, 1024, 2048}, {1, 2}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The same 3 + 3 transforms through FFTW's own 2D plans (FFTW_ESTIMATE, as the library used
// before it computed its transforms line by line, src/core/fft_lines.hpp): the reference
// for the line transforms' speed. Arguments: N, threads.
void BM_FFTW2DEstimate(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  gfmd::set_threads(threads);
  const gfmd::Grid g{n, n, 1.0, 1.0};
  gfmd::RealField r(g.size()), out(g.size());
  for (std::size_t i = 0; i < r.size(); ++i) r[i] = static_cast<double>(i % 17);
  gfmd::SpecField s(g.spectral_size());
  auto* c = reinterpret_cast<fftw_complex*>(s.data());
  fftw_plan_with_nthreads(threads);
  fftw_plan fwd = fftw_plan_dft_r2c_2d(n, n, r.data(), c, FFTW_ESTIMATE);
  fftw_plan bwd = fftw_plan_dft_c2r_2d(n, n, c, out.data(), FFTW_ESTIMATE);
  for (auto _ : state) {
    for (int k = 0; k < 3; ++k) {
      fftw_execute(fwd);
      fftw_execute(bwd);
    }
    benchmark::DoNotOptimize(out.data());
  }
  fftw_destroy_plan(fwd);
  fftw_destroy_plan(bwd);
}
BENCHMARK(BM_FFTW2DEstimate)
    ->ArgsProduct({{256, 512, 1024, 2048}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_FFTPair(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  gfmd::set_threads(0);
  const gfmd::Grid g{n, n, 1.0, 1.0};
  gfmd::FFT fft(g);
  gfmd::RealField r = fft.real_field(1.0);
  gfmd::SpecField s = fft.spec_field();
  for (auto _ : state) {
    fft.forward(r.data(), s.data());
    fft.backward(s.data(), r.data());
    benchmark::DoNotOptimize(r.data());
  }
}
BENCHMARK(BM_FFTPair)->Arg(256)->Arg(512)->Arg(1024)->Arg(2048)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_Compliance(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  gfmd::set_threads(0);
  const gfmd::Grid g{n, n, 1.0, 1.0};
  gfmd::ElasticBody body(g, gfmd::homogeneous_body(1.0, 0.25, 0.1, true));
  gfmd::SpecField a(g.spectral_size(), 1.0), b(g.spectral_size()), c(g.spectral_size()), d(g.spectral_size());
  for (auto _ : state) {
    body.displacement(a.data(), a.data(), a.data(), b.data(), c.data(), d.data());
    benchmark::DoNotOptimize(d.data());
  }
}
BENCHMARK(BM_Compliance)->Arg(512)->Arg(2048)->Unit(benchmark::kMillisecond)->UseRealTime();

// N x N cells, face conductances varying smoothly over four decades, a fixed value along
// the left edge: the kind of operator the flow solver hands to the AMG.
gfmd::CsrMatrix diffusion(int n) {
  auto k = [&](double x, double y) {
    const double t = 2.0 * std::numbers::pi;
    return std::pow(10.0, -2.0 + std::sin(3 * t * x) * std::cos(2 * t * y) + std::sin(5 * t * (x + y)));
  };
  gfmd::CsrMatrix a;
  a.n = static_cast<std::size_t>(n) * n;
  a.ptr.push_back(0);
  for (int iy = 0; iy < n; ++iy)
    for (int ix = 0; ix < n; ++ix) {
      const double x = (ix + 0.5) / n, y = (iy + 0.5) / n, h = 0.5 / n;
      const int i = iy * n + ix;
      const double kw = ix > 0 ? k(x - h, y) : 0.0, ke = ix + 1 < n ? k(x + h, y) : 0.0;
      const double ks = iy > 0 ? k(x, y - h) : 0.0, kn = iy + 1 < n ? k(x, y + h) : 0.0;
      a.col.push_back(i);
      a.val.push_back(kw + ke + ks + kn + (ix == 0 ? 1.0 : 0.0));
      const int nb[4] = {i - 1, i + 1, i - n, i + n};
      const double kk[4] = {kw, ke, ks, kn};
      for (int q = 0; q < 4; ++q)
        if (kk[q] > 0.0) {
          a.col.push_back(nb[q]);
          a.val.push_back(-kk[q]);
        }
      a.ptr.push_back(a.col.size());
    }
  return a;
}

void BM_AmgSetup(benchmark::State& state) {
  gfmd::set_threads(0);
  const gfmd::CsrMatrix a = diffusion(static_cast<int>(state.range(0)));
  double levels = 0.0, complexity = 0.0;
  for (auto _ : state) {
    gfmd::AlgebraicMultigrid mg(a);
    levels = mg.levels();
    complexity = mg.operator_complexity();
    benchmark::DoNotOptimize(&mg);
  }
  state.counters["levels"] = levels;
  state.counters["complexity"] = complexity;
}
BENCHMARK(BM_AmgSetup)->Arg(1024)->Arg(2048)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_AmgVCycle(benchmark::State& state) {
  gfmd::set_threads(0);
  const gfmd::AlgebraicMultigrid mg(diffusion(static_cast<int>(state.range(0))));
  std::vector<double> r(mg.size(), 1.0), z(mg.size());
  mg.precondition(r.data(), z.data());  // the first cycle touches the work arrays first
  for (auto _ : state) {
    mg.precondition(r.data(), z.data());
    benchmark::DoNotOptimize(z.data());
  }
}
BENCHMARK(BM_AmgVCycle)->Arg(1024)->Arg(2048)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_AmgMatvec(benchmark::State& state) {
  gfmd::set_threads(0);
  const gfmd::CsrMatrix a = diffusion(static_cast<int>(state.range(0)));
  std::vector<double> x(a.n, 1.0), y(a.n, 0.0);
  for (auto _ : state) {
    a.multiply(x.data(), y.data());
    benchmark::DoNotOptimize(y.data());
  }
}
BENCHMARK(BM_AmgMatvec)->Arg(1024)->Arg(2048)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
