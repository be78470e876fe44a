// Indenter types as registered parts (src/case/indenter_types.cpp): the registry drives the
// config's messages and the serialisation; the flat punch is validated against Boussinesq.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>

#include "gfmd/case/config.hpp"
#include "gfmd/case/run.hpp"
#include "test_util.hpp"

using namespace gfmd;
using gfmd::testing::solve;

namespace {

// A flat punch of radius a = 0.5 pressed with F = 0.01 E* a^2/0.25 on a half-space, hard wall.
const char* kPunch = R"(
[grid]
nx = 128
lx = 8.0
[elastic]
poisson = 0.25
[indenter]
type = "flatpunch"
radius = 0.5
[load]
force = 0.01
[interaction]
model = "hardwall"
[solver]
tolerance = 1e-10
)";

// The punch's stiffness error against Boussinesq's F / (2 a E*), a the radius of a disc with
// the contact's area (the staircase edge of the grid): the approach of a periodic cell is
// d(L) = F/k - c F/(E* L) (the images' uniform displacement), so two cells of side L and 2L
// at the same spacing give the isolated punch's d = 2 d(2L) - d(L).
double stiffness_error(int nx, double lx) {
  const double F = 0.01;
  const CaseResult small = solve(kPunch, {"grid.nx=" + std::to_string(nx), "grid.lx=" + std::to_string(lx)});
  const CaseResult big =
      solve(kPunch, {"grid.nx=" + std::to_string(2 * nx), "grid.lx=" + std::to_string(2 * lx)});
  const double area = small.observables.relative_contact_area * small.config.grid.area();
  EXPECT_NEAR(area, big.observables.relative_contact_area * big.config.grid.area(), 1e-12 * area)
      << "the punch's face is the contact, whatever the cell";
  const double a = std::sqrt(area / std::numbers::pi);
  const double d = 2 * big.info.approach - small.info.approach;
  return d / (F / (2 * a)) - 1;
}

}  // namespace

TEST(Indenters, FlatPunchStiffnessIsBoussinesqAndConverges) {
  // Boussinesq (Johnson, Contact Mechanics, eq. 3.36): F = 2 a E* d for a flat circular punch.
  const double coarse = stiffness_error(128, 8.0);  // a = 8 dx
  const double fine = stiffness_error(256, 8.0);    // a = 16 dx
  EXPECT_LT(std::abs(coarse), 0.02);
  EXPECT_LT(std::abs(fine), 0.01);
  EXPECT_LT(std::abs(fine), 0.7 * std::abs(coarse)) << "the error falls under refinement";
}

TEST(Indenters, FlatPunchPressureIsBoussinesqsInverseSquareRoot) {
  // p(r) = F / (2 pi a sqrt(a^2 - r^2)) inside the face (Johnson eq. 3.35): compared on rings
  // of the inner 60 % of the radius, away from the singular edge the grid cannot resolve.
  const CaseResult r = solve(kPunch, {"grid.nx=256"});
  const Grid& g = r.config.grid;
  const double F = 0.01;
  const double a = std::sqrt(r.observables.relative_contact_area * g.area() / std::numbers::pi);
  const int rings = 6;
  std::vector<double> sum(rings, 0.0), count(rings, 0.0), ref(rings, 0.0);
  for (int iy = 0; iy < g.ny; ++iy)
    for (int ix = 0; ix < g.nx; ++ix) {
      const double x = (ix - g.nx / 2) * g.dx(), y = (iy - g.ny / 2) * g.dy();
      const double rho = std::hypot(x, y) / a;
      if (rho >= 0.6) continue;
      const int k = static_cast<int>(rho / 0.6 * rings);
      sum[k] += r.fields.pressure[iy * g.nx + ix];
      ref[k] += F / (2 * std::numbers::pi * a * a * std::sqrt(1 - rho * rho));
      count[k] += 1;
    }
  for (int k = 0; k < rings; ++k) {
    ASSERT_GT(count[k], 0);
    EXPECT_NEAR(sum[k] / ref[k], 1.0, 0.03) << "ring " << k << " of " << rings;
  }
}

