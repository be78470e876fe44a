// Micro-benchmarks of the per-iteration kernels (Google Benchmark).
//   ./build/bench_kernels --benchmark_filter=FFT
// "FFTIteration" is the bare-FFT cost the issue compares against: 3 forward + 3 inverse
// real 2D transforms of an N x N grid.
#include <benchmark/benchmark.h>

#include "gfmd/elastic.hpp"
#include "gfmd/fft.hpp"

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
  gfmd::ElasticBody body(g, gfmd::ElasticParams{1.0, 0.25, 0.1, true});
  gfmd::SpecField a(g.spectral_size(), 1.0), b(g.spectral_size()), c(g.spectral_size()), d(g.spectral_size());
  for (auto _ : state) {
    body.displacement(a.data(), a.data(), a.data(), b.data(), c.data(), d.data());
    benchmark::DoNotOptimize(d.data());
  }
}
BENCHMARK(BM_Compliance)->Arg(512)->Arg(2048)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
