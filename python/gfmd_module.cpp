// Python bindings: run a case from a TOML file or string and get the scalar results as a
// dict and the fields as numpy arrays (shape (ny, nx), row = y index).
//
//   import gfmd
//   r = gfmd.run("examples/hertz_sliding.toml", set=["grid.nx=256"])
//   r["summary"]["friction_coefficient"], r["fields"]["pressure"].shape
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "gfmd/config.hpp"
#include "gfmd/error.hpp"
#include "gfmd/run.hpp"
#include "gfmd/version.hpp"

namespace py = pybind11;

namespace {

py::object json_to_py(const nlohmann::json& j) { return py::module_::import("json").attr("loads")(j.dump()); }

py::array_t<double> to_array(const gfmd::Grid& g, const gfmd::RealField& f) {
  py::array_t<double> a({g.ny, g.nx});
  std::copy(f.begin(), f.end(), a.mutable_data());
  return a;
}

py::dict result(const gfmd::CaseResult& r) {
  py::dict out;
  out["summary"] = json_to_py(gfmd::summary_json(r));
  py::dict f;
  const gfmd::Grid& g = r.config.grid;
  f["topography"] = to_array(g, r.topography.h);
  f["pressure"] = to_array(g, r.fields.pressure);
  f["gap"] = to_array(g, r.fields.gap);
  f["ux"] = to_array(g, r.fields.ux);
  f["uy"] = to_array(g, r.fields.uy);
  f["uz"] = to_array(g, r.fields.uz);
  f["traction_x"] = to_array(g, r.fields.tx);
  f["traction_y"] = to_array(g, r.fields.ty);
  if (!r.principal.s1.empty()) {
    f["sigma_1"] = to_array(g, r.principal.s1);
    f["von_mises"] = to_array(g, r.principal.von_mises);
  }
  out["fields"] = f;
  return out;
}

gfmd::CaseResult solve(const gfmd::Config& cfg) {
  gfmd::CaseResult r;
  {
    py::gil_scoped_release release;
    r = gfmd::run_case(cfg);
  }
  if (!r.info.converged) throw gfmd::SolveError(r.info.status);
  return r;
}

}  // namespace

PYBIND11_MODULE(gfmd, m) {
  m.doc() = "gfmd: steady sliding contacts with full elastic coupling";
  m.attr("__version__") = gfmd::kVersion;
  py::register_exception<gfmd::InputError>(m, "InputError", PyExc_ValueError);
  py::register_exception<gfmd::SolveError>(m, "SolveError", PyExc_RuntimeError);
  m.def(
      "run",
      [](const std::string& path, const std::vector<std::string>& set, const std::string& output) {
        const gfmd::Config cfg = gfmd::load_config(path, set);
        const gfmd::CaseResult r = solve(cfg);
        if (!output.empty()) gfmd::write_outputs(r, output);
        return result(r);
      },
      py::arg("case"), py::arg("set") = std::vector<std::string>{}, py::arg("output") = "",
      "Solve a case file; returns {'summary': dict, 'fields': {name: ndarray(ny, nx)}}. "
      "`set` takes 'section.key=value' overrides; `output` also writes the usual files there.");
  m.def(
      "run_toml",
      [](const std::string& text, const std::vector<std::string>& set) {
        return result(solve(gfmd::parse_config(text, "<string>", set)));
      },
      py::arg("toml"), py::arg("set") = std::vector<std::string>{}, "Solve a case given as TOML text.");
}