TEST(Indenters, FlatPunchMeetsTheBodyOnItsFaceOnly) {
  const CaseResult r = solve(kPunch, {"grid.nx=256"});
  const Grid& g = r.config.grid;
  for (int iy = 0; iy < g.ny; ++iy)
    for (int ix = 0; ix < g.nx; ++ix) {
      const double x = (ix - g.nx / 2) * g.dx(), y = (iy - g.ny / 2) * g.dy();
      const bool face = x * x + y * y <= 0.25;
      const double p = r.fields.pressure[iy * g.nx + ix];
      if (face) {
        ASSERT_GT(p, 0.0) << "at " << x << ", " << y;
      } else {
        ASSERT_EQ(p, 0.0) << "at " << x << ", " << y;
      }
    }
  EXPECT_EQ(r.config.to_json()["indenter"]["depth"], 0.5) << "depth defaults to the radius";
}

TEST(Indenters, RegistryNamesTheTypesInMessages) {
  std::vector<std::string> names;
  for (const IndenterTypeInfo& t : indenter_types()) {
    names.push_back(t.name);
    EXPECT_FALSE(t.purpose.empty()) << t.name;
  }
  EXPECT_NE(std::find(names.begin(), names.end(), "flatpunch"), names.end());
  EXPECT_EQ(std::find(names.begin(), names.end(), "array"), names.end()) << "not a case file's type";
  try {
    (void)parse_config(kPunch, "t.toml", {"indenter.type=\"flatpnch\""});
    FAIL() << "an unknown type was accepted";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("did you mean 'flatpunch'"), std::string::npos) << m;
    std::string list;
    for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
    EXPECT_NE(m.find("one of " + list), std::string::npos) << m;
    EXPECT_EQ(m.find("indenter.radius"), std::string::npos)
        << "the meant type's keys are no second error: " << m;
  }
}

