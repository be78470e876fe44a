// The gfmd executable: bad input gives a clear message, a non-zero exit and no output.
#include <gtest/gtest.h>
#include <netcdf.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>

#include "gfmd/case/run_directory.hpp"
#include "test_util.hpp"

namespace fs = std::filesystem;
using gfmd::testing::Outcome;
using gfmd::testing::run_gfmd;

namespace {

fs::path scratch(const std::string& name) { return gfmd::testing::scratch_dir("cli_test", name); }
using gfmd::testing::write_file;
const std::string& kGood = gfmd::testing::kSmallHertz;

struct BadCase {
  const char* name;
  std::string toml;      // case file text
  std::string extra;     // extra command-line arguments
  const char* fragment;  // expected in the message
};

}  // namespace

TEST(Cli, RunWritesSummaryFieldsAndMaps) {
  const fs::path d = scratch("good");
  write_file(d / "case.toml", kGood);
  const auto r = run_gfmd((d / "case.toml").string() + " -o " + (d / "out").string() + " -q");
  ASSERT_EQ(r.code, 2) << "a bare case path is not a command: " << r.output;  // 'run' is required
  const auto ok = run_gfmd("run " + (d / "case.toml").string() + " -o " + (d / "out").string() + " -q");
  ASSERT_EQ(ok.code, 0) << ok.output;
  for (const char* f : {"summary.json", "fields.nc", "pressure.png", "gap.png"})
    EXPECT_TRUE(fs::exists(d / "out" / f)) << f;
  std::ifstream in(d / "out" / "summary.json");
  const auto j = nlohmann::json::parse(in);
  for (const char* k : {"relative_contact_area", "normal_force", "mean_pressure", "max_pressure", "mean_gap",
                        "iterations", "converged", "residual", "wall_time_s", "input", "topography"})
    EXPECT_TRUE(j.contains(k)) << k;
  EXPECT_TRUE(j["converged"].get<bool>());
  EXPECT_NEAR(j["normal_force"].get<double>(), 0.01, 1e-12);
  EXPECT_EQ(j["input"]["elastic"]["thickness"], "inf");
  EXPECT_EQ(j["input"]["solver"]["tolerance"].get<double>(), 1e-8);  // default filled in
  // --set overrides reach the input record.
  const auto s = run_gfmd("run " + (d / "case.toml").string() + " -o " + (d / "out2").string() +
                          " -q --set elastic.poisson=0.3 --set load.pressure=0.0005 --set output.png=false");
  ASSERT_EQ(s.code, 0) << s.output;
  std::ifstream in2(d / "out2" / "summary.json");
  const auto j2 = nlohmann::json::parse(in2);
  EXPECT_EQ(j2["input"]["elastic"]["poisson"].get<double>(), 0.3);
  EXPECT_NEAR(j2["mean_pressure"].get<double>(), 0.0005, 1e-14);
}

