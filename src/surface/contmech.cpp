// The paper authors' self-affine surface, seed for seed. See include/gfmd/surface/contmech.hpp.
#include "gfmd/surface/contmech.hpp"

#include <cmath>
#include <complex>
#include <cstdint>
#include <numbers>
#include <string>
#include <vector>

#include "gfmd/core/backend.hpp"
#include "gfmd/core/error.hpp"

namespace gfmd {

namespace {
constexpr int kDegree = 31;  // glibc TYPE_3: 31 words of state, the second tap 3 words ahead
constexpr int kSeparation = 3;
}  // namespace

GlibcRand::GlibcRand(std::uint32_t seed) {
  if (seed == 0) seed = 1;
  r_[0] = seed;
  std::int64_t word = seed;
  for (int i = 1; i < kDegree; ++i) {
    // 16807 word mod (2^31 - 1) without overflowing 31 bits (Schrage), as glibc computes it.
    const std::int64_t hi = word / 127773, lo = word % 127773;
    word = 16807 * lo - 2836 * hi;
    if (word < 0) word += 2147483647;
    r_[i] = static_cast<std::uint32_t>(word);
  }
  front_ = kSeparation;
  rear_ = 0;
  for (int i = 0; i < 10 * kDegree; ++i) next();
}

std::int32_t GlibcRand::next() {
  r_[front_] += r_[rear_];  // modulo 2^32
  const std::uint32_t v = r_[front_];
  front_ = front_ + 1 == kDegree ? 0 : front_ + 1;
  rear_ = rear_ + 1 == kDegree ? 0 : rear_ + 1;
  return static_cast<std::int32_t>(v >> 1);
}

Topography make_selfaffine_contmech(const Grid& g, const SelfAffineParams& p) {
  check_selfaffine(g, p);
  // Their constants and expressions, in their order, so that the band edges round alike.
  const double pi = 4. * std::atan(1.), two_pi = 2 * pi;
  const double dqx = two_pi / g.lx, dqy = two_pi / g.ly;
  const double dqx2 = dqx * dqx, dqy2 = dqy * dqy;
  const double q_roll = two_pi / p.lambda_long, q_max = two_pi / p.lambda_short;
  const double expo = 1 + p.hurst;
  auto sqrt_spec = [&](double q) {
    const double q_red = q / q_roll;
    if (q_red < 1. - 1e-9) return 0.;  // their cut-off below lambda_long (no roll-off)
    return std::pow(1. / q_red, expo);
  };
  const long long NX = static_cast<long long>(0.1 + 2 * g.lx / p.lambda_short);
  const long long NY = static_cast<long long>(0.1 + 2 * g.ly / p.lambda_short);
  const long long NYHP1 = NY / 2 + 1, n_four = NX * NYHP1;
  const long long nx = g.nx, ny = g.ny, nxh = nx / 2, ny_half = ny / 2 + 1;

  // Their spectrum: x full (nx), y half (ny/2 + 1), as their c2r transform takes it.
  const std::size_t n_theirs = static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny_half);
  std::vector<cplx> F(n_theirs, cplx(0.0, 0.0));
  auto at = [&](long long ix, long long iy) -> cplx& {
    return F[static_cast<std::size_t>(ix * ny_half + iy)];
  };
  GlibcRand rng(static_cast<std::uint32_t>(p.seed));
  auto rrand = [&] { return rng.next() * 1. / GlibcRand::kRandMax; };
  for (int i = 0; i < 100; ++i) rrand();
  double var_height = 0, grad2 = 0;
  for (long long K = 1; K < n_four; ++K) {
    long long IQX = K / NYHP1;
    const long long IQY = K % NYHP1;
    const long long JQX = std::llabs(NX - IQX);
    IQX = IQX < JQX ? IQX : JQX;
    const double q = std::sqrt(1. * std::pow(IQX, 2) * dqx2 + std::pow(IQY, 2) * dqy2 / 1.);
    if (q > q_max) continue;
    double phase = rrand() * two_pi;
    const double abs_height = sqrt_spec(q);
    const double weight = (IQY == 0 || IQY == NY / 2) ? 1 : 2;
    const double spec = abs_height * abs_height * weight;
    var_height += spec;
    grad2 += (IQX * dqx2 * IQX + IQY * dqx2 * IQY) * spec;  // their y term uses the x spacing
    if (IQX > nx / 2 || IQY > ny / 2) continue;             // cannot happen with check_selfaffine's grids
    const long long iqx = IQX != JQX ? IQX : nx - IQX;
    const long long iqy = IQY;
    cplx& f = at(iqx % nx, iqy);
    f = abs_height * std::exp(cplx(0, 1) * phase);
    if (iqy == 0 || iqy == ny / 2) {
      if (iqx % nx == 0 || iqx == nxh) {
        phase = phase > pi ? -1 : 1;
        f = abs_height * phase;
      } else if (iqx > nxh) {
        f = std::conj(at(nx - iqx, iqy));
      }
    }
  }
  const double target = p.rms_height > 0 ? p.rms_height : p.rms_gradient;
  const double norm = p.rms_height > 0 ? var_height : grad2;
  if (!(norm > 0))
    throw InputError("indenter.lambda_short", "no Fourier mode lies between lambda_short and lambda_long");
  const double scale = std::sqrt(target * target / norm);

  // Our half spectrum (x half, y full) of minus their surface; FFT::backward divides by
  // nx ny, which their synthesis does not. Mode (kx >= 0, ky) is theirs at (kx, ky) for
  // ky <= ny/2, else the conjugate of theirs at (-kx, -ky).
  const double n_cells = static_cast<double>(nx) * static_cast<double>(ny);
  FFT fft(g);
  SpecField spec = fft.spec_field();
  const int gnxh = g.nxh();
  for_rows(g.rows(), [&](int row) {
    const long long iky = g.y0 + row;
    for (int ikx = 0; ikx < gnxh; ++ikx) {
      const cplx v = iky < ny_half ? at(ikx, iky) : std::conj(at((nx - ikx) % nx, ny - iky));
      spec[static_cast<std::size_t>(row) * gnxh + ikx] = -scale * n_cells * v;
    }
  });
  Topography t{g, RealField(g.local_size()), "selfaffine"};
  fft.backward(spec.data(), t.h.data());
  return t;
}

}  // namespace gfmd
