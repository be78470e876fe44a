// ISO 25178-72 (XML 3D surface profile, .x3p) height maps: a zip archive holding main.xml
// (the axes, the matrix dimension and the data link) and the binary heights. Every length
// in the format is in metres. Read with libzip and libxml2.
#include <libxml/parser.h>
#include <libxml/tree.h>
#include <zip.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "readers.hpp"

namespace gfmd::io_detail {

namespace {

// The largest main.xml read (a DataList of 2^22 points fits).
constexpr zip_uint64_t kMaxXmlBytes = zip_uint64_t{256} << 20;

struct ZipCloser {
  void operator()(zip_t* z) const { zip_discard(z); }
};
struct ZipFileCloser {
  void operator()(zip_file_t* f) const { zip_fclose(f); }
};
struct XmlDocFree {
  void operator()(xmlDoc* d) const { xmlFreeDoc(d); }
};

class Archive {
 public:
  explicit Archive(const std::string& path) : path_(path) {
    int err = 0;
    zip_.reset(zip_open(path.c_str(), ZIP_RDONLY | ZIP_CHECKCONS, &err));
    if (!zip_) {
      zip_error_t ze;
      zip_error_init_with_code(&ze, err);
      const std::string why = zip_error_strerror(&ze);
      zip_error_fini(&ze);
      throw InputError(path, "not a readable x3p (zip) archive: " + why);
    }
  }
  // The declared uncompressed size of a member, or -1 when absent.
  long long size(const std::string& name) const {
    zip_stat_t st;
    zip_stat_init(&st);
    if (zip_stat(zip_.get(), name.c_str(), 0, &st) != 0) return -1;
    if (!(st.valid & ZIP_STAT_SIZE))
      throw InputError(path_, "x3p member " + name + " has no size in the archive");
    return static_cast<long long>(std::min<zip_uint64_t>(st.size, zip_uint64_t{1} << 50));
  }
  // A member's bytes; `expect` is its size as checked by the caller.
  std::string read(const std::string& name, std::size_t expect) const {
    std::unique_ptr<zip_file_t, ZipFileCloser> f(zip_fopen(zip_.get(), name.c_str(), 0));
    if (!f) throw InputError(path_, "cannot open x3p member " + name + ": " + zip_strerror(zip_.get()));
    std::string out(expect, '\0');
    std::size_t got = 0;
    while (got < expect) {
      const zip_int64_t n = zip_fread(f.get(), out.data() + got, expect - got);
      if (n < 0) throw InputError(path_, "x3p member " + name + " is damaged: " + zip_file_strerror(f.get()));
      if (n == 0) break;
      got += static_cast<std::size_t>(n);
    }
    if (got != expect)
      throw InputError(path_, "x3p member " + name + " holds " + std::to_string(got) + " bytes, not the " +
                                  std::to_string(expect) + " its header declares: truncated archive?");
    char extra = 0;
    if (zip_fread(f.get(), &extra, 1) > 0)
      throw InputError(path_, "x3p member " + name + " is longer than its header declares: damaged archive");
    return out;
  }

 private:
  std::string path_;
  std::unique_ptr<zip_t, ZipCloser> zip_;
};

std::string_view local_name(const xmlNode* n) { return reinterpret_cast<const char*>(n->name); }

const xmlNode* child(const xmlNode* n, std::string_view name) {
  for (const xmlNode* c = n ? n->children : nullptr; c; c = c->next)
    if (c->type == XML_ELEMENT_NODE && local_name(c) == name) return c;
  return nullptr;
}

std::string text(const xmlNode* n) {
  std::string s;
  for (const xmlNode* c = n ? n->children : nullptr; c; c = c->next)
    if ((c->type == XML_TEXT_NODE || c->type == XML_CDATA_SECTION_NODE) && c->content)
      s += reinterpret_cast<const char*>(c->content);
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r\n") - b + 1);
}

class Xml {
 public:
  Xml(const std::string& path, const xmlNode* root) : path_(path), root_(root) {}
  [[noreturn]] void fail(const xmlNode* at, const std::string& why) const {
    const long line = at ? xmlGetLineNo(at) : 0;
    throw InputError(path_,
                     "main.xml" + (line > 0 ? " line " + std::to_string(line) : std::string()) + ": " + why);
  }
  // The element at a path of local names below the root ("Record1/Axes/CX"); required.
  const xmlNode* at(const std::vector<std::string_view>& names, bool required = true) const {
    const xmlNode* n = root_;
    std::string so_far;
    for (const auto name : names) {
      const xmlNode* c = child(n, name);
      if (!so_far.empty()) so_far += '/';
      so_far.append(name);
      if (!c) {
        if (!required) return nullptr;
        fail(n, "no <" + so_far + "> element (is this an ISO 25178-72 main.xml?)");
      }
      n = c;
    }
    return n;
  }
  double number(const xmlNode* n) const {
    const std::string s = text(n);
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    if (s.empty() || *end != '\0' || !std::isfinite(v))
      fail(n, cat("<", local_name(n), "> holds '", excerpt(s), "', not a finite number"));
    return v;
  }
  long long integer(const xmlNode* n) const {
    const double v = number(n);
    if (v != std::floor(v) || v < 0 || v > 1e12)
      fail(n, cat("<", local_name(n), "> holds '", excerpt(text(n)), "', not a count"));
    return static_cast<long long>(v);
  }

