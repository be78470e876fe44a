// Tests for atomic writes and NetCDF field files (include/gfmd/io/netcdf.hpp). The PNG maps
// are drawn by scripts/plot_maps.py: tests/python/test_plot_maps.py.
#include <gtest/gtest.h>
#include <netcdf.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "gfmd/core/error.hpp"
#include "gfmd/core/files.hpp"
#include "gfmd/io/netcdf.hpp"

namespace fs = std::filesystem;
using gfmd::Grid;

namespace {

// A fresh empty directory per test, removed afterwards.
class IoDir : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("gfmd_io_" + std::string(info->test_suite_name()) + "_" +
                                        info->name() + "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  [[nodiscard]] std::string file(const std::string& name) const { return (dir_ / name).string(); }

  [[nodiscard]] std::vector<std::string> entries() const {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(dir_)) out.push_back(e.path().filename().string());
    return out;
  }

  [[nodiscard]] bool has_tmp_file() const {
    for (const auto& name : entries())
      if (name.find(".tmp.") != std::string::npos) return true;
    return false;
  }

  fs::path dir_;
};

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// ---------------------------------------------------------------------------------------------

using AtomicWrite = IoDir;

TEST_F(AtomicWrite, CreatesAndReplacesContentWithoutLeavingTemporaries) {
  const std::string path = file("out.txt");
  gfmd::write_text_atomic(path, "first version, quite a bit longer than the second\n");
  EXPECT_EQ(slurp(path), "first version, quite a bit longer than the second\n");
  gfmd::write_text_atomic(path, "second\n");
  EXPECT_EQ(slurp(path), "second\n");
  gfmd::write_text_atomic(path, "");
  EXPECT_EQ(slurp(path), "");
  EXPECT_FALSE(has_tmp_file());
  EXPECT_EQ(entries().size(), 1u);
}

