// Tests for atomic writes, NetCDF field files and PNG maps (include/gfmd/io/netcdf.hpp).
#include <gtest/gtest.h>
#include <netcdf.h>
#include <unistd.h>

#include <array>
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
#include "gfmd/io/png.hpp"

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

using Rgb = std::array<unsigned char, 3>;

Rgb pixel(const std::vector<unsigned char>& img, int width, int x, int y) {
  const std::size_t i = (static_cast<std::size_t>(y) * width + x) * 3;
  return {img[i], img[i + 1], img[i + 2]};
}

std::string str(const Rgb& c) {
  return "(" + std::to_string(c[0]) + "," + std::to_string(c[1]) + "," + std::to_string(c[2]) + ")";
}

#define EXPECT_RGB(actual, expected) EXPECT_EQ(str(actual), str(expected))

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

// ---------------------------------------------------------------------------------------------

using Png = IoDir;

TEST_F(Png, SizeForGivenScaleAndAutomaticScale) {
  Grid g{7, 3, 7.0, 3.0};
  std::vector<double> f(g.size(), 1.0);
  gfmd::PngOptions opt;
  opt.scale = 5;
  opt.colorbar = false;
  const std::string path = file("a.png");
  gfmd::write_png_map(path, g, f.data(), opt);
  int w = 0, h = 0;
  auto img = gfmd::read_png_rgb(path, w, h);
  EXPECT_EQ(w, 35);
  EXPECT_EQ(h, 15);
  EXPECT_EQ(img.size(), 35u * 15u * 3u);
  EXPECT_FALSE(has_tmp_file());

  // The colour bar adds a strip on the right, not rows.
  opt.colorbar = true;
  opt.scale = 20;
  gfmd::write_png_map(path, g, f.data(), opt);
  img = gfmd::read_png_rgb(path, w, h);
  EXPECT_GT(w, 140);
  EXPECT_EQ(h, 60);

  // Automatic scale: small grids are magnified to >= 256 px on the long side ...
  opt = {};
  opt.colorbar = false;
  Grid small{40, 10, 1.0, 1.0};
  std::vector<double> fs_(small.size(), 0.0);
  gfmd::write_png_map(path, small, fs_.data(), opt);
  img = gfmd::read_png_rgb(path, w, h);
  EXPECT_EQ(w, 280);  // 7 px per cell
  EXPECT_EQ(h, 70);
  // ... large ones are averaged down to <= 1024 px.
  Grid big{2500, 30, 1.0, 1.0};
  std::vector<double> fb(big.size(), 0.0);
  gfmd::write_png_map(path, big, fb.data(), opt);
  img = gfmd::read_png_rgb(path, w, h);
  EXPECT_EQ(w, 834);  // blocks of 3 cells
  EXPECT_EQ(h, 10);
}

TEST_F(Png, RampEndsHaveColormapEndColoursAndYPointsUp) {
  // Ramp in y: the top image row shows iy = ny-1 (maximum), the bottom row iy = 0 (minimum).
  Grid g{4, 6, 1.0, 1.0};
  std::vector<double> f(g.size());
  for (int iy = 0; iy < g.ny; ++iy)
    for (int ix = 0; ix < g.nx; ++ix) f[static_cast<std::size_t>(iy) * g.nx + ix] = 3.0 * iy - 2.0;
  gfmd::PngOptions opt;
  opt.scale = 5;  // 20 x 30 px map; the colour bar needs no extra rows
  const std::string path = file("ramp.png");
  for (const std::string cmap : {"viridis", "inferno", "coolwarm", "gray"}) {
    opt.colormap = cmap;
    gfmd::write_png_map(path, g, f.data(), opt);
    int w = 0, h = 0;
    const auto img = gfmd::read_png_rgb(path, w, h);
    ASSERT_EQ(h, 30);
    ASSERT_GT(w, 40);
    const Rgb top = gfmd::colormap_rgb(cmap, 1.0), bottom = gfmd::colormap_rgb(cmap, 0.0);
    EXPECT_NE(str(top), str(bottom)) << cmap;
    EXPECT_RGB(pixel(img, w, 1, 0), top) << cmap;
    EXPECT_RGB(pixel(img, w, 17, 4), top) << cmap;
    EXPECT_RGB(pixel(img, w, 1, 29), bottom) << cmap;
    EXPECT_RGB(pixel(img, w, 18, 25), bottom) << cmap;
    // Colour bar (inside its 1 px frame, right of an 8 px gap): top colour at the top.
    EXPECT_RGB(pixel(img, w, 30, 1), top) << cmap;
    EXPECT_RGB(pixel(img, w, 30, 28), bottom) << cmap;
    EXPECT_RGB(pixel(img, w, 22, 15), (Rgb{255, 255, 255})) << cmap;  // gap
  }
  // Independent of colormap_rgb: viridis runs from dark purple to yellow, gray from black to white.
  EXPECT_RGB(gfmd::colormap_rgb("viridis", 0.0), (Rgb{68, 1, 84}));
  EXPECT_RGB(gfmd::colormap_rgb("viridis", 1.0), (Rgb{253, 231, 37}));
  EXPECT_RGB(gfmd::colormap_rgb("gray", 0.0), (Rgb{0, 0, 0}));
  EXPECT_RGB(gfmd::colormap_rgb("gray", 1.0), (Rgb{255, 255, 255}));
  EXPECT_RGB(gfmd::colormap_rgb("gray", 2.0), (Rgb{255, 255, 255}));  // clamped
  EXPECT_THROW((void)gfmd::colormap_rgb("jet", 0.5), gfmd::InputError);
}

