// libFuzzer target: every height-map reader (x3p, npy, gwy, sur, text, NetCDF; chosen by the
// bytes' signature, and by an extension taken from the first byte) must return a map whose
// size matches its dimensions, or throw gfmd::InputError naming the file.
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "gfmd/core/error.hpp"
#include "gfmd/io/height_map.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  static const char* kExt[] = {".x3p", ".npy", ".gwy", ".sur", ".txt", ".csv", ".nc", ".dat"};
  const std::string path =
      "/tmp/gfmd_fuzz_height_" + std::to_string(getpid()) + kExt[data[0] % (sizeof kExt / sizeof *kExt)];
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return 0;
  std::fwrite(data + 1, 1, size - 1, f);
  std::fclose(f);
  try {
    const gfmd::HeightMap m = gfmd::read_height_file(path);
    if (m.nx < 1 || m.ny < 1 || m.h.size() != static_cast<std::size_t>(m.nx) * static_cast<std::size_t>(m.ny))
      __builtin_trap();
    std::size_t missing = 0;
    for (double v : m.h) {
      if (std::isinf(v)) __builtin_trap();
      missing += std::isnan(v) ? 1 : 0;
    }
    if (missing != m.missing || (missing > 0 && m.first_missing.empty())) __builtin_trap();
    if (!(m.lx >= 0) || !(m.ly >= 0)) __builtin_trap();
  } catch (const gfmd::InputError& e) {
    if (std::string(e.what()).find(path) == std::string::npos) __builtin_trap();
  }
  std::remove(path.c_str());
  return 0;
}