TEST(Cli, BadInputIsRefusedCleanly) {
  const fs::path d = scratch("bad");
  write_file(d / "nan.txt", "# lx = 4\n# ly = 4\n1 2\nnan 4\n");
  const auto sub = [](std::string s, const std::string& from, const std::string& to) {
    const auto pos = s.find(from);
    EXPECT_NE(pos, std::string::npos) << from;
    return s.replace(pos, from.size(), to);
  };
  // [stress] depths with n entries of 0.1.
  const auto depths = [](int n) {
    std::string t = "[stress]\ndepths = [0.1";
    for (int i = 1; i < n; ++i) t += ",0.1";
    return t + "]\n";
  };
  const std::vector<BadCase> cases = {
      {"unknown_key", sub(kGood, "poisson = 0.25", "poison = 0.25"), "",
       "elastic.poison: unknown key (did you mean 'poisson'?)"},
      {"unknown_section", kGood + "[elastc]\nx = 1\n", "", "elastc: unknown section"},
      {"wrong_type", sub(kGood, "nx = 64", "nx = \"big\""), "", "grid.nx: must be an integer"},
      {"nu_high", sub(kGood, "poisson = 0.25", "poisson = 0.7"), "", "elastic.poisson"},
      {"nu_low", sub(kGood, "poisson = 0.25", "poisson = -1.0"), "", "outside (-1, 0.5]"},
      {"h_negative", sub(kGood, "poisson = 0.25", "poisson = 0.25\nthickness = -0.1"), "",
       "elastic.thickness"},
      {"h_zero", sub(kGood, "poisson = 0.25", "poisson = 0.25\nthickness = 0"), "", "elastic.thickness"},
      {"nu_half_layer", sub(kGood, "poisson = 0.25", "poisson = 0.5\nthickness = 0.2"), "", "singular"},
      {"grid_too_small", sub(kGood, "nx = 64", "nx = 1"), "", "grid.nx: must be an integer in [2, 65536]"},
      {"grid_too_big", sub(kGood, "nx = 64", "nx = 65536"), "", "GB allowed here (80% of"},
      {"lx_negative", sub(kGood, "lx = 4.0", "lx = -4.0"), "", "grid.lx"},
      {"cell_too_small", sub(kGood, "lx = 4.0", "lx = 0.5"), "", "periodic images"},
      {"no_load", sub(kGood, "force = 0.01", ""), "", "give exactly one of force, pressure, approach"},
      {"two_loads", sub(kGood, "force = 0.01", "force = 0.01\npressure = 0.1"), "", "exactly one of force"},
      {"negative_force", sub(kGood, "force = 0.01", "force = -0.01"), "", "load.force: must be positive"},
      {"bad_type", sub(kGood, "type = \"hertz\"", "type = \"herz\""), "", "did you mean 'hertz'"},
      {"missing_file",
       sub(sub(kGood, "type = \"hertz\"", "type = \"file\""), "radius = 1.0", "path = \"nope.txt\""), "",
       "nope.txt"},
      {"nan_file",
       sub(sub(kGood, "type = \"hertz\"", "type = \"file\""), "radius = 1.0", "path = \"nan.txt\""), "",
       "nan.txt"},
      {"syntax", "[grid\nnx = 3", "", "not valid TOML"},
      {"bad_set", kGood, "--set nonsense", "expected section.key=value"},
      {"set_unknown", kGood, "--set solver.tolerence=1e-6", "did you mean 'tolerance'"},
      // a bare word is a string, and its error names the override as a number's does
      {"set_bare_word", kGood, "--set grid.nx=abc",
       "grid.nx: must be an integer, got string [--set grid.nx=abc]"},
      // a value of the right type out of its range names its place too
      {"range_has_line", kGood + "[solver]\nmixing = 5\n", "", "solver.mixing: must be in (0, 1] ["},
      {"set_range_has_tag", kGood, "--set solver.backend=bogus",
       "(got \"bogus\") [--set solver.backend=bogus]"},
      {"tolerance", sub(kGood, "force = 0.01", "force = 0.01\n[solver]\ntolerance = 2"), "",
       "solver.tolerance"},
      {"invalid_utf8", kGood + "# \xff\xfe\n", "", "not valid UTF-8"},
      // overlong (E0 91 90), surrogate (ED A0 80), above U+10FFFF (F4 90 80 80): refused before
      // toml11, whose report of them inside a multi-line literal string reads past its buffer
      {"overlong_utf8",
       kGood + "[meta]\nnote = \'\'\'a\xe0\x91\x90"
               "b\'\'\'\n",
       "", "not valid UTF-8"},
      {"surrogate_utf8", kGood + "# \xed\xa0\x80\n", "", "not valid UTF-8"},
      {"beyond_unicode", kGood + "# \xf4\x90\x80\x80\n", "", "not valid UTF-8"},
      {"negative_mu", kGood + "[friction]\ncoefficient = -0.5\n", "", "friction.coefficient"},
      {"regularization", kGood + "[friction]\ncoefficient = 1\nregularization = 1.5\n", "",
       "friction.regularization: must be in [0, 1)"},
      {"bad_model", kGood + "[interaction]\nmodel = \"lennard-jones\"\n", "", "interaction.model"},
      {"threads", kGood + "[solver]\nthreads = -2\n", "", "solver.threads"},
      {"fft_planner", kGood + "[solver]\nfft_planner = \"patient\"\n", "",
       "solver.fft_planner: must be \"estimate\""},
      {"max_iterations", kGood + "[solver]\nmax_iterations = 0\n", "", "solver.max_iterations"},
      {"flow_solver", kGood + "[flow]\nsolver = \"petsc\"\n", "",
       "flow.solver: must be \"auto\", \"amg\" or \"boomeramg\""},
      {"sweep_no_values", kGood + "[sweep]\nparameter = \"load.force\"\n", "", "sweep.values"},
      {"eggcrate_period",
       sub(sub(kGood, "type = \"hertz\"", "type = \"eggcrate\""), "radius = 1.0", "wavelength = 0.7"), "",
       "whole number of wavelengths"},
      {"selfaffine_coarse",
       sub(sub(kGood, "type = \"hertz\"", "type = \"selfaffine\""), "radius = 1.0",
           "lambda_long = 1.0\nlambda_short = 0.05\nrms_height = 0.01"),
       "", "indenter.lambda_short"},
      {"selfaffine_two_rms",
       sub(sub(kGood, "type = \"hertz\"", "type = \"selfaffine\""), "radius = 1.0",
           "rms_height = 0.01\nrms_gradient = 0.1"),
       "", "exactly one of rms_height and rms_gradient"},
      {"hurst",
       sub(sub(kGood, "type = \"hertz\"", "type = \"selfaffine\""), "radius = 1.0",
           "hurst = 1.5\nrms_height = 0.01"),
       "", "indenter.hurst"},
      {"negative_radius", sub(kGood, "radius = 1.0", "radius = -1.0"), "", "indenter.radius"},
      {"grid_not_table", "grid = 3\n" + kGood.substr(kGood.find("[elastic]")), "", "grid: must be a table"},
      // Limits (issue 22): each once crashed, hung, ran for minutes or was silently truncated.
      {"deep_array", kGood + "[solver]\nx = " + std::string(10000, '[') + std::string(10000, ']') + "\n", "",
       "nested deeper than 64 levels"},
      {"deep_table",
       kGood + "[solver]\nx = " +
           [] {
             std::string t;
             for (int i = 0; i < 10000; ++i) t += "{a=";
             return t + "1" + std::string(10000, '}');
           }() +
           "\n",
       "", "nested deeper than 64 levels"},
      {"deep_dotted",
       kGood +
           [] {
             std::string t = "[a";
             for (int i = 0; i < 100000; ++i) t += ".a";
             return t + "]\n";
           }(),
       "", "dotted keys nested deeper than 64 levels"},
      {"deep_set", kGood, "--set solver.x=" + std::string(5000, '[') + std::string(5000, ']'),
       "nested deeper"},
      {"threads_huge", kGood + "[solver]\nthreads = 100000\n", "",
       "solver.threads: must be an integer in [0, 1024]"},
      {"sweep_points",
       kGood + "[sweep]\nparameter = \"load.force\"\nfrom = 0.001\nto = 0.01\npoints = 1000000000\n", "",
       "sweep.points: must be an integer in [0, 10000]"},
      {"long_array", kGood + depths(200001), "", "more than 10000 elements"},
      {"depths", kGood + depths(101), "", "stress.depths: at most 64 depths"},
      {"dev_zero",
       sub(sub(kGood, "type = \"hertz\"", "type = \"file\""), "radius = 1.0", "path = \"/dev/zero\""), "",
       "not a regular file"},
      {"fifo", sub(sub(kGood, "type = \"hertz\"", "type = \"file\""), "radius = 1.0", "path = \"fifo.txt\""),
       "", "not a regular file"},
      {"stiffness_nan", kGood + "[interaction]\nstiffness = nan\n", "",
       "interaction.stiffness: must be a finite"},
      {"lx_tiny", sub(kGood, "lx = 4.0", "lx = 1e-300"), "",
       "grid.lx: must be a positive length in [1e-30, 1e30]"},
      {"force_inf", sub(kGood, "force = 0.01", "force = inf"), "", "load.force: must be a finite number"},
      {"force_huge", sub(kGood, "force = 0.01", "force = 1e300"), "", "load.force: the mean pressure"},
      {"pressure_huge", sub(kGood, "force = 0.01", "pressure = 1e5"), "", "load.pressure: exceeds 1000 E*"},
      {"max_iterations_wrap", kGood + "[solver]\nmax_iterations = 4294967297\n", "",
       "solver.max_iterations: must be an integer in [1, 1000000000], got 4294967297"},
      {"seed_negative",
       sub(sub(kGood, "type = \"hertz\"", "type = \"selfaffine\""), "radius = 1.0",
           "rms_height = 0.01\nseed = -3"),
       "", "indenter.seed"},
      {"case_is_fifo", "", "", "not a regular file"},
      // Once out of the checks: a thickness of 1e-310 overflowed the layer's stiffness (exit 3).
      {"h_denormal", sub(kGood, "poisson = 0.25", "poisson = 0.25\nthickness = 1e-310"), "",
       "elastic.thickness: must be at least 1e-12 of the cell size"},
      {"flow_direction_bool", kGood + "[flow]\ndirection = true\n", "",
       "flow.direction: must be \"x\", \"y\", \"both\" or an angle in degrees, got boolean"},
      {"flow_direction_word", kGood + "[flow]\ndirection = \"diagonal\"\n", "", "got \"diagonal\""},
      {"map_unit",
       sub(sub(kGood, "type = \"hertz\"", "type = \"file\""), "radius = 1.0",
           "path = \"nan.txt\"\nunit = \"furlong\""),
       "", "1 problem in the case:\n  - indenter.unit: unknown length unit \"furlong\""},
  };
  ASSERT_EQ(::mkfifo((d / "fifo.txt").c_str(), 0600), 0);
  for (const auto& c : cases) {
    const fs::path tomlp = d / (std::string(c.name) + ".toml");
    const fs::path out = d / (std::string(c.name) + "_out");
    if (std::string(c.name) == "case_is_fifo")
      ASSERT_EQ(::mkfifo(tomlp.c_str(), 0600), 0);  // the case file itself: must not hang
    else
      write_file(tomlp, c.toml);
    const auto r = run_gfmd("run " + tomlp.string() + " -o " + out.string() + " -q " + c.extra);
    EXPECT_NE(r.code, 0) << c.name;
    EXPECT_NE(r.output.find(c.fragment), std::string::npos) << c.name << ": " << r.output;
    EXPECT_FALSE(fs::exists(out)) << c.name << " left an output directory";
  }
  const auto missing = run_gfmd("run " + (d / "does_not_exist.toml").string() + " -q");
  EXPECT_EQ(missing.code, 2);
  EXPECT_NE(missing.output.find("cannot open the case file"), std::string::npos);
}

