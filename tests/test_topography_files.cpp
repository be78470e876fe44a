// Topography file readers: text and CSV height maps, NetCDF (classic and HDF5) with attributes and
// coordinates, their errors.
#include <gtest/gtest.h>
#include <netcdf.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "gfmd/case/config.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/fft.hpp"
#include "gfmd/core/rng.hpp"
#include "gfmd/surface/topography.hpp"
#include "topography_helpers.hpp"

namespace {

using gfmd::Grid;
using gfmd::InputError;
using gfmd::SelfAffineParams;
using gfmd::Topography;
using topo_test::bit_identical;
using topo_test::expect_input_error;
using topo_test::paper_like;

// ------------------------------------------------------------------------------------
// File readers

class TopographyFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("gfmd_topo_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string write_text(const std::string& name, const std::string& content) const {
    const std::string p = path(name);
    std::ofstream(p, std::ios::binary) << content;
    return p;
  }

  // Writes a NetCDF file with variable `var` of dims (y, x) (or rank 3 if rank3), optional
  // global lx/ly attributes and optional coordinate variables.
  struct NcSpec {
    std::string var = "topography";
    int format = NC_CLOBBER;  // | NC_NETCDF4 for HDF5-based files
    nc_type type = NC_DOUBLE;
    double lx = 0.0, ly = 0.0;  // > 0: global attributes
    bool coords = false;        // write x, y coordinate variables with spacing dx, dy
    double dx = 0.0, dy = 0.0;
    bool rank3 = false;
    bool unlimited_y = false;  // y as the record dimension
  };
  std::string write_nc(const std::string& name, int nx, int ny, const std::vector<double>& h,
                       const NcSpec& s) const {
    const std::string p = path(name);
    int id = 0, dx_id = 0, dy_id = 0, dz_id = 0, var = 0;
    EXPECT_EQ(nc_create(p.c_str(), s.format, &id), NC_NOERR);
    EXPECT_EQ(nc_def_dim(id, "y", s.unlimited_y ? NC_UNLIMITED : static_cast<std::size_t>(ny), &dy_id),
              NC_NOERR);
    EXPECT_EQ(nc_def_dim(id, "x", static_cast<std::size_t>(nx), &dx_id), NC_NOERR);
    if (s.rank3) {
      EXPECT_EQ(nc_def_dim(id, "t", 1, &dz_id), NC_NOERR);
      const int dims[3] = {dz_id, dy_id, dx_id};
      EXPECT_EQ(nc_def_var(id, s.var.c_str(), s.type, 3, dims, &var), NC_NOERR);
    } else {
      const int dims[2] = {dy_id, dx_id};
      EXPECT_EQ(nc_def_var(id, s.var.c_str(), s.type, 2, dims, &var), NC_NOERR);
    }
    if (s.lx > 0) {
      EXPECT_EQ(nc_put_att_double(id, NC_GLOBAL, "lx", NC_DOUBLE, 1, &s.lx), NC_NOERR);
    }
    if (s.ly > 0) {
      EXPECT_EQ(nc_put_att_double(id, NC_GLOBAL, "ly", NC_DOUBLE, 1, &s.ly), NC_NOERR);
    }
    int xv = 0, yv = 0;
    if (s.coords) {
      EXPECT_EQ(nc_def_var(id, "x", NC_DOUBLE, 1, &dx_id, &xv), NC_NOERR);
      EXPECT_EQ(nc_def_var(id, "y", NC_DOUBLE, 1, &dy_id, &yv), NC_NOERR);
    }
    EXPECT_EQ(nc_enddef(id), NC_NOERR);
    const std::size_t start[2] = {0, 0},
                      count[2] = {static_cast<std::size_t>(ny), static_cast<std::size_t>(nx)};
    if (s.rank3) {
      EXPECT_EQ(nc_put_var_double(id, var, h.data()), NC_NOERR);
    } else {
      EXPECT_EQ(nc_put_vara_double(id, var, start, count, h.data()), NC_NOERR);
    }
    if (s.coords) {
      std::vector<double> x(static_cast<std::size_t>(nx)), y(static_cast<std::size_t>(ny));
      for (int i = 0; i < nx; ++i) x[i] = i * s.dx;
      for (int i = 0; i < ny; ++i) y[i] = i * s.dy;
      EXPECT_EQ(nc_put_var_double(id, xv, x.data()), NC_NOERR);
      EXPECT_EQ(nc_put_var_double(id, yv, y.data()), NC_NOERR);
    }
    EXPECT_EQ(nc_close(id), NC_NOERR);
    return p;
  }

  std::filesystem::path dir_;
};