TEST_F(Png, RampInXWithExplicitLimitsClamps) {
  Grid g{5, 2, 1.0, 1.0};
  std::vector<double> f(g.size());
  for (int iy = 0; iy < g.ny; ++iy)
    for (int ix = 0; ix < g.nx; ++ix) f[static_cast<std::size_t>(iy) * g.nx + ix] = ix;  // 0..4
  gfmd::PngOptions opt;
  opt.scale = 2;
  opt.colorbar = false;
  opt.colormap = "gray";
  opt.vmin = 1.0;
  opt.vmax = 3.0;
  const std::string path = file("x.png");
  gfmd::write_png_map(path, g, f.data(), opt);
  int w = 0, h = 0;
  const auto img = gfmd::read_png_rgb(path, w, h);
  ASSERT_EQ(w, 10);
  EXPECT_RGB(pixel(img, w, 0, 0), (Rgb{0, 0, 0}));        // 0 < vmin: clamped
  EXPECT_RGB(pixel(img, w, 2, 0), (Rgb{0, 0, 0}));        // vmin
  EXPECT_RGB(pixel(img, w, 4, 3), (Rgb{128, 128, 128}));  // middle (127.5 rounds up)
  EXPECT_RGB(pixel(img, w, 6, 0), (Rgb{255, 255, 255}));  // vmax
  EXPECT_RGB(pixel(img, w, 9, 3), (Rgb{255, 255, 255}));  // 4 > vmax: clamped
}

TEST_F(Png, NanCellIsGrey) {
  Grid g{3, 3, 1.0, 1.0};
  std::vector<double> f = {0, 1, 2, 3, std::numeric_limits<double>::quiet_NaN(), 5, 6, 7, 8};
  gfmd::PngOptions opt;
  opt.scale = 4;
  const std::string path = file("nan.png");
  gfmd::write_png_map(path, g, f.data(), opt);
  int w = 0, h = 0;
  const auto img = gfmd::read_png_rgb(path, w, h);
  EXPECT_RGB(pixel(img, w, 5, 6), (Rgb{128, 128, 128}));                 // centre cell
  EXPECT_RGB(pixel(img, w, 1, 10), gfmd::colormap_rgb("viridis", 0.0));  // (0,0): minimum
  EXPECT_RGB(pixel(img, w, 10, 1), gfmd::colormap_rgb("viridis", 1.0));  // (2,2): maximum

  // An all-NaN field still gives a (grey) picture.
  std::vector<double> all_nan(g.size(), std::numeric_limits<double>::quiet_NaN());
  gfmd::write_png_map(path, g, all_nan.data(), opt);
  const auto img2 = gfmd::read_png_rgb(path, w, h);
  EXPECT_RGB(pixel(img2, w, 0, 0), (Rgb{128, 128, 128}));
}