 private:
  std::string path_;
  const xmlNode* root_;
};

int type_width(char t) { return t == 'I' ? 2 : t == 'L' ? 4 : t == 'F' ? 4 : t == 'D' ? 8 : 0; }

}  // namespace

HeightMap read_x3p(const std::string& path) {
  const Archive zip(path);
  const long long xml_size = zip.size("main.xml");
  if (xml_size < 0) throw InputError(path, "the x3p archive has no main.xml");
  if (static_cast<zip_uint64_t>(xml_size) > kMaxXmlBytes)
    throw InputError(path, "main.xml declares " + std::to_string(xml_size) + " bytes; at most " +
                               std::to_string(kMaxXmlBytes) + " are read");
  const std::string xml = zip.read("main.xml", static_cast<std::size_t>(xml_size));
  // No network, no entity substitution (no external entities), libxml2's size limits kept.
  std::unique_ptr<xmlDoc, XmlDocFree> doc(
      xmlReadMemory(xml.data(), static_cast<int>(xml.size()), "main.xml", nullptr,
                    XML_PARSE_NONET | XML_PARSE_NOERROR | XML_PARSE_NOWARNING));
  if (!doc) {
    const xmlError* e = xmlGetLastError();
    std::string why = e && e->message ? e->message : "not well-formed XML";
    while (!why.empty() && why.back() == '\n') why.pop_back();
    throw InputError(path, "main.xml" +
                               (e && e->line > 0 ? " line " + std::to_string(e->line) : std::string()) +
                               ": " + excerpt(why));
  }
  const xmlNode* root = xmlDocGetRootElement(doc.get());
  if (!root || local_name(root) != "ISO5436_2")
    throw InputError(path, "main.xml: the root element is not <ISO5436_2> (not an x3p file)");
  const Xml x(path, root);

  const xmlNode* feature = x.at({"Record1", "FeatureType"});
  if (text(feature) != "SUR")
    x.fail(feature, "feature type '" + excerpt(text(feature)) +
                        "' is not SUR (an areal surface); profiles (PRF) " +
                        "and point clouds (PCL) are not height maps");
  double dx[2] = {0, 0};
  const char* axis[2] = {"CX", "CY"};
  for (int k = 0; k < 2; ++k) {
    const xmlNode* a = x.at({"Record1", "Axes", axis[k]});
    const xmlNode* type = x.at({"Record1", "Axes", axis[k], "AxisType"});
    if (text(type) != "I")
      x.fail(type, std::string("axis ") + axis[k] + " is of type '" + excerpt(text(type)) +
                       "', not I (incremental): maps with listed coordinates are not supported");
    const xmlNode* inc = child(a, "Increment");
    if (!inc) x.fail(a, std::string("axis ") + axis[k] + " has no <Increment> (the point spacing in metres)");
    dx[k] = x.number(inc);
    if (!(dx[k] > 0))
      x.fail(inc,
             std::string("axis ") + axis[k] + " has a spacing of " + num(dx[k]) + " m; it must be positive");
  }
  const xmlNode* cz = x.at({"Record1", "Axes", "CZ"});
  const xmlNode* ztype_node = child(cz, "DataType");
  const std::string ztype = ztype_node ? text(ztype_node) : "D";
  const int width = ztype.size() == 1 ? type_width(ztype[0]) : 0;
  if (width == 0) x.fail(ztype_node, "Z data type '" + excerpt(ztype) + "' is not one of I, L, F, D");
  const xmlNode* zinc = child(cz, "Increment");
  const xmlNode* zoff = child(cz, "Offset");
  const double zscale = zinc ? x.number(zinc) : 1.0;
  const double zoffset = zoff ? x.number(zoff) : 0.0;
  if (!(zscale > 0)) x.fail(zinc, "the Z increment must be positive (got " + num(zscale) + ")");

  const long long nx = x.integer(x.at({"Record3", "MatrixDimension", "SizeX"}));
  const long long ny = x.integer(x.at({"Record3", "MatrixDimension", "SizeY"}));
  const xmlNode* sz = x.at({"Record3", "MatrixDimension", "SizeZ"});
  if (x.integer(sz) != 1)
    x.fail(sz, "SizeZ is " + text(sz) + "; only single-layer maps (SizeZ = 1) are height maps");
  check_map_dims(path, nx, ny);
  const std::size_t n = static_cast<std::size_t>(nx * ny);

  HeightMap t;
  t.format = "x3p";
  t.unit = std::string(1, 'm');
  t.nx = static_cast<int>(nx);
  t.ny = static_cast<int>(ny);
  t.lx = dx[0] * static_cast<double>(nx);
  t.ly = dx[1] * static_cast<double>(ny);
  const auto note_missing = [&](std::size_t i) {
    t.h[i] = std::nan("");
    if (t.first_missing.empty())
      t.first_missing = "point (x, y) = (" + std::to_string(i % static_cast<std::size_t>(nx)) + ", " +
                        std::to_string(i / static_cast<std::size_t>(nx)) + ")";
  };

  const xmlNode* link = x.at({"Record3", "DataLink", "PointDataLink"}, false);
  const xmlNode* list = x.at({"Record3", "DataList"}, false);
  if (link) {
    const std::string member = text(link);
    const long long size = zip.size(member);
    if (size < 0) x.fail(link, "the data member '" + excerpt(member) + "' is not in the archive");
    const std::size_t want = n * static_cast<std::size_t>(width);
    if (static_cast<std::size_t>(size) != want)
      x.fail(link, "the data member " + excerpt(member) + " holds " + std::to_string(size) + " bytes; " +
                       std::to_string(nx) + " x " + std::to_string(ny) + " values of type " + ztype +
                       " need " + std::to_string(want));
    const std::string data = zip.read(member, want);
    ByteReader r(path + ":" + member, data);
    t.h.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const double raw = ztype == "I"   ? r.i16le()
                         : ztype == "L" ? r.i32le()
                         : ztype == "F" ? r.f32le()
                                        : r.f64le();
      if (std::isnan(raw)) {
        note_missing(i);
        continue;
      }
      if (std::isinf(raw)) r.fail_at(i * static_cast<std::size_t>(width), "an infinite height");
      t.h[i] = raw * zscale + zoffset;
    }
    // Integer data marks invalid points in a bit array (1 = valid, least significant bit first).
    const xmlNode* valid = x.at({"Record3", "ValidPointsLink"}, false);
    if (valid) {
      const std::string vname = text(valid);
      const long long vsize = zip.size(vname);
      const std::size_t vwant = (n + 7) / 8;
      if (vsize < 0 || static_cast<std::size_t>(vsize) != vwant)
        x.fail(valid, "the valid-points member '" + excerpt(vname) + "' is missing or not " +
                          std::to_string(vwant) + " bytes long (one bit per point)");
      const std::string bits = zip.read(vname, static_cast<std::size_t>(vsize));
      for (std::size_t i = 0; i < n; ++i)
        if (!((static_cast<unsigned char>(bits[i / 8]) >> (i % 8)) & 1)) note_missing(i);
    }
  } else if (list) {
    t.h.resize(n);
    std::size_t i = 0;
    for (const xmlNode* d = list->children; d; d = d->next) {
      if (d->type != XML_ELEMENT_NODE || local_name(d) != "Datum") continue;
      if (i >= n) x.fail(d, "the DataList holds more than SizeX * SizeY = " + std::to_string(n) + " values");
      if (text(d).empty())
        note_missing(i);
      else
        t.h[i] = x.number(d) * zscale + zoffset;
      ++i;
    }
    if (i != n)
      x.fail(list,
             "the DataList holds " + std::to_string(i) + " values; SizeX * SizeY = " + std::to_string(n));
  } else {
    x.fail(x.at({"Record3"}), "Record3 has neither a DataLink nor a DataList");
  }
  return t;
}

}  // namespace gfmd::io_detail
