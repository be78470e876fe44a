// gfmd._core: the compiled half of the Python package (python/gfmd/ is the other). Cases from
// TOML (file or text) or from a height array; the result stays a C++ CaseResult whose
// fields numpy sees as read-only (ny, nx) views, without copies; topographies, statistics,
// flow through the gap, and the run-directory writer of `gfmd run`. Solves release the GIL
// and stop on Ctrl-C within an iteration (KeyboardInterrupt).
#include <dlfcn.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>

#include "_core_detail.hpp"
#include "gfmd/case/config.hpp"
#include "gfmd/case/leakage.hpp"
#include "gfmd/case/outputs.hpp"
#include "gfmd/case/run.hpp"
#include "gfmd/case/run_dir.hpp"
#include "gfmd/case/run_directory.hpp"
#include "gfmd/core/backend.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/elastic/elastic.hpp"
#include "gfmd/io/height_map.hpp"
#include "gfmd/surface/spectrum.hpp"
#include "gfmd/surface/topography.hpp"
#include "gfmd/version.hpp"

namespace py = pybind11;

extern "C" void gfmd_python_on_sigint(int sig) {
  gfmd_python::g_stop_signal.store(sig);
  gfmd_python::g_interrupted.store(true);
}

namespace gfmd_python {

namespace {

// A copy of a field as a fresh (ny, nx) array.
py::array_t<double> to_array(const gfmd::Grid& g, const double* data) {
  py::array_t<double> a({g.ny, g.nx});
  std::copy(data, data + g.size(), a.mutable_data());
  return a;
}
py::array_t<double> to_array(const gfmd::Grid& g, const gfmd::RealField& f) { return to_array(g, f.data()); }

}  // namespace

// {'summary': dict, 'fields': {name: ndarray}} with every field of fields.nc (copies), as
// gfmd.run has returned it; traction_x / traction_y are there without friction too (zeros).
py::dict result(const gfmd::CaseResult& r) {
  py::dict out;
  out["summary"] = json_to_py(gfmd::summary_json(r));
  py::dict f;
  const gfmd::Grid& g = r.config.grid;
  const gfmd::FieldSet set = gfmd::result_fields(r);
  for (const auto& nf : set.fields) f[nf.name.c_str()] = to_array(g, nf.data);
  if (!f.contains("traction_x")) {
    f["traction_x"] = to_array(g, r.fields.tx);
    f["traction_y"] = to_array(g, r.fields.ty);
  }
  out["fields"] = f;
  return out;
}

namespace {

// The generators' memory check, before they allocate: the CLI's limit (memory_limit, through
// memory_shortfall), MemoryError naming the grid and the bytes needed and allowed.
void require_memory(int nx, int ny, double bytes_per_point, const std::string& what) {
  const std::string why =
      gfmd::memory_shortfall(bytes_per_point * static_cast<double>(nx) * static_cast<double>(ny),
                             "nx, ny: a " + std::to_string(nx) + " x " + std::to_string(ny) + " " + what);
  if (why.empty()) return;
  PyErr_SetString(PyExc_MemoryError, why.c_str());
  throw py::error_already_set();
}

gfmd::CaseResult solve(const gfmd::Config& cfg, gfmd::RunOptions ro = {}) {
  gfmd::CaseResult r = interruptible([&](std::function<bool()> stop) {
    ro.stop_request = std::move(stop);
    return gfmd::run_case(cfg, ro);
  });
  if (!r.info.converged) throw gfmd::SolveError(r.info.status);
  return r;
}

// A plotting helper beside this module: <package>/share/gfmd/scripts in an installed
// package, <build>/share/gfmd/scripts from <build>/python/gfmd/_core*.so. Empty if not found.
std::string find_script(const std::string& name) {
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&find_script), &info) == 0 || info.dli_fname == nullptr) return "";
  std::error_code ec;
  const auto dir = std::filesystem::absolute(info.dli_fname, ec).parent_path();
  for (const auto& cand :
       {dir / "share" / "gfmd" / "scripts" / name, dir / ".." / "share" / "gfmd" / "scripts" / name,
        dir / ".." / ".." / "share" / "gfmd" / "scripts" / name})
    if (std::filesystem::is_regular_file(cand, ec)) return cand.lexically_normal().string();
  return "";
}

}  // namespace