Topography sample_surface() {
  SelfAffineParams p = paper_like(1.5);
  p.lambda_short = 0.25;
  return gfmd::make_selfaffine(Grid{32, 24, 2.0, 1.5}, p);
}

TEST_F(TopographyFile, TextRoundTrip) {
  const Topography t = sample_surface();
  std::ostringstream os;
  os.precision(17);
  os << "# a comment line\n# lx = 2.0\n#ly: 1.5\n\n";
  for (int iy = 0; iy < t.grid.ny; ++iy) {
    for (int ix = 0; ix < t.grid.nx; ++ix)
      os << (ix ? "\t" : "  ") << t.h[static_cast<std::size_t>(iy) * t.grid.nx + ix];
    os << "  \r\n";  // trailing blanks and CRLF are tolerated
  }
  const std::string p = write_text("surface.txt", os.str());
  const Topography r = gfmd::read_topography(p, 0.0, 0.0);
  EXPECT_EQ(r.kind, "file");
  EXPECT_EQ(r.grid.nx, 32);
  EXPECT_EQ(r.grid.ny, 24);
  EXPECT_EQ(r.grid.lx, 2.0);
  EXPECT_EQ(r.grid.ly, 1.5);
  EXPECT_TRUE(bit_identical(r.h, t.h));  // 17 significant digits round-trip exactly
  // Arguments win over the header.
  const Topography r2 = gfmd::read_topography(p, 4.0, 3.0);
  EXPECT_EQ(r2.grid.lx, 4.0);
  EXPECT_EQ(r2.grid.ly, 3.0);
}

TEST_F(TopographyFile, TextSizeFromArgumentsWithoutHeader) {
  const std::string p = write_text("plain.dat", "1 2 3\n4 5 6\n");
  const Topography r = gfmd::read_topography(p, 3.0, 2.0);
  EXPECT_EQ(r.grid.nx, 3);
  EXPECT_EQ(r.grid.ny, 2);
  EXPECT_EQ(r.h[5], 6.0);  // row iy = 1, ix = 2
  EXPECT_EQ(r.h[1], 2.0);
}

// CSV exports: comma, semicolon or tab separated, blanks around separators, CRLF line ends
// and one trailing separator; the size from the header lines.
TEST_F(TopographyFile, ReadsCsvWithAnySeparator) {
  for (const std::string& text : {std::string("# lx = 2\n# ly = 3\n1,2,3\n4, 5 ,6\n"),
                                  std::string("# lx = 2\n# ly = 3\n1;2;3\r\n4;5;6;\r\n"),
                                  std::string("# lx = 2\n# ly = 3\n1\t2\t3\n4\t5\t6\n")}) {
    const std::string p = write_text("map.csv", text);
    const gfmd::Topography t = gfmd::read_topography(p, 0.0, 0.0);
    ASSERT_EQ(t.grid.nx, 3) << text;
    ASSERT_EQ(t.grid.ny, 2) << text;
    EXPECT_EQ(t.grid.lx, 2.0);
    EXPECT_EQ(t.grid.ly, 3.0);
    EXPECT_EQ(t.h[4], 5.0) << text;
  }
}

// Only regular files are read: a device or a FIFO is refused at once (no endless read, no
// hang waiting for a writer).
TEST_F(TopographyFile, RefusesDevicesAndFifos) {
  expect_input_error([] { (void)gfmd::read_topography("/dev/zero", 1, 1); }, "/dev/zero",
                     "not a regular file");
  const std::string fifo = write_text("placeholder", "");
  std::filesystem::remove(fifo);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  expect_input_error([&] { (void)gfmd::read_topography(fifo, 1, 1); }, fifo, "not a regular file");
}

