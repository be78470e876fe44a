// A measured master curve (elastic.viscoelastic = "master_curve"): a tabulated standard linear
// solid is that solid, a temperature shift is a speed shift, and a bad file is named by its line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "gfmd/case/config.hpp"
#include "gfmd/case/run.hpp"
#include "gfmd/contact/observables.hpp"
#include "gfmd/contact/solver.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/elastic/stress.hpp"
#include "gfmd/elastic/viscoelastic.hpp"
#include "gfmd/surface/topography.hpp"
#include "test_util.hpp"
#include "visco_util.hpp"

using namespace gfmd;
using namespace gfmd::testing::visco;

using gfmd::testing::scratch_dir;
using gfmd::testing::write_file;

namespace {
// A master curve tabulating the standard linear solid E0 = 1, E_inf = 10, tau = 1 at `per_decade`
// rows per decade over omega in [1e-4, 1e4], with a header and a comment.
std::string sls_master_curve(int per_decade) {
  std::string t = "# a standard linear solid\nomega, storage, loss\n";
  const ViscoelasticParams v = sls(10.0, 1.0, 0.0);
  for (int k = 0; k <= 8 * per_decade; ++k) {
    const double w = std::pow(10.0, -4.0 + static_cast<double>(k) / per_decade);
    const std::complex<double> e = v.modulus_ratio(w, 1.0);
    char row[128];
    std::snprintf(row, sizeof row, "%.17g, %.17g, %.17g\n", w, e.real(), e.imag());
    t += row;
  }
  return t;
}
}  // namespace

// A measured master curve (elastic.viscoelastic = "master_curve"): tabulating a standard linear
// solid at 20 rows per decade it is that solid to the log-log interpolation's error (the wave
// in full contact at omega tau = 1 against the closed form: 1e-3; measured 3e-4 for a sphere).
TEST(Viscoelastic, AMasterCurveOfAStandardLinearSolidIsThatSolid) {
  ViscoelasticParams m;
  m.model = ViscoelasticParams::Model::MasterCurve;
  parse_master_curve(sls_master_curve(20), "sls.csv", m);
  ASSERT_EQ(m.curve_omega.size(), 161u);
  EXPECT_EQ(m.master_relaxed_modulus(), m.curve_storage.front());
  const ViscoelasticParams v = sls(10.0, 1.0, 0.0);
  for (const double w : {1e-3, 0.37, 1.0, 42.0})
    EXPECT_LT(std::abs(m.modulus_ratio(w, 1.0) - v.modulus_ratio(w, 1.0)) / std::abs(v.modulus_ratio(w, 1.0)),
              1e-3)
        << w;
  EXPECT_EQ(m.modulus_ratio(-0.37, 1.0), std::conj(m.modulus_ratio(0.37, 1.0)));
  const double lx = 1.0, amp = 0.005, k = 2 * kPi / lx, pbar = 0.2;
  const Grid g{64, 4, lx, lx / 16};
  ElasticParams ep;
  ep.poisson = 0.5;
  ep.contact_modulus = m.master_relaxed_modulus();
  m.velocity = 1.0 / k;  // omega tau = 1
  const Solved s = solve_with(g, wave(g, amp), ep, m, LoadParams{LoadMode::Pressure, pbar});
  ASSERT_TRUE(s.info.converged) << s.info.status;
  const double mu = k * amp * k * amp * 4.5 / (4 * pbar);  // E''(1/tau) = (E_inf - E0)/2
  EXPECT_NEAR(s.o.hysteresis_friction / mu, 1.0, 1e-3);
}

