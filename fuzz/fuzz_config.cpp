// libFuzzer target: the case-file parser must either accept a configuration or reject it
// with gfmd::InputError; any other exception, crash or sanitizer report is a bug.
#include <cstddef>
#include <cstdint>
#include <string>

#include "gfmd/case/config.hpp"
#include "gfmd/core/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const gfmd::Config c = gfmd::parse_config(text, "fuzz.toml");
    (void)c.to_toml();
  } catch (const gfmd::InputError&) {
  }
  return 0;
}
