// PNG maps. See include/gfmd/io/png.hpp.
#include "gfmd/io/png.hpp"

#include <png.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <system_error>

#include "gfmd/core/error.hpp"
#include "gfmd/core/files.hpp"

namespace gfmd {

namespace {

// ---------------------------------------------------------------------------------------------
// Colormaps: control points evenly spaced in [0, 1], linear interpolation in sRGB.
// Hand-picked approximations of the well-known maps.

using Rgb = std::array<unsigned char, 3>;

constexpr Rgb kNanGrey = {128, 128, 128};

constexpr Rgb kViridis[] = {{68, 1, 84},    {71, 45, 123}, {59, 82, 139},  {44, 114, 142}, {33, 145, 140},
                            {40, 174, 128}, {94, 201, 98}, {170, 220, 50}, {253, 231, 37}};
constexpr Rgb kInferno[] = {{0, 0, 4},     {31, 12, 72},   {85, 15, 109},  {136, 34, 106}, {186, 54, 85},
                            {227, 89, 51}, {249, 140, 10}, {249, 201, 50}, {252, 255, 164}};
constexpr Rgb kCoolwarm[] = {{59, 76, 192},   {98, 130, 234},  {141, 176, 254},
                             {184, 208, 249}, {221, 221, 221}, {245, 196, 173},
                             {244, 154, 123}, {222, 96, 77},   {180, 4, 38}};
constexpr Rgb kGray[] = {{0, 0, 0}, {255, 255, 255}};

struct Colormap {
  const Rgb* points;
  int n;
  Rgb outline;  // contrasting colour for mask outlines
};

Colormap find_colormap(const std::string& name, const std::string& where) {
  if (name == "viridis") return {kViridis, static_cast<int>(std::size(kViridis)), {255, 0, 255}};
  if (name == "inferno") return {kInferno, static_cast<int>(std::size(kInferno)), {0, 255, 255}};
  if (name == "coolwarm") return {kCoolwarm, static_cast<int>(std::size(kCoolwarm)), {0, 0, 0}};
  if (name == "gray" || name == "grey") return {kGray, static_cast<int>(std::size(kGray)), {255, 0, 0}};
  throw InputError(where, "unknown colormap '" + name + "' (expected viridis, inferno, coolwarm or gray)");
}

Rgb cmap_color(const Colormap& cm, double t) {
  if (std::isnan(t)) return kNanGrey;
  t = std::clamp(t, 0.0, 1.0);
  const double pos = t * (cm.n - 1);
  const int i = std::min(static_cast<int>(pos), cm.n - 2);
  const double f = pos - i;
  Rgb c{};
  for (int k = 0; k < 3; ++k) {
    const double a = cm.points[i][k], b = cm.points[i + 1][k];
    c[k] = static_cast<unsigned char>(std::lround(a + f * (b - a)));
  }
  return c;
}

// ---------------------------------------------------------------------------------------------
// Tiny 5x7 bitmap font: 7 rows of 5 columns, '#' = ink.

struct Glyph {
  char c;
  const char* bits;
};

// clang-format off
constexpr Glyph kFont[] = {
  {'0', ".###." "#...#" "#..##" "#.#.#" "##..#" "#...#" ".###."},
  {'1', "..#.." ".##.." "..#.." "..#.." "..#.." "..#.." ".###."},
  {'2', ".###." "#...#" "....#" "...#." "..#.." ".#..." "#####"},
  {'3', "#####" "...#." "..#.." "...#." "....#" "#...#" ".###."},
  {'4', "...#." "..##." ".#.#." "#..#." "#####" "...#." "...#."},
  {'5', "#####" "#...." "####." "....#" "....#" "#...#" ".###."},
  {'6', "..##." ".#..." "#...." "####." "#...#" "#...#" ".###."},
  {'7', "#####" "....#" "...#." "..#.." ".#..." ".#..." ".#..."},
  {'8', ".###." "#...#" "#...#" ".###." "#...#" "#...#" ".###."},
  {'9', ".###." "#...#" "#...#" ".####" "....#" "...#." ".##.."},
  {'.', "....." "....." "....." "....." "....." ".##.." ".##.."},
  {'-', "....." "....." "....." "#####" "....." "....." "....."},
  {'+', "....." "..#.." "..#.." "#####" "..#.." "..#.." "....."},
  {':', "....." ".##.." ".##.." "....." ".##.." ".##.." "....."},
  {'=', "....." "....." "#####" "....." "#####" "....." "....."},
  {'_', "....." "....." "....." "....." "....." "....." "#####"},
  {'(', "...#." "..#.." ".#..." ".#..." ".#..." "..#.." "...#."},
  {')', ".#..." "..#.." "...#." "...#." "...#." "..#.." ".#..."},
  {'/', "....." "....#" "...#." "..#.." ".#..." "#...." "....."},
  {',', "....." "....." "....." "....." ".##.." "..#.." ".#..."},
  {'a', "....." "....." ".###." "....#" ".####" "#...#" ".####"},
  {'b', "#...." "#...." "#.##." "##..#" "#...#" "#...#" "####."},
  {'c', "....." "....." ".###." "#...." "#...." "#...#" ".###."},
  {'d', "....#" "....#" ".##.#" "#..##" "#...#" "#...#" ".####"},
  {'e', "....." "....." ".###." "#...#" "#####" "#...." ".###."},
  {'f', "..##." ".#..#" ".#..." "###.." ".#..." ".#..." ".#..."},
  {'g', "....." ".####" "#...#" "#...#" ".####" "....#" ".###."},
  {'h', "#...." "#...." "#.##." "##..#" "#...#" "#...#" "#...#"},
  {'i', "..#.." "....." ".##.." "..#.." "..#.." "..#.." ".###."},
  {'j', "...#." "....." "..##." "...#." "...#." "#..#." ".##.."},
  {'k', "#...." "#...." "#..#." "#.#.." "##..." "#.#.." "#..#."},
  {'l', ".##.." "..#.." "..#.." "..#.." "..#.." "..#.." ".###."},
  {'m', "....." "....." "##.#." "#.#.#" "#.#.#" "#...#" "#...#"},
  {'n', "....." "....." "#.##." "##..#" "#...#" "#...#" "#...#"},
  {'o', "....." "....." ".###." "#...#" "#...#" "#...#" ".###."},
  {'p', "....." "....." "####." "#...#" "####." "#...." "#...."},
  {'q', "....." "....." ".##.#" "#..##" ".####" "....#" "....#"},
  {'r', "....." "....." "#.##." "##..#" "#...." "#...." "#...."},
  {'s', "....." "....." ".###." "#...." ".###." "....#" "####."},
  {'t', ".#..." ".#..." "###.." ".#..." ".#..." ".#..#" "..##."},
  {'u', "....." "....." "#...#" "#...#" "#...#" "#..##" ".##.#"},
  {'v', "....." "....." "#...#" "#...#" "#...#" ".#.#." "..#.."},
  {'w', "....." "....." "#...#" "#...#" "#.#.#" "#.#.#" ".#.#."},
  {'x', "....." "....." "#...#" ".#.#." "..#.." ".#.#." "#...#"},
  {'y', "....." "....." "#...#" "#...#" ".####" "....#" ".###."},
  {'z', "....." "....." "#####" "...#." "..#.." ".#..." "#####"},
};
// clang-format on

constexpr int kGlyphW = 5, kGlyphH = 7;

constexpr bool font_is_well_formed() {
  for (const Glyph& g : kFont) {
    int n = 0;
    for (const char* p = g.bits; *p != '\0'; ++p, ++n)
      if (*p != '#' && *p != '.') return false;
    if (n != kGlyphW * kGlyphH) return false;
  }
  return true;
}
static_assert(font_is_well_formed(), "every glyph must have 7 rows of 5 '#'/'.' characters");

const char* glyph_bits(char c) {
  if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  for (const Glyph& g : kFont)
    if (g.c == c) return g.bits;
  return nullptr;  // space and unknown characters: blank
}

struct Canvas {
  int w = 0, h = 0;
  std::vector<unsigned char> px;  // RGB, top row first

