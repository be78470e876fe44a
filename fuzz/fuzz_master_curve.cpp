// libFuzzer target: a viscoelastic master curve's table (elastic.master_curve) must parse into
// ascending, positive, finite rows whose modulus is finite with a positive storage part at any
// frequency, or throw gfmd::InputError naming the file's line.
#include <cmath>
#include <complex>
#include <cstddef>
#include <cstdint>
#include <string>

#include "gfmd/core/error.hpp"
#include "gfmd/elastic/viscoelastic.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  gfmd::ViscoelasticParams v;
  v.model = gfmd::ViscoelasticParams::Model::MasterCurve;
  try {
    gfmd::parse_master_curve(text, "curve.csv", v);
  } catch (const gfmd::InputError& e) {
    if (e.where().rfind("curve.csv", 0) != 0) __builtin_trap();
    return 0;
  }
  const std::size_t n = v.curve_omega.size();
  if (n < 2 || v.curve_storage.size() != n || v.curve_loss.size() != n) __builtin_trap();
  for (std::size_t i = 0; i < n; ++i) {
    if (!(v.curve_omega[i] > 0 && v.curve_storage[i] > 0 && v.curve_loss[i] > 0)) __builtin_trap();
    if (i > 0 && !(v.curve_omega[i] > v.curve_omega[i - 1])) __builtin_trap();
  }
  v.validate(v.master_relaxed_modulus());  // must not throw on a table the parser accepted
  for (const double w :
       {0.0, 1e-300, v.curve_omega.front(), std::sqrt(v.curve_omega.front() * v.curve_omega.back()),
        v.curve_omega.back(), 1e300}) {
    const std::complex<double> e = v.modulus_ratio(w, v.master_relaxed_modulus());
    if (!std::isfinite(e.real()) || !std::isfinite(e.imag()) || !(e.real() > 0)) __builtin_trap();
  }
  return 0;
}