TEST(Cli, BadTopographyFilesAreRefusedCleanly) {
  const fs::path d = scratch("badtopo");
  const std::string head = "# lx = 4\n# ly = 4\n";
  struct F {
    const char* name;
    std::string content;
    const char* fragment;
  };
  std::string truncated_nc;
  {
    // A valid NetCDF written by gfmd, cut short.
    write_file(d / "src.toml", kGood + "[output]\npng = false\n");
    const auto r = run_gfmd("run " + (d / "src.toml").string() + " -o " + (d / "src").string() + " -q");
    ASSERT_EQ(r.code, 0) << r.output;
    std::ifstream in(d / "src" / "fields.nc", std::ios::binary);
    truncated_nc.assign((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    truncated_nc.resize(truncated_nc.size() / 2);
  }
  const std::vector<F> files = {
      {"ragged.txt", head + "1 2 3\n4 5\n", "ragged rows"},
      {"word.txt", head + "1 2\nx 4\n", "non-numeric value"},
      {"nan.txt", head + "1 2\nnan 4\n", "1 point has no value"},
      {"inf.txt", head + "1 inf\n3 4\n", "non-finite"},
      {"empty.txt", "", "empty"},
      {"comments_only.txt", head, "no data"},
      {"binary.txt", head + std::string("\x01\x02\xff 7\n", 6), "non-numeric value"},
      {"badheader.txt", "# lx = -3\n# ly = 4\n1 2\n3 4\n", "lx"},
      {"garbage.nc", "this is not netcdf", ".nc"},
      {"truncated.nc", truncated_nc, "truncated.nc"},
  };
  for (const auto& f : files) {
    {
      std::ofstream o(d / f.name, std::ios::binary);
      o << f.content;
    }
    std::string toml = kGood;
    toml.replace(toml.find("type = \"hertz\""), 14, "type = \"file\"");
    toml.replace(toml.find("radius = 1.0"), 12, std::string("path = \"") + f.name + "\"");
    write_file(d / "case.toml", toml);
    const fs::path out = d / (std::string(f.name) + "_out");
    const auto r = run_gfmd("run " + (d / "case.toml").string() + " -o " + out.string() + " -q");
    EXPECT_NE(r.code, 0) << f.name;
    EXPECT_NE(r.output.find(f.name), std::string::npos) << f.name << ": " << r.output;
    EXPECT_NE(r.output.find(f.fragment), std::string::npos) << f.name << ": " << r.output;
    EXPECT_FALSE(fs::exists(out)) << f.name;
  }
  // A directory is not a height map.
  fs::create_directories(d / "adir.txt");
  std::string toml = kGood;
  toml.replace(toml.find("type = \"hertz\""), 14, "type = \"file\"");
  toml.replace(toml.find("radius = 1.0"), 12, "path = \"adir.txt\"");
  write_file(d / "case.toml", toml);
  const auto r = run_gfmd("run " + (d / "case.toml").string() + " -o " + (d / "dir_out").string() + " -q");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.output.find("adir.txt"), std::string::npos) << r.output;
}

// A text height map with its size header needs no [grid]: dimensions and size come from it
// (as the README says).
TEST(Cli, HeightMapHeaderGivesTheGrid) {
  const fs::path d = scratch("header");
  std::string map = "# lx = 2\n# ly = 1\n";
  for (int iy = 0; iy < 16; ++iy) {
    for (int ix = 0; ix < 32; ++ix)
      map += std::to_string(0.01 * std::cos(2 * 3.141592653589793 * ix / 32.0)) + (ix < 31 ? "," : "\n");
  }
  write_file(d / "map.csv", map);
  write_file(
      d / "case.toml",
      "[indenter]\ntype = \"file\"\npath = \"map.csv\"\n[load]\npressure = 0.001\n[output]\npng = false\n");
  const auto r = run_gfmd("run " + (d / "case.toml").string() + " -o " + (d / "out").string() + " -q");
  ASSERT_EQ(r.code, 0) << r.output;
  std::ifstream in(d / "out" / "summary.json");
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j["input"]["grid"]["nx"], 32);
  EXPECT_EQ(j["input"]["grid"]["ny"], 16);
  EXPECT_EQ(j["input"]["grid"]["lx"].get<double>(), 2.0);
  EXPECT_EQ(j["input"]["grid"]["ly"].get<double>(), 1.0);
  // Without a header and without [grid] the error says what is missing.
  write_file(d / "bare.txt", "1 2\n3 4\n");
  write_file(d / "bare.toml", "[indenter]\ntype = \"file\"\npath = \"bare.txt\"\n[load]\npressure = 0.001\n");
  const auto b = run_gfmd("run " + (d / "bare.toml").string() + " -o " + (d / "bout").string() + " -q");
  EXPECT_EQ(b.code, 2);
  EXPECT_NE(b.output.find("no physical size lx"), std::string::npos) << b.output;
  EXPECT_NE(b.output.find("grid.lx"), std::string::npos) << b.output;
}