// A temperature is a speed: with a shift factor a_T the body at v0 is the reference body at
// v0 a_T (WLF with the "universal" constants c1 = 8.86, c2 = 101.6 K, 10 K above the reference).
TEST(Viscoelastic, ATemperatureShiftIsASpeedShift) {
  ViscoelasticParams m;
  m.model = ViscoelasticParams::Model::MasterCurve;
  parse_master_curve(sls_master_curve(10), "sls.csv", m);
  const double at = wlf_shift(30.0, 20.0, 8.86, 101.6);
  EXPECT_NEAR(std::log10(at), -8.86 * 10 / 111.6, 1e-12);
  const Grid g{64, 64, 2.0, 2.0};
  const Topography topo = make_hertz(g, 1.0, 1.0);
  ElasticParams ep;
  ep.poisson = 0.5;
  ep.contact_modulus = m.master_relaxed_modulus();
  ViscoelasticParams hot = m;
  hot.shift_factor = at;
  hot.velocity = 0.05;
  ViscoelasticParams ref = m;
  ref.velocity = 0.05 * at;
  const Solved a = solve_with(g, topo, ep, hot, LoadParams{LoadMode::Force, 0.01});
  const Solved b = solve_with(g, topo, ep, ref, LoadParams{LoadMode::Force, 0.01});
  ASSERT_TRUE(a.info.converged && b.info.converged);
  EXPECT_GT(a.o.hysteresis_friction, 0.0);
  EXPECT_NEAR(a.o.hysteresis_friction / b.o.hysteresis_friction, 1.0, 1e-9);
  EXPECT_NEAR(arrhenius_shift(300.0, 300.0, 5000.0), 1.0, 1e-15);
  EXPECT_NEAR(std::log(arrhenius_shift(310.0, 300.0, 5000.0)), 5000.0 * (1 / 310.0 - 1 / 300.0), 1e-12);
}

// A master curve's bad lines are named by file and line; its keys by key.
TEST(Viscoelastic, BadMasterCurvesNameTheFileLine) {
  const auto dir = scratch_dir("viscoelastic", "master");
  write_file(dir / "good.csv", sls_master_curve(2));
  write_file(dir / "decreasing.csv", "omega,E1,E2\n1,1,0.1\n10,2,0.5\n5,3,0.2\n");
  write_file(dir / "two.csv", "1 1\n10 2\n");
  write_file(dir / "negative.csv", "1,1,0.1\n10,-2,0.5\n");
  // kSlsSphere with the table good.csv in place of the solid's keys.
  const std::string base =
      gfmd::testing::without_keys(kSlsSphere, {"viscoelastic", "high_frequency_modulus", "relaxation_time"});
  const auto problem = [&](const std::vector<std::string>& sets) {
    std::vector<std::string> all = {"elastic.viscoelastic=\"master_curve\"",
                                    "elastic.master_curve=\"good.csv\""};
    all.insert(all.end(), sets.begin(), sets.end());
    return gfmd::testing::config_problem(base, all, dir.string());
  };
  EXPECT_EQ(problem({}), "");
  {
    ViscoelasticParams m;
    parse_master_curve(sls_master_curve(2), "good.csv", m);
    char own[64];
    std::snprintf(own, sizeof own, "elastic.contact_modulus=%.17g", m.master_relaxed_modulus());
    EXPECT_EQ(problem({own}), "");  // its own value is accepted (a case's record of itself reads back)
  }
  const std::string dec = problem({"elastic.master_curve=\"decreasing.csv\""});
  EXPECT_NE(dec.find("decreasing.csv:4"), std::string::npos) << dec;
  EXPECT_NE(dec.find("omega must increase"), std::string::npos) << dec;
  EXPECT_NE(problem({"elastic.master_curve=\"two.csv\""}).find("two.csv:1: expected three columns"),
            std::string::npos);
  EXPECT_NE(problem({"elastic.master_curve=\"negative.csv\""}).find("negative.csv:2"), std::string::npos);
  EXPECT_NE(problem({"elastic.master_curve=\"missing.csv\""}).find("elastic.master_curve"),
            std::string::npos);
  EXPECT_NE(
      problem({"elastic.contact_modulus=2"}).find("elastic.contact_modulus: is set by the master curve"),
      std::string::npos);
  EXPECT_NE(problem({"elastic.temperature=30"}).find("elastic.temperature"), std::string::npos);
  EXPECT_NE(problem({"elastic.wlf_c1=8.86", "elastic.temperature=30", "elastic.reference_temperature=20"})
                .find("elastic.wlf_c2: the WLF shift needs both"),
            std::string::npos);
  EXPECT_NE(problem({"elastic.wlf_c1=8.86", "elastic.wlf_c2=101.6", "elastic.temperature=30",
                     "elastic.reference_temperature=20", "elastic.activation_temperature=5000"})
                .find("elastic.activation_temperature"),
            std::string::npos);
  EXPECT_NE(problem({"elastic.viscoelastic=\"sls\"", "elastic.high_frequency_modulus=10",
                     "elastic.relaxation_time=1"})
                .find("elastic.master_curve: belongs to"),
            std::string::npos);
}