TEST_F(TopographyFile, TextErrors) {
  std::string p = write_text("ragged.txt", "# lx = 1\n# ly = 1\n1 2 3\n4 5\n");
  expect_input_error([&] { (void)gfmd::read_topography(p, 0, 0); }, p, "ragged rows: line 4 has 2 values");
  p = write_text("word.txt", "# lx = 1\n# ly = 1\n1 2 3\n4 five 6\n");
  expect_input_error([&] { (void)gfmd::read_topography(p, 0, 0); }, p, "line 4: non-numeric value 'five'");
  // A size with a unit, heights without: the remedy, and why indenter.unit does not apply.
  p = write_text("sizeunit.txt", "# lx = 10 um\n1 2\n3 4\n");
  expect_input_error(
      [&] { (void)gfmd::read_topography(p, 0, 0); }, p,
      "line 1: the size has a unit but the heights have none: add a header line '# unit = <unit "
      "of the heights>' (a case's indenter.unit is for files that state no unit at all");
  p = write_text("comma.txt", "1,,2\n");
  expect_input_error([&] { (void)gfmd::read_topography(p, 1, 1); }, p, "line 1: empty value 2");
  p = write_text("mixed.txt", "1;2\n3,x\n");
  expect_input_error([&] { (void)gfmd::read_topography(p, 1, 1); }, p, "line 2: non-numeric value 'x'");
  // A long unparseable line is quoted as a short excerpt, not whole.
  p = write_text("long.txt", "1 " + std::string(5000, 'a') + "\n");
  try {
    (void)gfmd::read_topography(p, 1, 1);
    ADD_FAILURE() << "a non-numeric line was accepted";
  } catch (const gfmd::InputError& e) {
    EXPECT_LT(std::string(e.what()).size(), 300u) << e.what();
    EXPECT_NE(std::string(e.what()).find("aaa..."), std::string::npos) << e.what();
  }
  p = write_text("nan.txt", "1 2\n\n3 nan\n");
  expect_input_error([&] { (void)gfmd::read_topography(p, 1, 1); }, p,
                     "1 point has no value (NaN or the file's no-data marker), the first at line 3, value 2");
  p = write_text("inf.txt", "1 -inf\n3 4\n");
  expect_input_error([&] { (void)gfmd::read_topography(p, 1, 1); }, p, "line 1: non-finite");
  p = write_text("huge.txt", "1 1e999\n");
  expect_input_error([&] { (void)gfmd::read_topography(p, 1, 1); }, p, "line 1: non-finite");
  p = write_text("nosize.txt", "1 2\n3 4\n5 6\n");
  expect_input_error([&] { (void)gfmd::read_topography(p, 0, 0); }, p, "no physical size lx");
  EXPECT_DOUBLE_EQ(gfmd::read_topography(p, 1.0, 0.0).grid.ly, 1.5);  // ly = lx ny/nx: square pixels
  p = write_text("onlyly.txt", "# ly = 3\n1 2\n3 4\n5 6\n");
  EXPECT_DOUBLE_EQ(gfmd::read_topography(p, 0, 0).grid.lx, 2.0);  // lx = ly nx/ny from the file's ly
  EXPECT_DOUBLE_EQ(gfmd::read_topography(p, 1.0, 0.0).grid.ly,
                   3.0);  // lx from the argument, ly from the file
  p = write_text("empty.txt", "");
  expect_input_error([&] { (void)gfmd::read_topography(p, 1, 1); }, p, "empty");
  p = write_text("comments.txt", "# nothing here\n\n");
  expect_input_error([&] { (void)gfmd::read_topography(p, 1, 1); }, p, "no data");
  p = write_text("badheader.txt", "# lx = -3\n1 2\n");
  expect_input_error([&] { (void)gfmd::read_topography(p, 0, 1); }, p, "line 1: invalid lx header");
  p = write_text("twice.txt", "# lx = 1\n# LX: 2\n1 2\n");
  expect_input_error([&] { (void)gfmd::read_topography(p, 0, 1); }, p, "given twice");
  p = path("does_not_exist.txt");
  expect_input_error([&] { (void)gfmd::read_topography(p, 1, 1); }, p, "no such file");
  p = path("missing.nc");
  expect_input_error([&] { (void)gfmd::read_topography(p, 1, 1); }, p, "no such file");
}

TEST_F(TopographyFile, NetcdfRoundTripWithAttributes) {
  const Topography t = sample_surface();
  std::vector<double> h(t.h.begin(), t.h.end());
  NcSpec s;
  s.lx = 2.0;
  s.ly = 1.5;
  const std::string p = write_nc("surface.nc", 32, 24, h, s);
  const Topography r = gfmd::read_topography(p, 0.0, 0.0);
  EXPECT_EQ(r.kind, "file");
  EXPECT_EQ(r.grid.nx, 32);
  EXPECT_EQ(r.grid.ny, 24);
  EXPECT_EQ(r.grid.lx, 2.0);
  EXPECT_EQ(r.grid.ly, 1.5);
  EXPECT_TRUE(bit_identical(r.h, t.h));
  const Topography r2 = gfmd::read_topography(p, 5.0, 0.0);  // argument wins for lx only
  EXPECT_EQ(r2.grid.lx, 5.0);
  EXPECT_EQ(r2.grid.ly, 1.5);
}