// Runs the plotting helper `name` (share/gfmd/scripts beside this module) with args in a
// separate interpreter ($GFMD_PYTHON, else this one), so that matplotlib's backend and state
// in the caller's process stay untouched. Returns "" or what went wrong. Needs the GIL.
std::string run_plot_script(const std::string& name, const std::vector<std::string>& arguments) {
  try {
    const std::string script = find_script(name);
    if (script.empty()) return name + " not found next to the gfmd module";
    const char* env = std::getenv("GFMD_PYTHON");
    std::string python =
        env && *env ? env : py::module_::import("sys").attr("executable").cast<std::string>();
    if (python.empty()) python = "/usr/bin/python3";
    py::list args;
    args.append(python);
    args.append(script);
    for (const auto& a : arguments) args.append(a);
    const py::module_ subprocess = py::module_::import("subprocess");
    const py::object p =
        subprocess.attr("run")(args, py::arg("stdout") = subprocess.attr("DEVNULL"),
                               py::arg("stderr") = subprocess.attr("PIPE"), py::arg("text") = true);
    const int rc = p.attr("returncode").cast<int>();
    // Stopped by the Ctrl-C (or SIGTERM) that stops the caller too (a terminal's reaches the whole
    // process group): not a drawing problem to report; the caller sees its stop request.
    if (rc != 0 && g_interrupted.load()) return "";
    if (rc != 0)
      return python + " " + script + " failed (exit status " + std::to_string(rc) +
             "): " + p.attr("stderr").cast<std::string>();
    return "";
  } catch (py::error_already_set& e) {
    if (e.matches(PyExc_KeyboardInterrupt)) throw;  // Ctrl-C while drawing: the caller stops
    return e.what();
  } catch (const std::exception& e) {
    return e.what();
  }
}

// The maps (and with --profiles profiles.png) of run directories (output.png), drawn as the
// command line draws them (plot_maps.py, run_plot_script). A failure only warns on stderr: the
// data files are complete. The staging files of the maps (output.fields off) are removed.
// Called with the GIL released.
void draw_maps(const std::vector<std::string>& dirs, const std::vector<std::string>& options) {
  if (dirs.empty()) return;
  {
    py::gil_scoped_acquire acquire;
    std::string problem = run_plot_script("plot_maps.py", gfmd::plot_maps_arguments(dirs, options));
    if (!problem.empty()) {
      while (!problem.empty() && problem.back() == '\n') problem.pop_back();
      const std::string where =
          dirs.size() == 1 ? dirs.front() : std::to_string(dirs.size()) + " directories";
      PySys_WriteStderr("gfmd: warning: the PNG maps of %.200s were not (all) drawn: %.1500s\n",
                        where.c_str(), problem.c_str());
    }
  }
  // Kept on a stop (the caller publishes the data without the maps, to draw from later).
  if (g_interrupted.load()) return;
  for (const auto& d : dirs) {
    std::error_code ec;
    std::filesystem::remove(std::filesystem::path(d) / gfmd::kMapsStagingFile, ec);
  }
}

// A run directory's maps and profiles.png.
void draw_maps(const std::string& dir) { draw_maps(std::vector<std::string>{dir}, {"--profiles"}); }

