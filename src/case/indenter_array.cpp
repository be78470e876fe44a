// indenter.type = "array": heights handed over by a program (Python's gfmd.solve puts them in
// RunOptions::topography); no keys, and not a type a case file may give.
#include "gfmd/core/error.hpp"
#include "indenter_types.hpp"

namespace gfmd::config_detail {

namespace {

void read(Section&, IndenterRead&) {}
// The summaries have always recorded a file indenter's (empty) keys for it: kept as they were.
void write(const IndenterConfig& in, nlohmann::json& out) { file_indenter().write(in, out); }

Topography make(const Config&, MapReport*) {
  throw InputError("indenter.type",
                   "\"array\" takes its heights from the calling program (Python: gfmd.solve); "
                   "a case file gives type = \"file\" and a path");
}

std::pair<std::string, std::string> implausible(const Config& c, const MapReport*) {
  return {"the given heights'", "the heights against the cell's size (" + cell_text(c) + ")"};
}

}  // namespace

const IndenterType& array_indenter() {
  static const IndenterType t{.name = "array",
                              .purpose = "heights given by the calling program (Python)",
                              .keys = {},
                              .in_case_files = false,
                              .rough = true,
                              .read = read,
                              .write = write,
                              .make = make,
                              .implausible = implausible};
  return t;
}

}  // namespace gfmd::config_detail