  Canvas(int width, int height)
      : w(width), h(height), px(static_cast<std::size_t>(width) * height * 3, 255) {}

  void set(int x, int y, const Rgb& c) {
    if (x < 0 || y < 0 || x >= w || y >= h) return;
    unsigned char* p = &px[(static_cast<std::size_t>(y) * w + x) * 3];
    p[0] = c[0];
    p[1] = c[1];
    p[2] = c[2];
  }
  void fill(int x0, int y0, int ww, int hh, const Rgb& c) {
    for (int y = y0; y < y0 + hh; ++y)
      for (int x = x0; x < x0 + ww; ++x) set(x, y, c);
  }
};

// Glyph advance is 6*k pixels; the ink of a string is advance*len - k wide and 7*k high.
int text_width(const std::string& s, int k) {
  return s.empty() ? 0 : static_cast<int>(s.size()) * (kGlyphW + 1) * k - k;
}

void draw_text(Canvas& cv, int x, int y, const std::string& s, int k, const Rgb& color) {
  for (std::size_t i = 0; i < s.size(); ++i) {
    const char* bits = glyph_bits(s[i]);
    if (bits == nullptr) continue;
    const int gx = x + static_cast<int>(i) * (kGlyphW + 1) * k;
    for (int r = 0; r < kGlyphH; ++r)
      for (int c = 0; c < kGlyphW; ++c)
        if (bits[r * kGlyphW + c] == '#') cv.fill(gx + c * k, y + r * k, k, k, color);
  }
}

std::string format_label(double v) {
  if (std::isnan(v)) return "nan";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

}  // namespace

std::array<unsigned char, 3> colormap_rgb(const std::string& name, double t) {
  return cmap_color(find_colormap(name, "colormap"), t);
}

void write_png_map(const std::string& path, const Grid& grid, const double* field, const PngOptions& opt) {
  const Colormap cm = find_colormap(opt.colormap, path);
  if (grid.nx <= 0 || grid.ny <= 0) throw InputError(path, "grid must have nx, ny > 0");
  if (field == nullptr) throw InputError(path, "no field data");
  if (opt.scale < 0) throw InputError(path, "scale must be >= 0");
  const int nx = grid.nx, ny = grid.ny;
  const std::size_t n = grid.size();

  // Pixels per cell (s) and cells per block (f, downsampling).
  const int long_side = std::max(nx, ny);
  int f = 1, s = opt.scale;
  if (s == 0) {
    s = 1;
    if (long_side > 1024)
      f = (long_side + 1023) / 1024;
    else if (long_side < 256)
      s = (256 + long_side - 1) / long_side;
  }
  const int cw = (nx + f - 1) / f, ch = (ny + f - 1) / f;  // cells of the picture
  constexpr long long kMaxSide = 30000;
  if (static_cast<long long>(cw) * s > kMaxSide || static_cast<long long>(ch) * s > kMaxSide)
    throw InputError(path, "image would be larger than " + std::to_string(kMaxSide) + " pixels on a side");
  const int mw = cw * s, mh = ch * s;

  // Block averages (NaNs ignored; all-NaN blocks stay NaN) and mask majority.
  std::vector<double> cell(static_cast<std::size_t>(cw) * ch);
  std::vector<unsigned char> cmask(opt.mask != nullptr ? cell.size() : 0);
  for (int by = 0; by < ch; ++by)
    for (int bx = 0; bx < cw; ++bx) {
      double sum = 0.0;
      long cnt = 0, tot = 0, msk = 0;
      for (int iy = by * f; iy < std::min(ny, (by + 1) * f); ++iy)
        for (int ix = bx * f; ix < std::min(nx, (bx + 1) * f); ++ix) {
          const std::size_t i = static_cast<std::size_t>(iy) * nx + ix;
          ++tot;
          if (!std::isnan(field[i])) {
            sum += field[i];
            ++cnt;
          }
          if (opt.mask != nullptr && opt.mask[i] != 0) ++msk;
        }
      const std::size_t c = static_cast<std::size_t>(by) * cw + bx;
      cell[c] = cnt > 0 ? sum / static_cast<double>(cnt) : std::numeric_limits<double>::quiet_NaN();
      if (!cmask.empty()) cmask[c] = (2 * msk >= tot) ? 1 : 0;
    }

  // Colour limits.
  double dmin = std::numeric_limits<double>::infinity(), dmax = -dmin;
  for (std::size_t i = 0; i < n; ++i)
    if (std::isfinite(field[i])) {
      dmin = std::min(dmin, field[i]);
      dmax = std::max(dmax, field[i]);
    }
  const bool have_data = dmin <= dmax;
  if (!have_data) dmin = dmax = std::numeric_limits<double>::quiet_NaN();
  const bool given_lo = !std::isnan(opt.vmin), given_hi = !std::isnan(opt.vmax);
  if (given_lo && !std::isfinite(opt.vmin)) throw InputError(path, "vmin must be finite or NaN");
  if (given_hi && !std::isfinite(opt.vmax)) throw InputError(path, "vmax must be finite or NaN");
  if (given_lo && given_hi && opt.vmin > opt.vmax) throw InputError(path, "vmin > vmax");
  double lo = given_lo ? opt.vmin : dmin, hi = given_hi ? opt.vmax : dmax;
  if (std::isnan(lo)) lo = hi;  // no data: fall back to the one given limit, if any
  if (std::isnan(hi)) hi = lo;
  if (lo > hi) {  // only one limit was given and the data lie beyond it
    if (given_lo)
      hi = lo;
    else
      lo = hi;
  }
  if (opt.symmetric && !std::isnan(lo)) {
    const double m = std::max(std::abs(lo), std::abs(hi));
    lo = -m;
    hi = m;
  }
  auto to_t = [&](double v) -> double {
    if (std::isnan(v)) return v;
    if (std::isnan(lo)) return v > 0 ? 1.0 : 0.0;  // only infinities can get here
    if (hi > lo) return (v - lo) / (hi - lo);
    return v < lo ? 0.0 : (v > lo ? 1.0 : 0.5);
  };

  // Layout: [title band] over [map | gap | bar | gap | labels].
  const int k = std::clamp(std::max(mw, mh) / 300, 1, 3);  // text scale
  const int gh = kGlyphH * k, pad = 4 * k;
  const int title_h = opt.title.empty() ? 0 : gh + 2 * pad;
  const std::string lab_hi = format_label(hi), lab_lo = format_label(lo);
  const int area_h = opt.colorbar ? std::max(mh, 2 * gh + 3 * pad) : mh;
  int width = mw;
  int bar_x = 0, bar_w = 0, label_x = 0;
  if (opt.colorbar) {
    bar_x = mw + 2 * pad + 1;
    bar_w = 3 * kGlyphW * k;
    label_x = bar_x + bar_w + 1 + pad;
    width = label_x + std::max(text_width(lab_hi, k), text_width(lab_lo, k)) + pad;
  }
  if (!opt.title.empty()) width = std::max(width, text_width(opt.title, k) + 2 * pad);
  const int height = title_h + area_h;

  Canvas cv(width, height);
  const Rgb black = {0, 0, 0};

  // Map.
  for (int py = 0; py < mh; ++py) {
    const int cy = ch - 1 - py / s;
    for (int px = 0; px < mw; ++px) {
      const int cx = px / s;
      const std::size_t c = static_cast<std::size_t>(cy) * cw + cx;
      Rgb col = cmap_color(cm, to_t(cell[c]));
      if (!cmask.empty() && cmask[c] != 0) {
        // Outline: a masked pixel with a 4-neighbour (inside the map) in an unmasked cell.
        auto unmasked = [&](int qx, int qy) {
          if (qx < 0 || qy < 0 || qx >= mw || qy >= mh) return false;
          return cmask[static_cast<std::size_t>(ch - 1 - qy / s) * cw + qx / s] == 0;
        };
        if (unmasked(px - 1, py) || unmasked(px + 1, py) || unmasked(px, py - 1) || unmasked(px, py + 1))
          col = cm.outline;
      }
      cv.set(px, title_h + py, col);
    }
  }

  // Colour bar: frame, gradient (top row = top colour), labels.
  if (opt.colorbar) {
    const int bar_h = area_h - 2;
    cv.fill(bar_x - 1, title_h, bar_w + 2, area_h, black);
    for (int r = 0; r < bar_h; ++r) {
      const double t = bar_h > 1 ? 1.0 - static_cast<double>(r) / (bar_h - 1) : 0.5;
      cv.fill(bar_x, title_h + 1 + r, bar_w, 1, cmap_color(cm, t));
    }
    draw_text(cv, label_x, title_h, lab_hi, k, black);
    draw_text(cv, label_x, title_h + area_h - gh, lab_lo, k, black);
  }
  if (!opt.title.empty()) draw_text(cv, pad, pad, opt.title, k, black);

  // Encode in memory, then write atomically.
  png_image img;
  std::memset(&img, 0, sizeof img);
  img.version = PNG_IMAGE_VERSION;
  img.width = static_cast<png_uint_32>(width);
  img.height = static_cast<png_uint_32>(height);
  img.format = PNG_FORMAT_RGB;
  png_alloc_size_t size = 0;
  if (!png_image_write_to_memory(&img, nullptr, &size, 0, cv.px.data(), 0, nullptr)) {
    const std::string msg = img.message;
    png_image_free(&img);
    throw std::runtime_error(path + ": cannot encode PNG: " + msg);
  }
  std::vector<unsigned char> buf(size);
  if (!png_image_write_to_memory(&img, buf.data(), &size, 0, cv.px.data(), 0, nullptr)) {
    const std::string msg = img.message;
    png_image_free(&img);
    throw std::runtime_error(path + ": cannot encode PNG: " + msg);
  }
  png_image_free(&img);
  write_bytes_atomic(path, buf.data(), size);
}

std::vector<unsigned char> read_png_rgb(const std::string& path, int& width, int& height) {
  png_image img;
  std::memset(&img, 0, sizeof img);
  img.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&img, path.c_str())) {
    const std::string msg = img.message;
    png_image_free(&img);
    throw InputError(path, "cannot read PNG: " + msg);
  }
  img.format = PNG_FORMAT_RGB;
  std::vector<unsigned char> px(PNG_IMAGE_SIZE(img));
  if (!png_image_finish_read(&img, nullptr, px.data(), 0, nullptr)) {
    const std::string msg = img.message;
    png_image_free(&img);
    throw InputError(path, "cannot decode PNG: " + msg);
  }
  width = static_cast<int>(img.width);
  height = static_cast<int>(img.height);
  png_image_free(&img);
  return px;
}

}  // namespace gfmd
