// indenter.type = "selfaffine": a random self-affine surface (surface/topography.hpp), ours or
// the paper authors' (generator = "contmech").
#include <cstdint>
#include <limits>

#include "indenter_types.hpp"

namespace gfmd::config_detail {

namespace {

void read(Section& ind, IndenterRead& r) {
  const Grid& g = r.c.grid;
  SelfAffineParams& s = r.c.indenter.selfaffine;
  s.hurst = ind.number("hurst", 0.8);
  s.lambda_long = ind.number("lambda_long", g.lx / 2);
  s.lambda_short = ind.number("lambda_short", s.lambda_long / 128);
  s.rms_height = ind.number("rms_height", 0.0);
  s.rms_gradient = ind.number("rms_gradient", 0.0);
  s.lambda_rolloff = ind.number("lambda_rolloff", 0.0);
  s.peklenik = ind.number("peklenik", 1.0);
  s.seed = static_cast<std::uint64_t>(ind.integer("seed", 0, 0, std::numeric_limits<long long>::max()));
  s.generator = ind.string("generator", "gfmd");
  if ((s.rms_height > 0) == (s.rms_gradient > 0)) {
    ind.error("rms_height", "give exactly one of rms_height and rms_gradient (positive)");
  } else {
    // The surface's own checks (band, resolution), here so that they name the line.
    ind.check([&] { check_selfaffine(g, s); });
  }
}

void write(const IndenterConfig& in, nlohmann::json& out) {
  const SelfAffineParams& s = in.selfaffine;
  out["hurst"] = s.hurst;
  out["lambda_long"] = s.lambda_long;
  out["lambda_short"] = s.lambda_short;
  if (s.rms_height > 0) out["rms_height"] = s.rms_height;
  if (s.rms_gradient > 0) out["rms_gradient"] = s.rms_gradient;
  if (s.lambda_rolloff > 0) out["lambda_rolloff"] = s.lambda_rolloff;
  if (s.peklenik != 1.0) out["peklenik"] = s.peklenik;  // absent: isotropic (as before the key)
  out["seed"] = s.seed;
  if (s.generator != "gfmd") out["generator"] = s.generator;  // absent: ours (as before the key)
}

Topography make(const Config& c, MapReport*) { return make_selfaffine(c.grid, c.indenter.selfaffine); }

std::pair<std::string, std::string> implausible(const Config& c, const MapReport*) {
  const SelfAffineParams& s = c.indenter.selfaffine;
  return {"the self-affine surface's",
          s.rms_gradient > 0 ? "indenter.rms_gradient = " + g3(s.rms_gradient) + " (asked for)"
                             : "indenter.rms_height = " + g3(s.rms_height) + " against " + cell_text(c)};
}

}  // namespace

const IndenterType& selfaffine_indenter() {
  static const IndenterType t{
      .name = "selfaffine",
      .purpose =
          "random self-affine surface: hurst, lambda_long, lambda_short, rms_height or rms_gradient, seed",
      .keys = {"hurst", "lambda_long", "lambda_short", "rms_height", "rms_gradient", "seed", "lambda_rolloff",
               "generator", "peklenik"},
      .rough = true,
      .read = read,
      .write = write,
      .make = make,
      .implausible = implausible};
  return t;
}

}  // namespace gfmd::config_detail