TEST_F(Png, SymmetricMapsZeroToCentreColour) {
  Grid g{3, 1, 1.0, 1.0};
  std::vector<double> f = {-1.0, 0.0, 4.0};
  gfmd::PngOptions opt;
  opt.scale = 2;
  opt.colormap = "coolwarm";
  opt.symmetric = true;
  opt.colorbar = false;
  const std::string path = file("sym.png");
  gfmd::write_png_map(path, g, f.data(), opt);
  int w = 0, h = 0;
  const auto img = gfmd::read_png_rgb(path, w, h);
  const Rgb centre = gfmd::colormap_rgb("coolwarm", 0.5);
  EXPECT_RGB(centre, (Rgb{221, 221, 221}));
  EXPECT_RGB(pixel(img, w, 2, 0), centre);                                 // 0
  EXPECT_RGB(pixel(img, w, 0, 1), gfmd::colormap_rgb("coolwarm", 0.375));  // -1 of ±4
  EXPECT_RGB(pixel(img, w, 5, 1), gfmd::colormap_rgb("coolwarm", 1.0));    // 4

  // Without the option the data range [-1, 4] is used and 0 is off-centre.
  opt.symmetric = false;
  gfmd::write_png_map(path, g, f.data(), opt);
  const auto img2 = gfmd::read_png_rgb(path, w, h);
  EXPECT_RGB(pixel(img2, w, 2, 0), gfmd::colormap_rgb("coolwarm", 0.2));
}

TEST_F(Png, MaskOutlineColourbarAndTitle) {
  Grid g{8, 8, 1.0, 1.0};
  std::vector<double> f(g.size(), 0.0);
  std::vector<unsigned char> mask(g.size(), 0);
  for (int iy = 2; iy < 6; ++iy)
    for (int ix = 2; ix < 6; ++ix) mask[static_cast<std::size_t>(iy) * g.nx + ix] = 1;
  f[0] = 1.0;
  gfmd::PngOptions opt;
  opt.scale = 4;
  opt.mask = mask.data();
  opt.title = "Pressure p/E* = 0.5";
  const std::string path = file("mask.png");
  gfmd::write_png_map(path, g, f.data(), opt);
  int w = 0, h = 0;
  const auto img = gfmd::read_png_rgb(path, w, h);
  EXPECT_GT(w, 32);
  EXPECT_GT(h, 32);        // title band
  const int top = h - 32;  // the map sits at the bottom left
  const Rgb base = gfmd::colormap_rgb("viridis", 0.0);
  EXPECT_RGB(pixel(img, w, 1, top + 1), base);           // unmasked cell
  EXPECT_NE(str(pixel(img, w, 8, top + 8)), str(base));  // corner of the masked square: outline
  EXPECT_RGB(pixel(img, w, 14, top + 14), base);         // inside the masked square
  // Some dark ink in the title band and in the label column next to the bar.
  bool ink_title = false, ink_label = false;
  for (int y = 0; y < top; ++y)
    for (int x = 0; x < w; ++x)
      if (pixel(img, w, x, y)[0] < 64) ink_title = true;
  for (int y = top; y < h; ++y)
    for (int x = 58; x < w; ++x)  // right of the bar's frame (map 32 + gap 8 + frame 1 + bar 15 + frame 1)
      if (pixel(img, w, x, y)[0] < 64) ink_label = true;
  EXPECT_TRUE(ink_title);
  EXPECT_TRUE(ink_label);
}

TEST_F(Png, BadOptionsAndUnreadableFiles) {
  Grid g{2, 2, 1.0, 1.0};
  std::vector<double> f(g.size(), 0.0);
  gfmd::PngOptions opt;
  opt.colormap = "rainbow";
  EXPECT_THROW(gfmd::write_png_map(file("a.png"), g, f.data(), opt), gfmd::InputError);
  opt = {};
  opt.vmin = 2.0;
  opt.vmax = 1.0;
  EXPECT_THROW(gfmd::write_png_map(file("a.png"), g, f.data(), opt), gfmd::InputError);
  opt = {};
  EXPECT_THROW(gfmd::write_png_map(file("nodir/a.png"), g, f.data(), opt), std::runtime_error);
  EXPECT_TRUE(entries().empty());

  int w = 0, h = 0;
  EXPECT_THROW((void)gfmd::read_png_rgb(file("missing.png"), w, h), gfmd::InputError);
  gfmd::write_text_atomic(file("not.png"), "this is not a png");
  EXPECT_THROW((void)gfmd::read_png_rgb(file("not.png"), w, h), gfmd::InputError);
}

}  // namespace