namespace {

// Writes a run directory as `gfmd run -o` does (RunDirectory: a directory gfmd made, or any
// with force; one writer; the files and maps staged and published together, the previous
// result untouched if anything fails); a write error (disk full, permissions) raises OSError
// naming the file, Ctrl-C while drawing KeyboardInterrupt.
// png: draw the maps (as output.png does; fields.nc must be written, output.fields).
void write_run(const gfmd::CaseResult& r, const std::string& dir, bool png, bool force) {
  std::optional<gfmd::RunDirectory> rd;
  // Ctrl-C while the maps are drawn (KeyboardInterrupt): the data files are whole and are
  // published without the maps (status.json says so), then the interrupt goes on.
  std::optional<py::error_already_set> stopped;
  try {
    py::gil_scoped_release release;
    rd.emplace(dir, gfmd::OutputDirOptions{force, false, {}, true, "run"});
    rd->begin();
    gfmd::publish_outputs(r, rd->staging(), [&] {
      if (!png) return;
      try {
        draw_maps(rd->staging());
      } catch (py::error_already_set& e) {
        stopped.emplace(std::move(e));
      }
    });
    if (stopped)
      rd->publish(gfmd::is_gfmd_output_name, "converged", gfmd::kFiguresNotDrawn);
    else
      rd->publish();
  } catch (py::error_already_set&) {
    if (rd) (void)rd->interrupt("interrupted while drawing the maps");
    throw;
  } catch (const gfmd::InputError&) {
    throw;
  } catch (const std::exception& e) {
    if (rd) (void)rd->fail(std::string("writing the outputs: ") + e.what());
    PyErr_SetString(PyExc_OSError, e.what());
    throw py::error_already_set();
  }
  if (stopped) {
    py::gil_scoped_acquire acquire;
    PySys_WriteStderr(
        "gfmd: interrupted while drawing the maps; the results are in %.500s/ without (all) their "
        "maps: gfmd plot draws them\n",
        dir.c_str());
    throw std::move(*stopped);
  }
}

// A solved case with the fields of fields.nc as views (FieldSet points into r: the holder is
// made once and never moved).
struct Solution {
  gfmd::CaseResult r;
  gfmd::FieldSet set;
};

std::shared_ptr<Solution> make_solution(gfmd::CaseResult&& r) {
  auto s = std::make_shared<Solution>();
  s->r = std::move(r);
  s->set = gfmd::result_fields(s->r);
  return s;
}

// A read-only (ny, nx) view of data owned by `owner` (kept alive by the array).
template <class Owner>
py::array_t<double> view(const std::shared_ptr<Owner>& owner, const gfmd::Grid& g, const double* data) {
  const py::capsule keep(new std::shared_ptr<Owner>(owner),
                         [](void* p) { delete static_cast<std::shared_ptr<Owner>*>(p); });
  py::array_t<double> a(
      {static_cast<py::ssize_t>(g.ny), static_cast<py::ssize_t>(g.nx)},
      {static_cast<py::ssize_t>(g.nx * sizeof(double)), static_cast<py::ssize_t>(sizeof(double))}, data,
      keep);
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

// (ny, nx) float64 C-contiguous heights on a grid of lx x ly; the Python layer has converted
// and checked the array (dtype, order, finiteness) and names the argument; this checks again.
gfmd::Topography heights_to_topography(const py::array_t<double, py::array::c_style>& h, double lx, double ly,
                                       const std::string& kind) {
  if (h.ndim() != 2) throw gfmd::InputError("heights", "must be a 2-D array (ny, nx)");
  gfmd::Grid g{static_cast<int>(h.shape(1)), static_cast<int>(h.shape(0)), lx, ly};
  if (g.nx < 2 || g.ny < 2) throw gfmd::InputError("heights", "needs at least 2 x 2 points");
  if (!(lx > 0 && std::isfinite(lx)) || !(ly > 0 && std::isfinite(ly)))
    throw gfmd::InputError("lx", "the cell size must be positive and finite");
  gfmd::Topography t{g, gfmd::RealField(g.size()), kind};
  const double* src = h.data();
  for (std::size_t i = 0; i < g.size(); ++i) {
    if (!std::isfinite(src[i]))
      throw gfmd::InputError("heights", "holds a non-finite value at index " + std::to_string(i));
    t.h[i] = src[i];
  }
  return t;
}

// Progress of a solve for a Python callable, at most every 0.2 s; an exception in the
// callable stops the solve and is raised afterwards.
struct ProgressRelay {
  py::object callback;
  std::chrono::steady_clock::time_point last{};
  bool failed = false;
  py::object error;
  void operator()(const gfmd::Progress& p) {
    const auto now = std::chrono::steady_clock::now();
    if (failed || now - last < std::chrono::milliseconds(200)) return;
    last = now;
    py::gil_scoped_acquire acquire;
    try {
      callback(p.iteration, p.outer, p.error);
    } catch (py::error_already_set& e) {
      failed = true;
      error = py::reinterpret_borrow<py::object>(e.value());
      g_interrupted.store(true);
    }
  }
};

// A case parsed once with its heights converted once; each solve sets the load and starts
// from the previous solve's solution (Python's gfmd.ContactSolver; gfmd.solve is one solve).
class CaseSolver {
 public:
  // The case as tables (a dict of sections, each a dict of keys: what gfmd.ContactSolver builds),
  // read by the case file's rules without passing through text; problems name "gfmd.solve".
  CaseSolver(const py::dict& tables, const py::object& heights, double lx, double ly)
      : CaseSolver(gfmd::config_from_tables(py_to_json(tables, ""), "gfmd.solve"), heights, lx, ly) {}
  // The case as TOML text (kept for scripts written against it).
  CaseSolver(const std::string& toml, const py::object& heights, double lx, double ly)
      : CaseSolver(gfmd::parse_config(toml, "<gfmd.solve>"), heights, lx, ly) {}
  CaseSolver(gfmd::Config cfg, const py::object& heights, double lx, double ly) : cfg_(std::move(cfg)) {
    if (!heights.is_none())
      topo_ = std::make_shared<const gfmd::Topography>(
          heights_to_topography(heights.cast<py::array_t<double, py::array::c_style>>(), lx, ly, "array"));
  }

  // load: "force", "pressure" or "approach". warm: start from the previous solve's solution
  // (if there is one); the new solution becomes the next solve's start.
  std::shared_ptr<Solution> solve(const std::string& load, double value, const py::object& progress,
                                  bool warm) {
    const gfmd::LoadMode mode = load == "force"      ? gfmd::LoadMode::Force
                                : load == "pressure" ? gfmd::LoadMode::Pressure
                                : load == "approach"
                                    ? gfmd::LoadMode::Approach
                                    : throw gfmd::InputError(load, "not a load: force, pressure or approach");
    gfmd::Config cfg = cfg_;
    cfg.load = {mode, value};
    gfmd::check_load(cfg);
    gfmd::RunOptions ro;
    if (topo_) ro.topography = std::make_shared<gfmd::Topography>(*topo_);  // run_case takes it over
    if (warm && last_) ro.warm_start = &last_->r.fields;
    std::shared_ptr<ProgressRelay> relay;
    if (!progress.is_none()) {
      relay = std::make_shared<ProgressRelay>();
      relay->callback = progress;
      ro.progress = [relay](const gfmd::Progress& p) { (*relay)(p); };
    }
    try {
      last_ = make_solution(gfmd_python::solve(cfg, ro));
      return last_;
    } catch (py::error_already_set&) {
      if (relay && relay->failed) {
        PyErr_SetObject(reinterpret_cast<PyObject*>(Py_TYPE(relay->error.ptr())), relay->error.ptr());
        throw py::error_already_set();
      }
      throw;
    }
  }
  void reset() { last_.reset(); }
  [[nodiscard]] bool warm() const { return last_ != nullptr; }

 private:
  gfmd::Config cfg_;                              // the load is set per solve
  std::shared_ptr<const gfmd::Topography> topo_;  // null: the case makes its own
  std::shared_ptr<Solution> last_;                // the previous solve's solution
};

py::dict flow_of(const Solution& s, const std::vector<double>& angles, double tol,
                 const std::string& solver) {
  gfmd::FlowSolver fs = gfmd::FlowSolver::Auto;
  if (!gfmd::parse_flow_solver(solver, fs)) {
    throw gfmd::InputError("solver", "must be \"auto\", \"amg\" or \"boomeramg\" (got \"" + solver + "\")");
  }
  const gfmd::LeakageResult lk = interruptible([&](const std::function<bool()>& stop) {
    return gfmd::compute_leakage(s.r.config.grid, s.r.fields.gap.data(), angles, tol, fs, stop);
  });
  py::dict out;
  out["summary"] = json_to_py(lk.json);
  std::vector<gfmd::NamedField> fields;
  gfmd::append_current_fields(lk, fields, s.r.config.length_unit);
  py::dict f;
  for (const auto& nf : fields) f[py::str(nf.name)] = to_array(s.r.config.grid, nf.data);
  out["fields"] = f;
  return out;
}

}  // namespace

}  // namespace gfmd_python