// gfmd plot on a directory that holds no run, sweep or study: exit 2 naming it, nothing
// written there. (Drawing itself: tests/python/test_plot_maps.py.)
TEST(Cli, PlotRefusesADirectoryWithoutResults) {
  const fs::path d = scratch("plot_empty");
  fs::create_directories(d / "empty");
  const auto r = run_gfmd("plot " + (d / "empty").string());
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find((d / "empty").string() + ": not a gfmd run, sweep, curve or study directory"),
            std::string::npos)
      << r.output;
  EXPECT_TRUE(fs::is_empty(d / "empty"));
  const auto m = run_gfmd("plot " + (d / "missing").string());
  EXPECT_EQ(m.code, 2) << m.output;
  EXPECT_NE(m.output.find((d / "missing").string()), std::string::npos) << m.output;
  EXPECT_FALSE(fs::exists(d / "missing"));
}

TEST(Cli, UnconvergedSolveWritesNothing) {
  const fs::path d = scratch("unconverged");
  write_file(d / "case.toml", kGood + "[solver]\nmax_iterations = 3\n");
  const auto r = run_gfmd("run " + (d / "case.toml").string() + " -o " + (d / "out").string() + " -q");
  EXPECT_EQ(r.code, 3);
  EXPECT_NE(r.output.find("not converged"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(d / "out" / "summary.json"));
}

// The OpenMP wait: bounded spinning (GOMP_SPINCOUNT=10000, set by gfmd restarting itself) unless
// the user chose a policy; summary.json says which one the run had.
TEST(Cli, OpenMpSpinIsBoundedUnlessTheUserChoseAPolicy) {
  const fs::path d = scratch("spin");
  write_file(d / "case.toml", kGood + "[output]\npng = false\nfields = false\n");
  const auto omp_wait = [&](const std::string& env, const std::string& out) {
    const std::string cmd = "env -u OMP_WAIT_POLICY -u GOMP_SPINCOUNT " + env + " " + GFMD_EXE + " run " +
                            (d / "case.toml").string() + " -q -o " + (d / out).string() + " 2>&1";
    FILE* pipe = popen(cmd.c_str(), "r");
    std::array<char, 4096> buf{};
    std::string log;
    while (pipe && fgets(buf.data(), buf.size(), pipe)) log += buf.data();
    EXPECT_EQ(pipe ? pclose(pipe) : -1, 0) << log;
    std::ifstream in(d / out / "summary.json");
    return nlohmann::json::parse(in)["omp_wait"].get<std::string>();
  };
  EXPECT_EQ(omp_wait("", "none"), "GOMP_SPINCOUNT=10000");
  EXPECT_EQ(omp_wait("GOMP_SPINCOUNT=500", "count"), "GOMP_SPINCOUNT=500");
  EXPECT_EQ(omp_wait("OMP_WAIT_POLICY=passive", "policy"), "OMP_WAIT_POLICY=passive");
}

// Review findings (2026-11-26): -o "" is refused instead of writing to the default directory;
// grid.unit reaches the units of fields.nc and flow.nc; a numeric flow.direction is an angle.
TEST(Cli, EmptyOutputUnitsAndNumericFlowDirection) {
  const fs::path d = scratch("units");
  write_file(d / "case.toml", kGood + "[output]\npng = false\n");
  const auto empty = run_gfmd("run " + (d / "case.toml").string() + " -q -o \"\"");
  EXPECT_EQ(empty.code, 2) << empty.output;
  EXPECT_NE(empty.output.find("--output: must not be empty"), std::string::npos) << empty.output;
  EXPECT_FALSE(fs::exists("out/case")) << "an empty -o fell back to the default directory";
  const auto r = run_gfmd("run " + (d / "case.toml").string() + " -q -o " + (d / "out").string() +
                          " --set 'grid.unit=\"um\"' --set flow.direction=30");
  ASSERT_EQ(r.code, 0) << r.output;
  // The units attribute of a variable ("" if it has none).
  const auto units = [](const fs::path& file, const char* var) {
    int nc = -1, v = -1;
    std::size_t len = 0;
    std::string text;
    if (nc_open(file.c_str(), NC_NOWRITE, &nc) != NC_NOERR) return std::string("(cannot open)");
    if (nc_inq_varid(nc, var, &v) == NC_NOERR && nc_inq_attlen(nc, v, "units", &len) == NC_NOERR) {
      text.resize(len);
      if (nc_get_att_text(nc, v, "units", text.data()) != NC_NOERR) text = "(unreadable)";
    }
    nc_close(nc);
    return text;
  };
  for (const char* var : {"x", "y", "topography", "gap", "ux", "uz"})
    EXPECT_EQ(units(d / "out" / "fields.nc", var), "um") << var;
  EXPECT_EQ(units(d / "out" / "fields.nc", "pressure"), "E*");
  EXPECT_EQ(units(d / "out" / "fields.nc", "current_30deg"), "um^3");
  EXPECT_EQ(units(d / "out" / "flow.nc", "current_x_30deg"), "um^3");
  EXPECT_EQ(units(d / "out" / "flow.nc", "x"), "um");
  std::ifstream in(d / "out" / "flow.json");
  const auto j = nlohmann::json::parse(in);
  EXPECT_TRUE(j.contains("flow_factor_30deg")) << j.dump();
}

// Review findings (2026-11-26, second review): a list given to `gfmd run` points to `gfmd sweep`;
// `gfmd flow` on a run without fields.nc says which key was off.
TEST(Cli, HintsForAListAndForAFlowWithoutFields) {
  const fs::path d = scratch("hints");
  write_file(d / "case.toml", kGood + "[output]\npng = false\nfields = false\n");
  const auto list = run_gfmd("run " + (d / "case.toml").string() + " -q -o " + (d / "a").string() +
                             " --set load.force=1e-3,2e-3");
  EXPECT_EQ(list.code, 2) << list.output;
  EXPECT_NE(list.output.find("is for `gfmd sweep"), std::string::npos) << list.output;
  EXPECT_FALSE(fs::exists(d / "a" / "summary.json"));
  const auto one = run_gfmd("run " + (d / "case.toml").string() + " -q -o " + (d / "b").string() +
                            " --set 'load.force=\"a,b\"'");
  EXPECT_EQ(one.code, 2) << one.output;
  EXPECT_EQ(one.output.find("gfmd sweep"), std::string::npos)
      << "a quoted string is not a list: " << one.output;
  ASSERT_EQ(run_gfmd("run " + (d / "case.toml").string() + " -q -o " + (d / "c").string()).code, 0);
  const auto flow = run_gfmd("flow " + (d / "c").string());
  EXPECT_EQ(flow.code, 2) << flow.output;
  EXPECT_NE(flow.output.find("output.fields = false"), std::string::npos) << flow.output;
}

// A sweep's plot column that the summaries do not have stops the sweep after its first point
// (exit 2, naming the option), not after every point with a warning.
TEST(Cli, SweepPlotColumnIsCheckedAtTheFirstPoint) {
  const fs::path d = scratch("sweep_plot");
  write_file(d / "case.toml", kGood + "[output]\npng = false\nfields = false\n");
  const auto r = run_gfmd("sweep " + (d / "case.toml").string() + " -q -o " + (d / "s").string() +
                          " --set load.force=0.005,0.01,0.02 --plot contact_areaa");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("--plot: the summaries have no column 'contact_areaa'"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("relative_contact_area"), std::string::npos) << r.output;  // the columns it has
  EXPECT_TRUE(fs::exists(d / "s" / "point_000" / "summary.json"));
  EXPECT_FALSE(fs::exists(d / "s" / "point_001"));
  // The case's [sweep] plot likewise, named by its key; a column that exists draws as before.
  write_file(d / "sw.toml", kGood +
                                "[output]\npng = false\nfields = false\n[sweep]\nparameter = \"load.force\"\n"
                                "values = [0.005, 0.01]\nplot = \"nope\"\n");
  const auto k = run_gfmd("sweep " + (d / "sw.toml").string() + " -q -o " + (d / "k").string());
  EXPECT_EQ(k.code, 2) << k.output;
  EXPECT_NE(k.output.find("sweep.plot: the summaries have no column 'nope'"), std::string::npos) << k.output;
  const auto ok = run_gfmd("sweep " + (d / "case.toml").string() + " -q -o " + (d / "s").string() +
                           " --set load.force=0.005,0.01 --plot max_pressure");
  EXPECT_EQ(ok.code, 0) << ok.output;
  EXPECT_TRUE(fs::exists(d / "s" / "sweep_max_pressure.png")) << ok.output;
}

// A TOML array, table or string given with --set beside the swept key is one value (it was
// split on its commas: "only one swept key per sweep" or "'[0.02' is not a number").
TEST(Cli, SweepTakesArrayValuedSettings) {
  const fs::path d = scratch("sweep_arrays");
  write_file(d / "case.toml", kGood + "[output]\npng = false\nfields = false\n");
  const auto r = run_gfmd("sweep " + (d / "case.toml").string() + " -q -o " + (d / "s").string() +
                          " --set load.force=0.005,0.01 --set 'stress.depths=[0.02, 0.04]'");
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string summary = gfmd::testing::read_file(d / "s" / "point_001" / "summary.json");
  EXPECT_NE(summary.find("\"subsurface\""), std::string::npos);
  const auto j = nlohmann::json::parse(summary);
  EXPECT_EQ(j["input"]["stress"]["depths"], nlohmann::json({0.02, 0.04}));
  // A word where a number is swept says what a sweep takes.
  const auto w = run_gfmd("sweep " + (d / "case.toml").string() + " -q -o " + (d / "w").string() +
                          " --set elastic.coupling=true,false");
  EXPECT_EQ(w.code, 2) << w.output;
  EXPECT_NE(w.output.find("a sweep's values are numbers"), std::string::npos) << w.output;
}

// Without friction the default plot is not the friction coefficient (there is none): a load
// sweep draws the contact area, an approach sweep the force it finds, with no complaint about a
// missing column; sweeping friction itself draws the friction coefficient.
TEST(Cli, AFrictionlessSweepDrawsWhatItHas) {
  const fs::path d = scratch("sweep_default_plot");
  write_file(d / "case.toml", kGood + "[output]\npng = false\nfields = false\n");
  const auto a = run_gfmd("sweep " + (d / "case.toml").string() + " -q -o " + (d / "a").string() +
                          " --set load.force=0.005,0.01");
  EXPECT_EQ(a.code, 0) << a.output;
  EXPECT_EQ(a.output.find("no column"), std::string::npos) << a.output;
  EXPECT_TRUE(fs::exists(d / "a" / "sweep_relative_contact_area.png")) << a.output;
  const auto b = run_gfmd("sweep " + (d / "case.toml").string() + " -q -o " + (d / "b").string() +
                          " --set load.approach=0.005,0.01");
  EXPECT_EQ(b.code, 0) << b.output;
  EXPECT_TRUE(fs::exists(d / "b" / "sweep_normal_force.png")) << b.output;
  const auto c = run_gfmd("sweep " + (d / "case.toml").string() + " -q -o " + (d / "c").string() +
                          " --set friction.coefficient=0.2,0.4");
  EXPECT_EQ(c.code, 0) << c.output;
  EXPECT_TRUE(fs::exists(d / "c" / "sweep_friction_coefficient.png")) << c.output;
}

// A speed sweep of a frictionless viscoelastic body draws its hysteresis friction (it drew
// nothing: "could not draw friction_coefficient", exit 0), and gfmd plot redraws that column.
TEST(Cli, AViscoelasticSpeedSweepDrawsItsHysteresisFriction) {
  const fs::path d = scratch("sweep_visco_plot");
  write_file(d / "case.toml",
             "[grid]\nnx = 32\nlx = 1.5\n[elastic]\nviscoelastic = \"sls\"\nhigh_frequency_modulus = 10.0\n"
             "relaxation_time = 1.0\n[indenter]\ntype = \"hertz\"\nradius = 1.0\n[load]\nforce = 0.01\n"
             "[friction]\nvelocity = 0.02\n[output]\npng = false\nfields = false\n");
  const fs::path out = d / "s";
  const auto a = run_gfmd("sweep " + (d / "case.toml").string() + " -q -o " + out.string() +
                          " --set friction.velocity=0.01,0.1");
  EXPECT_EQ(a.code, 0) << a.output;
  EXPECT_EQ(a.output.find("could not draw"), std::string::npos) << a.output;
  EXPECT_TRUE(fs::exists(out / "sweep_hysteresis_friction.png")) << a.output;
  fs::remove(out / "sweep_hysteresis_friction.png");
  const auto p = run_gfmd("plot " + out.string());
  EXPECT_EQ(p.code, 0) << p.output;
  EXPECT_TRUE(fs::exists(out / "sweep_hysteresis_friction.png")) << p.output;
  // gfmd run prints the body's hysteresis friction (it printed none; with friction, the total
  // stood as the "downhill" coefficient).
  const auto r = run_gfmd("run " + (d / "case.toml").string() + " -o " + (d / "r").string() +
                          " --set friction.coefficient=0.3");
  ASSERT_EQ(r.code, 0) << r.output;
  const auto j = nlohmann::json::parse(gfmd::testing::read_file(d / "r" / "summary.json"));
  char line[160];
  std::snprintf(line, sizeof line, "hysteresis friction    %.6g (the body's)",
                j["hysteresis_friction"].get<double>());
  EXPECT_NE(r.output.find(line), std::string::npos) << r.output;
  std::snprintf(line, sizeof line, "total friction coeff.  %.6g (interface + hysteresis)",
                j["total_friction_coefficient"].get<double>());
  EXPECT_NE(r.output.find(line), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("(downhill)"), std::string::npos) << r.output;
}

// A percolation search's area tolerance is a fraction in (0, 1): nan or a negative one never
// ended the bracketing and gave the unfinished bracket's threshold with exit 0.
TEST(Cli, APercolationToleranceOutsideItsRangeIsRefused) {
  const fs::path d = scratch("perc_tolerance");
  write_file(d / "case.toml", kGood);
  for (const char* tol : {"nan", "-1", "0", "1.5"}) {
    const auto r = run_gfmd("percolation " + (d / "case.toml").string() +
                            " --direction x -q --area-tolerance " + tol + " -o " + (d / "out").string());
    EXPECT_EQ(r.code, 2) << tol << ": " << r.output;
    EXPECT_NE(r.output.find("--area-tolerance: must be a contact-area fraction in (0, 1)"), std::string::npos)
        << r.output;
    EXPECT_FALSE(fs::exists(d / "out")) << tol;
  }
}

// gfmd plot on a folder of sweeps without a table of its own (a study's series of seeds, a
// sweep per seed) redraws their figures; it was "not a gfmd run, sweep, curve or study
// directory". Runs without fields.nc get one note together.
TEST(Cli, PlotRedrawsAFolderOfSweeps) {
  const fs::path d = scratch("plot_group");
  write_file(d / "case.toml", kGood + "[output]\npng = false\nfields = false\n");
  for (const char* seed : {"seed_0", "seed_1"})
    ASSERT_EQ(run_gfmd("sweep " + (d / "case.toml").string() + " -q -o " + (d / "series" / seed).string() +
                       " --set load.force=0.006,0.014")
                  .code,
              0);
  fs::remove(d / "series" / "seed_0" / "sweep_relative_contact_area.png");
  const auto p = run_gfmd("plot " + (d / "series").string());
  EXPECT_EQ(p.code, 0) << p.output;
  EXPECT_TRUE(fs::exists(d / "series" / "seed_0" / "sweep_relative_contact_area.png")) << p.output;
  EXPECT_NE(p.output.find("4 runs ("), std::string::npos) << p.output;  // one note for the four points
  // The folder is not marked as gfmd's by it (the marker would let a run replace its sweeps).
  EXPECT_FALSE(fs::exists(d / "series" / gfmd::kDirectoryMarker));
  // A folder with nothing of gfmd's is still refused.
  fs::create_directories(d / "other" / "sub");
  EXPECT_EQ(run_gfmd("plot " + (d / "other").string()).code, 2);
}
