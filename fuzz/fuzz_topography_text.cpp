// libFuzzer target: the text height-map reader must return a valid topography or throw
// gfmd::InputError naming the file.
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "gfmd/core/error.hpp"
#include "gfmd/surface/topography.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string path = "/tmp/gfmd_fuzz_topo_" + std::to_string(getpid()) + ".txt";
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return 0;
  std::fwrite(data, 1, size, f);
  std::fclose(f);
  try {
    const gfmd::Topography t = gfmd::read_topography(path, 0.0, 0.0);
    for (double v : t.h)
      if (!std::isfinite(v)) __builtin_trap();
    if (t.h.size() != t.grid.size() || t.grid.nx < 1 || t.grid.ny < 1) __builtin_trap();
  } catch (const gfmd::InputError&) {
  }
  return 0;
}