TEST_F(TopographyFile, NetcdfFloatHdf5WithCoordinatesAndNoExtension) {
  std::vector<double> h(6 * 4);
  for (std::size_t i = 0; i < h.size(); ++i) h[i] = 0.25 * static_cast<double>(i) - 1.0;  // exact in float
  NcSpec s;
  s.var = "heights";
  s.format = NC_CLOBBER | NC_NETCDF4;
  s.type = NC_FLOAT;
  s.coords = true;
  s.dx = 0.5;
  s.dy = 0.25;
  const std::string p = write_nc("surface_hdf5", 6, 4, h, s);  // detected by its signature
  const Topography r = gfmd::read_topography(p, 0.0, 0.0);
  EXPECT_EQ(r.grid.nx, 6);
  EXPECT_EQ(r.grid.ny, 4);
  EXPECT_DOUBLE_EQ(r.grid.lx, 3.0);
  EXPECT_DOUBLE_EQ(r.grid.ly, 1.0);
  for (std::size_t i = 0; i < h.size(); ++i) EXPECT_EQ(r.h[i], h[i]);
}

TEST_F(TopographyFile, NetcdfClassicVariantsReadAndTruncationDetected) {
  // netcdf-c reads past the end of a truncated classic file as zeros; the reader checks
  // the size implied by the header. Exercised for CDF-1, CDF-2, CDF-5, with and without
  // a record dimension, with a few bytes cut off.
  std::vector<double> h(10 * 7);
  for (std::size_t i = 0; i < h.size(); ++i) h[i] = std::sin(static_cast<double>(i));
  const int formats[] = {NC_CLOBBER, NC_CLOBBER | NC_64BIT_OFFSET, NC_CLOBBER | NC_64BIT_DATA};
  int k = 0;
  for (int fmt : formats)
    for (bool rec : {false, true}) {
      NcSpec s;
      s.format = fmt;
      s.unlimited_y = rec;
      s.coords = true;  // a second and third variable after the height map
      s.dx = 0.1;
      s.dy = 0.2;
      const std::string p = write_nc("variant" + std::to_string(k++) + ".nc", 10, 7, h, s);
      const Topography r = gfmd::read_topography(p, 0.0, 0.0);
      ASSERT_EQ(r.grid.nx, 10);
      ASSERT_EQ(r.grid.ny, 7);
      EXPECT_DOUBLE_EQ(r.grid.lx, 1.0);
      EXPECT_DOUBLE_EQ(r.grid.ly, 1.4);
      EXPECT_TRUE(bit_identical(r.h, gfmd::RealField(h.begin(), h.end())))
          << "format " << fmt << " record " << rec;
      std::filesystem::resize_file(p, std::filesystem::file_size(p) - 4);
      expect_input_error([&] { (void)gfmd::read_topography(p, 0, 0); }, p, "truncated");
    }
}

TEST_F(TopographyFile, NetcdfErrors) {
  std::vector<double> h(16 * 16, 0.5);
  NcSpec s;
  s.lx = s.ly = 1.0;
  // Truncated file (classic and HDF5-based).
  std::string p = write_nc("truncated.nc", 16, 16, h, s);
  std::filesystem::resize_file(p, std::filesystem::file_size(p) / 2);
  expect_input_error([&] { (void)gfmd::read_topography(p, 0, 0); }, p, "NetCDF");
  NcSpec s4 = s;
  s4.format = NC_CLOBBER | NC_NETCDF4;
  p = write_nc("truncated4.nc", 16, 16, h, s4);
  std::filesystem::resize_file(p, std::filesystem::file_size(p) / 2);
  expect_input_error([&] { (void)gfmd::read_topography(p, 0, 0); }, p, "NetCDF");
  // Not a NetCDF file at all.
  p = write_text("garbage.nc", "this is not netcdf\n");
  expect_input_error([&] { (void)gfmd::read_topography(p, 0, 0); }, p, "cannot read the NetCDF file");
  // Missing variable.
  NcSpec sv = s;
  sv.var = "elevation";
  p = write_nc("novar.nc", 16, 16, h, sv);
  expect_input_error([&] { (void)gfmd::read_topography(p, 0, 0); }, p, "no variable named 'topography'");
  // Wrong rank.
  NcSpec sr = s;
  sr.rank3 = true;
  p = write_nc("rank3.nc", 16, 16, h, sr);
  expect_input_error([&] { (void)gfmd::read_topography(p, 0, 0); }, p, "has 3 dimensions");
  // NaN.
  std::vector<double> hn = h;
  hn[3 * 16 + 5] = std::numeric_limits<double>::quiet_NaN();
  p = write_nc("nan.nc", 16, 16, hn, s);
  expect_input_error(
      [&] { (void)gfmd::read_topography(p, 0, 0); }, p,
      "1 point has no value (NaN or the file's no-data marker), the first at (iy, ix) = (3, 5)");
  // No size anywhere.
  p = write_nc("nosize.nc", 16, 16, h, NcSpec{});
  expect_input_error([&] { (void)gfmd::read_topography(p, 0, 0); }, p, "no physical size lx");
  EXPECT_NO_THROW((void)gfmd::read_topography(p, 1.0, 1.0));
}

}  // namespace