TEST_F(AtomicWrite, MissingDirectoryThrowsWithPathAndCreatesNothing) {
  const std::string path = file("no_such_dir/out.txt");
  try {
    gfmd::write_text_atomic(path, "data");
    FAIL() << "expected an exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(dir_ / "no_such_dir"));
  EXPECT_TRUE(entries().empty());
}

TEST_F(AtomicWrite, FailedRenameKeepsOldFileAndRemovesTemporary) {
  // The target is a non-empty directory: the temporary can be written, the rename fails.
  const std::string path = file("target");
  fs::create_directories(dir_ / "target");
  gfmd::write_text_atomic(file("target/keep.txt"), "old");
  EXPECT_THROW(gfmd::write_text_atomic(path, "new"), std::runtime_error);
  EXPECT_TRUE(fs::is_directory(path));
  EXPECT_EQ(slurp(file("target/keep.txt")), "old");
  EXPECT_FALSE(has_tmp_file());
}

// ---------------------------------------------------------------------------------------------

using NetCdf = IoDir;

TEST_F(NetCdf, RoundTripValuesDimsAndAttributes) {
  Grid g{5, 3, 2.5, 0.75};
  std::vector<double> p(g.size()), u(g.size());
  for (int iy = 0; iy < g.ny; ++iy)
    for (int ix = 0; ix < g.nx; ++ix) {
      p[static_cast<std::size_t>(iy) * g.nx + ix] = 10.0 * iy + ix + 0.125;
      u[static_cast<std::size_t>(iy) * g.nx + ix] = -std::sin(ix + 7.0 * iy);
    }
  const std::string path = file("fields.nc");
  gfmd::write_fields_netcdf(
      path, g,
      {{"pressure", p.data(), "contact pressure", "E*"},
       {"displacement", u.data(), "surface displacement", "h_rms"}},
      {{"gfmd_version", "0.1.0"}, {"git_commit", "abc123"}, {"input_toml", "[grid]\nnx = 5\n"}}, "um");
  EXPECT_FALSE(has_tmp_file());

  int nx = 0, ny = 0;
  const auto p2 = gfmd::read_netcdf_field(path, "pressure", nx, ny);
  EXPECT_EQ(nx, 5);
  EXPECT_EQ(ny, 3);
  ASSERT_EQ(p2.size(), p.size());
  for (std::size_t i = 0; i < p.size(); ++i) EXPECT_EQ(p2[i], p[i]) << i;
  const auto u2 = gfmd::read_netcdf_field(path, "displacement", nx, ny);
  ASSERT_EQ(u2.size(), u.size());
  for (std::size_t i = 0; i < u.size(); ++i) EXPECT_EQ(u2[i], u[i]) << i;

  int ncid = -1;
  ASSERT_EQ(nc_open(path.c_str(), NC_NOWRITE, &ncid), NC_NOERR);
  double lx = 0, ly = 0;
  EXPECT_EQ(nc_get_att_double(ncid, NC_GLOBAL, "lx", &lx), NC_NOERR);
  EXPECT_EQ(nc_get_att_double(ncid, NC_GLOBAL, "ly", &ly), NC_NOERR);
  EXPECT_EQ(lx, 2.5);
  EXPECT_EQ(ly, 0.75);

  auto text_att = [&](int varid, const char* name) {
    std::size_t len = 0;
    if (nc_inq_attlen(ncid, varid, name, &len) != NC_NOERR) return std::string("<missing>");
    std::string s(len, '\0');
    if (nc_get_att_text(ncid, varid, name, s.data()) != NC_NOERR) return std::string("<unreadable>");
    return s;
  };
  EXPECT_EQ(text_att(NC_GLOBAL, "git_commit"), "abc123");
  EXPECT_EQ(text_att(NC_GLOBAL, "input_toml"), "[grid]\nnx = 5\n");

  // Dimension order (y, x) and coordinate variables.
  int varid = -1, dimids[2] = {-1, -1};
  char dname[NC_MAX_NAME + 1];
  ASSERT_EQ(nc_inq_varid(ncid, "pressure", &varid), NC_NOERR);
  EXPECT_EQ(text_att(varid, "long_name"), "contact pressure");
  EXPECT_EQ(text_att(varid, "units"), "E*");
  ASSERT_EQ(nc_inq_vardimid(ncid, varid, dimids), NC_NOERR);
  ASSERT_EQ(nc_inq_dimname(ncid, dimids[0], dname), NC_NOERR);
  EXPECT_STREQ(dname, "y");
  ASSERT_EQ(nc_inq_dimname(ncid, dimids[1], dname), NC_NOERR);
  EXPECT_STREQ(dname, "x");

  ASSERT_EQ(nc_inq_varid(ncid, "x", &varid), NC_NOERR);
  EXPECT_EQ(text_att(varid, "units"), "um");
  std::vector<double> xs(5);
  ASSERT_EQ(nc_get_var_double(ncid, varid, xs.data()), NC_NOERR);
  for (int i = 0; i < 5; ++i) EXPECT_DOUBLE_EQ(xs[static_cast<std::size_t>(i)], i * 0.5);
  ASSERT_EQ(nc_inq_varid(ncid, "y", &varid), NC_NOERR);
  std::vector<double> ys(3);
  ASSERT_EQ(nc_get_var_double(ncid, varid, ys.data()), NC_NOERR);
  for (int i = 0; i < 3; ++i) EXPECT_DOUBLE_EQ(ys[static_cast<std::size_t>(i)], i * 0.25);
  nc_close(ncid);
}

TEST_F(NetCdf, RewriteReplacesOldFile) {
  Grid g{4, 4, 1.0, 1.0};
  std::vector<double> a(g.size(), 1.0), b(g.size(), 2.0);
  const std::string path = file("f.nc");
  gfmd::write_fields_netcdf(path, g, {{"h", a.data(), "", ""}}, {});
  gfmd::write_fields_netcdf(path, g, {{"h", b.data(), "", ""}}, {});
  int nx = 0, ny = 0;
  const auto h = gfmd::read_netcdf_field(path, "h", nx, ny);
  ASSERT_EQ(h.size(), g.size());
  EXPECT_EQ(h[0], 2.0);
  EXPECT_EQ(entries().size(), 1u);
}

TEST_F(NetCdf, ReadErrorsNameThePath) {
  const std::string missing = file("missing.nc");
  int nx = -1, ny = -1;
  try {
    (void)gfmd::read_netcdf_field(missing, "pressure", nx, ny);
    FAIL() << "expected InputError";
  } catch (const gfmd::InputError& e) {
    EXPECT_EQ(e.where(), missing);
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos);
  }

  Grid g{2, 2, 1.0, 1.0};
  std::vector<double> a(g.size(), 0.0);
  const std::string path = file("one.nc");
  gfmd::write_fields_netcdf(path, g, {{"gap", a.data(), "gap", "m"}}, {});
  try {
    (void)gfmd::read_netcdf_field(path, "pressure", nx, ny);
    FAIL() << "expected InputError";
  } catch (const gfmd::InputError& e) {
    EXPECT_EQ(e.where(), path);
    EXPECT_NE(e.why().find("pressure"), std::string::npos) << e.why();
  }
  // A 1D variable is not a field.
  EXPECT_THROW((void)gfmd::read_netcdf_field(path, "x", nx, ny), gfmd::InputError);
  EXPECT_EQ(nx, -1);  // untouched on failure
}

TEST_F(NetCdf, WriteErrorsLeaveNothingBehind) {
  Grid g{2, 2, 1.0, 1.0};
  std::vector<double> a(g.size(), 0.0);
  EXPECT_THROW(gfmd::write_fields_netcdf(file("nodir/f.nc"), g, {{"h", a.data(), "", ""}}, {}),
               std::runtime_error);
  EXPECT_THROW(
      gfmd::write_fields_netcdf(file("dup.nc"), g, {{"h", a.data(), "", ""}, {"h", a.data(), "", ""}}, {}),
      gfmd::InputError);
  EXPECT_THROW(gfmd::write_fields_netcdf(file("bad.nc"), g, {{"bad/name", a.data(), "", ""}}, {}),
               std::runtime_error);
  EXPECT_TRUE(entries().empty());
}

}  // namespace