PYBIND11_MODULE(_core, m) {
  using namespace gfmd_python;
  m.doc() = "gfmd's compiled core (use the package gfmd)";
  m.attr("__version__") = gfmd::kVersion;
  m.attr("spin_count") = gfmd::kSpinCount;  // what the package sets GOMP_SPINCOUNT to (__init__.py)
  gfmd::omp_wait_setting();  // the wait setting libgomp read as this module loaded, kept for summaries
  m.attr("max_plausible_rms_gradient") = gfmd::kMaxPlausibleRmsGradient;  // warned above (_api.py)
  py::register_exception<gfmd::InputError>(m, "InputError", PyExc_ValueError);
  py::register_exception<gfmd::SolveError>(m, "SolveError", PyExc_RuntimeError);
  m.def("run_plot_script", &run_plot_script, py::arg("name"), py::arg("args"),
        "Run a plotting helper of share/gfmd/scripts in a separate interpreter, as the maps are drawn; "
        "returns '' or what went wrong.");
  m.def(
      "check_elastic",
      [](double contact_modulus, double poisson, double thickness, double substrate_contact_modulus,
         double substrate_poisson, const std::vector<std::array<double, 3>>& layers) {
        gfmd::ElasticParams e = gfmd::homogeneous_body(contact_modulus, poisson, thickness);
        e.substrate_contact_modulus = substrate_contact_modulus;
        e.substrate_poisson = substrate_poisson;
        for (const auto& l : layers) e.layers.push_back({l[0], l[1], l[2]});
        e.validate();  // a ParameterError naming the argument: InputError in Python
      },
      py::arg("contact_modulus"), py::arg("poisson"), py::arg("thickness"),
      py::arg("substrate_contact_modulus") = std::numeric_limits<double>::infinity(),
      py::arg("substrate_poisson") = 0.25, py::arg("layers") = std::vector<std::array<double, 3>>{},
      "Check an elastic body's parameters as the case files' [elastic] are checked.");
  m.def(
      "run",
      [](const std::string& path, const std::vector<std::string>& set, const std::string& output,
         bool force) {
        const gfmd::Config cfg = gfmd::load_config(path, set);
        if (!output.empty()) gfmd::check_output_directory(output, force, "run");  // before the solve
        const gfmd::CaseResult r = solve(cfg);
        if (!output.empty()) write_run(r, output, r.config.output.png, force);
        return result(r);
      },
      py::arg("case"), py::arg("set") = std::vector<std::string>{}, py::arg("output") = "",
      py::arg("force") = false,
      "Solve a case file; returns {'summary': dict, 'fields': {name: ndarray(ny, nx)}}. "
      "`set` takes 'section.key=value' overrides; `output` also writes the usual files there "
      "(with output.png the PNG maps and profiles.png, drawn by plot_maps.py in a separate Python).");
  m.def(
      "run_toml",
      [](const std::string& text, const std::vector<std::string>& set) {
        return result(solve(gfmd::parse_config(text, "<string>", set)));
      },
      py::arg("toml"), py::arg("set") = std::vector<std::string>{}, "Solve a case given as TOML text.");

  py::class_<Solution, std::shared_ptr<Solution>>(m, "Solution")
      .def_property_readonly("summary", [](const Solution& s) { return json_to_py(gfmd::summary_json(s.r)); })
      .def_property_readonly("grid",
                             [](const Solution& s) {
                               const gfmd::Grid& g = s.r.config.grid;
                               return py::make_tuple(g.nx, g.ny, g.lx, g.ly);
                             })
      .def("field_names",
           [](const Solution& s) {
             std::vector<std::string> names;
             for (const auto& f : s.set.fields) names.push_back(f.name);
             return names;
           })
      .def(
          "field",
          [](const std::shared_ptr<Solution>& s, const std::string& name) {
            for (const auto& f : s->set.fields)
              if (f.name == name) return view(s, s->r.config.grid, f.data);
            throw py::key_error("no field '" + name + "' in this result");
          },
          py::arg("name"))
      .def(
          "field_info",
          [](const Solution& s, const std::string& name) {
            for (const auto& f : s.set.fields)
              if (f.name == name) return py::make_tuple(f.long_name, f.units);
            throw py::key_error("no field '" + name + "' in this result");
          },
          py::arg("name"))
      .def(
          "save",
          [](const Solution& s, const std::string& dir, bool png, bool force) {
            if (png && !s.r.config.output.fields)
              throw gfmd::InputError("png", "the maps are drawn from fields.nc: solve with output.fields on");
            write_run(s.r, dir, png || s.r.config.output.png, force);
          },
          py::arg("dir"), py::arg("png") = false, py::arg("force") = false)
      .def("flow", &flow_of, py::arg("angles"), py::arg("tolerance") = 1e-10, py::arg("solver") = "auto")
      .def_property_readonly("toml", [](const Solution& s) { return s.r.config.to_toml(); })
      .def(
          "toml_with_heights",
          [](const Solution& s, const std::string& heights) { return s.r.config.to_toml(heights); },
          py::arg("heights"))
      .def_property_readonly("given_heights",
                             [](const Solution& s) { return s.r.config.indenter.type == "array"; });
  py::class_<CaseSolver>(m, "CaseSolver")
      .def(py::init<const py::dict&, const py::object&, double, double>(), py::arg("case"),
           py::arg("heights"), py::arg("lx"), py::arg("ly"))
      .def(py::init<const std::string&, const py::object&, double, double>(), py::arg("toml"),
           py::arg("heights"), py::arg("lx"), py::arg("ly"))
      .def("solve", &CaseSolver::solve, py::arg("load"), py::arg("value"), py::arg("progress"),
           py::arg("warm") = true)
      .def("reset", &CaseSolver::reset)
      .def_property_readonly("warm", &CaseSolver::warm);
  bind_registries(m);  // friction_laws, body_types, interaction_models, indenter_types (_core_registries.cpp)
  m.def(
      "make_indenter",
      [](const std::string& type, int nx, int ny, double lx, double ly, const py::dict& keys) {
        require_memory(nx, ny, 16.0, "topography (its heights and their copy)");
        const nlohmann::json parsed = py_to_json(keys, "indenter");
        const gfmd::Topography t = gfmd::make_indenter(type, gfmd::Grid{nx, ny, lx, ly}, parsed, ".");
        return to_array(t.grid, t.h);
      },
      py::arg("type"), py::arg("nx"), py::arg("ny"), py::arg("lx"), py::arg("ly"), py::arg("keys"));
  m.def(
      "make_hertz",
      [](int nx, int ny, double lx, double ly, double rx, double ry) {
        require_memory(nx, ny, 16.0, "Hertz topography (its heights and their copy)");
        const gfmd::Topography t = gfmd::make_hertz(gfmd::Grid{nx, ny, lx, ly}, rx, ry);
        return to_array(t.grid, t.h);
      },
      py::arg("nx"), py::arg("ny"), py::arg("lx"), py::arg("ly"), py::arg("radius_x"), py::arg("radius_y"));
  m.def(
      "make_eggcrate",
      [](int nx, int ny, double lx, double ly, double wavelength, double amplitude) {
        require_memory(nx, ny, 16.0, "egg-crate topography (its heights and their copy)");
        const gfmd::Topography t = gfmd::make_eggcrate(gfmd::Grid{nx, ny, lx, ly}, wavelength, amplitude);
        return to_array(t.grid, t.h);
      },
      py::arg("nx"), py::arg("ny"), py::arg("lx"), py::arg("ly"), py::arg("wavelength"),
      py::arg("amplitude"));
  m.def(
      "make_selfaffine",
      [](int nx, int ny, double lx, double ly, double hurst, double lambda_long, double lambda_short,
         double rms_height, double rms_gradient, double lambda_rolloff, std::uint64_t seed,
         const std::string& generator, double peklenik) {
        gfmd::SelfAffineParams p;
        p.generator = generator;
        p.peklenik = peklenik;
        p.hurst = hurst;
        p.lambda_long = lambda_long;
        p.lambda_short = lambda_short;
        p.rms_height = rms_height;
        p.rms_gradient = rms_gradient;
        p.lambda_rolloff = lambda_rolloff;
        p.seed = seed;
        require_memory(nx, ny, 40.0, "self-affine topography (its heights, spectrum, phases and their copy)");
        gfmd::Topography t;
        {
          py::gil_scoped_release release;
          t = gfmd::make_selfaffine(gfmd::Grid{nx, ny, lx, ly}, p);
        }
        return to_array(t.grid, t.h);
      },
      py::arg("nx"), py::arg("ny"), py::arg("lx"), py::arg("ly"), py::arg("hurst"), py::arg("lambda_long"),
      py::arg("lambda_short"), py::arg("rms_height"), py::arg("rms_gradient"), py::arg("lambda_rolloff"),
      py::arg("seed"), py::arg("generator") = "gfmd", py::arg("peklenik") = 1.0);
  m.def(
      "read_height_file",
      [](const std::string& path) {
        gfmd::HeightMap hm;
        {
          py::gil_scoped_release release;
          hm = gfmd::read_height_file(path);
        }
        py::dict d;
        d["h"] = to_array(gfmd::Grid{hm.nx, hm.ny, 1.0, 1.0}, hm.h);
        d["lx"] = hm.lx;
        d["ly"] = hm.ly;
        d["unit"] = hm.unit;
        d["format"] = hm.format;
        d["missing"] = hm.missing;
        d["first_missing"] = hm.first_missing;
        return d;
      },
      py::arg("path"));
  m.def(
      "load_height_map",
      [](const std::string& path, const std::string& case_unit, const std::string& file_unit, double lx,
         double ly, const std::vector<long long>& crop, const std::string& missing,
         const std::string& detrend, const std::string& periodize, int nx, int ny) {
        gfmd::MapOptions o;
        o.case_unit = case_unit;
        o.file_unit = file_unit;
        o.lx = lx;
        o.ly = ly;
        if (!crop.empty()) {
          if (crop.size() != 4) throw gfmd::InputError("crop", "must be (ix0, iy0, nx, ny)");
          for (int k = 0; k < 4; ++k) o.crop[static_cast<std::size_t>(k)] = crop[static_cast<std::size_t>(k)];
        }
        o.missing = missing;
        o.detrend = detrend;
        o.periodize = periodize;
        o.nx = nx;
        o.ny = ny;
        gfmd::MapReport rep;
        gfmd::Topography t;
        {
          py::gil_scoped_release release;
          t = gfmd::load_height_map(path, o, &rep);
        }
        return py::make_tuple(to_array(t.grid, t.h), t.grid.lx, t.grid.ly,
                              json_to_py(gfmd::map_report_json(rep)));
      },
      py::arg("path"), py::arg("case_unit"), py::arg("unit"), py::arg("lx"), py::arg("ly"), py::arg("crop"),
      py::arg("missing"), py::arg("detrend"), py::arg("periodize"), py::arg("nx"), py::arg("ny"));
  m.def(
      "statistics",
      [](const py::array_t<double, py::array::c_style>& h, double lx, double ly) {
        return json_to_py(
            gfmd::topography_stats_json(gfmd::statistics(heights_to_topography(h, lx, ly, "array"))));
      },
      py::arg("heights"), py::arg("lx"), py::arg("ly"));
  m.def(
      "isotropic_psd",
      [](const py::array_t<double, py::array::c_style>& h, double lx, double ly, int bins) {
        const gfmd::IsotropicPsd psd = gfmd::isotropic_psd(heights_to_topography(h, lx, ly, "array"), bins);
        return py::make_tuple(py::array_t<double>(static_cast<py::ssize_t>(psd.q.size()), psd.q.data()),
                              py::array_t<double>(static_cast<py::ssize_t>(psd.c.size()), psd.c.data()));
      },
      py::arg("heights"), py::arg("lx"), py::arg("ly"), py::arg("bins"),
      "The radially averaged PSD (q, C(q)) over logarithmic bins with modes, as spectrum.csv.");
  bind_studies(m);  // sweep_case, percolation_case, curve_case, ensemble_case (_core_studies.cpp)
}