TEST(Indenters, FlatPunchKeysAreChecked) {
  const auto problem = [](const std::vector<std::string>& sets) {
    try {
      (void)parse_config(kPunch, "t.toml", sets);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(problem({"indenter.radius=0.05"})
                .find("indenter.radius: the punch radius 0.05 spans fewer than 2 grid"),
            std::string::npos);
  EXPECT_NE(problem({"indenter.radius=3"}).find("wider than half the cell"), std::string::npos);
  EXPECT_NE(problem({"indenter.depth=-1"}).find("indenter.depth: must be positive"), std::string::npos);
  EXPECT_NE(problem({"indenter.wavelength=1"}).find("indenter.wavelength: unknown key"), std::string::npos);
}

// Keys that exclude each other: a file's radius beside a different radius_x was read as an
// ellipse without a word; --set of one of them replaces the other (as load.* do), and --set
// indenter.type drops the file's type's keys that the new type lacks.
TEST(Indenters, ExclusiveKeysConflictInAFileAndReplaceEachOtherFromSet) {
  const std::string hertz =
      "[grid]\nnx = 64\nlx = 4.0\n[indenter]\ntype = \"hertz\"\nradius = 1.0\n[load]\nforce = 0.01\n";
  const auto problem = [](const std::string& text, const std::vector<std::string>& sets) {
    try {
      (void)parse_config(text, "t.toml", sets);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  std::string both = hertz;
  both.insert(both.find("[load]"), "radius_x = 2.0\n");
  EXPECT_NE(problem(both, {}).find("indenter.radius_x: conflicts with indenter.radius = 1"),
            std::string::npos)
      << problem(both, {});
  std::string same = hertz;  // summary.json's input writes all three when they are equal
  same.insert(same.find("[load]"), "radius_x = 1.0\nradius_y = 1.0\n");
  EXPECT_EQ(problem(same, {}), "");
  const Config ellipse = parse_config(hertz, "t.toml", {"indenter.radius_x=2", "indenter.radius_y=0.5"});
  EXPECT_EQ(ellipse.indenter.radius_x, 2.0);
  EXPECT_EQ(ellipse.indenter.radius_y, 0.5);
  const Config round = parse_config(both, "t.toml", {"indenter.radius=3"});
  EXPECT_EQ(round.indenter.radius_x, 3.0);
  EXPECT_EQ(round.indenter.radius_y, 3.0);
  // rms_height <-> rms_gradient; hertz -> step (radius is not a step's key; depth stays a step's).
  const std::string rough =
      "[grid]\nnx = 64\nlx = 1.0\n[indenter]\ntype = \"selfaffine\"\nlambda_short = 0.05\nrms_height = 0.01\n"
      "[load]\npressure = 0.01\n";
  const Config g = parse_config(rough, "t.toml", {"indenter.rms_gradient=0.1"});
  EXPECT_EQ(g.indenter.selfaffine.rms_gradient, 0.1);
  EXPECT_EQ(g.indenter.selfaffine.rms_height, 0.0);
  // One axis over a round indenter: the other keeps its radius (it fell to 0 and blamed radius_x).
  const Config half = parse_config(hertz, "t.toml", {"indenter.radius_x=2"});
  EXPECT_EQ(half.indenter.radius_x, 2.0);
  EXPECT_EQ(half.indenter.radius_y, 1.0);
  // A file that leaves its type to the default (hertz) switches too.
  std::string implicit = hertz;
  implicit.erase(implicit.find("type = \"hertz\"\n"), std::string("type = \"hertz\"\n").size());
  EXPECT_EQ(parse_config(implicit, "t.toml", {"indenter.type=\"step\"", "indenter.width=1.0"}).indenter.type,
            "step");
  const Config step = parse_config(hertz, "t.toml", {"indenter.type=\"step\"", "indenter.width=1.0"});
  EXPECT_EQ(step.indenter.type, "step");
  EXPECT_NE(problem(hertz, {"indenter.type=\"step\""}).find("indenter.width"), std::string::npos)
      << "the new type's own keys are still required";
}

TEST(Indenters, MakeIndenterReadsKeysAsTheCaseFileDoes) {
  const Grid g{128, 128, 8.0, 8.0};
  const Topography t = make_indenter("flatpunch", g, {{"radius", 0.5}, {"depth", 0.25}});
  EXPECT_EQ(t.kind, "flatpunch");
  EXPECT_EQ(t.h[64 * 128 + 64], 0.0);
  EXPECT_EQ(t.h[0], -0.25);
  const Topography h = make_indenter("hertz", g, {{"radius", 2.0}});
  const Topography ref = make_hertz(g, 2.0, 2.0);
  for (std::size_t i = 0; i < ref.h.size(); ++i) ASSERT_EQ(h.h[i], ref.h[i]);
  try {
    (void)make_indenter("flatpunch", g, {{"radius", 0.5}, {"dept", 1.0}});
    FAIL() << "a misspelt key was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), "indenter.dept");
    EXPECT_NE(std::string(e.what()).find("did you mean 'depth'"), std::string::npos) << e.what();
  }
  EXPECT_THROW((void)make_indenter("array", g, nlohmann::json::object()), InputError);
  // An elastic indenter's keys make no heights: refused, not dropped (the indenter stayed rigid).
  try {
    (void)make_indenter("hertz", g, {{"radius", 1.0}, {"contact_modulus", 1.0}});
    FAIL() << "an elastic indenter's key was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), "indenter.contact_modulus");
    EXPECT_NE(std::string(e.what()).find("indenter_body="), std::string::npos) << e.what();
  }
}

TEST(Indenters, FlatPunchExampleRunsFromTheCommandLine) {
  // examples/flatpunch.toml as a user runs it: the summary records the type and its keys, and
  // the approach is Boussinesq's F / (2 a E*) = 0.01 less the periodic images' share (about
  // 14 % in this cell, L = 16 a; extrapolated away in the test above).
  const auto dir = gfmd::testing::scratch_dir("indenters", "example");
  const auto out =
      gfmd::testing::run_gfmd("run " + std::string(GFMD_SOURCE_DIR) + "/examples/flatpunch.toml -o " +
                              (dir / "run").string() + " --set output.png=false -q");
  ASSERT_EQ(out.code, 0) << out.output;
  std::ifstream f(dir / "run" / "summary.json");
  const nlohmann::json s = nlohmann::json::parse(f);
  EXPECT_EQ(s["input"]["indenter"]["type"], "flatpunch");
  EXPECT_EQ(s["input"]["indenter"]["depth"], 0.5);
  const double d = s["approach"].get<double>();
  EXPECT_GT(d, 0.8 * 0.01);
  EXPECT_LT(d, 0.01);
}
