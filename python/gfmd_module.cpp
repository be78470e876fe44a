// Python bindings: run a case from a TOML file or string and get the scalar results as a
// dict and the fields as numpy arrays (shape (ny, nx), row = y index).
//
//   import gfmd
//   r = gfmd.run("examples/hertz_sliding.toml", set=["grid.nx=256"])
//   r["summary"]["friction_coefficient"], r["fields"]["pressure"].shape
#include <dlfcn.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <atomic>
#include <csignal>
#include <cstdlib>
#include <filesystem>

#include "gfmd/case/config.hpp"
#include "gfmd/case/outputs.hpp"
#include "gfmd/case/run.hpp"
#include "gfmd/case/run_dir.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/studies/sweep.hpp"
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

// Ctrl-C during a solve: while the solve runs without the GIL, Python's own SIGINT handler
// cannot run, so a C handler sets a flag that the solver polls; the solve then stops within
// an iteration and KeyboardInterrupt is raised. Installed only on the main thread (where
// Python receives signals), and the previous handler is restored afterwards.
std::atomic<bool> g_interrupted{false};
extern "C" void on_sigint(int) { g_interrupted.store(true); }

class SigintToFlag {
 public:
  SigintToFlag() {
    const py::module_ threading = py::module_::import("threading");
    if (!threading.attr("current_thread")().is(threading.attr("main_thread")())) return;
    g_interrupted.store(false);
    struct sigaction sa {};
    sa.sa_handler = on_sigint;
    sigemptyset(&sa.sa_mask);
    active_ = sigaction(SIGINT, &sa, &old_) == 0;
  }
  ~SigintToFlag() {
    if (active_) sigaction(SIGINT, &old_, nullptr);
  }
  SigintToFlag(const SigintToFlag&) = delete;
  SigintToFlag& operator=(const SigintToFlag&) = delete;

 private:
  struct sigaction old_ {};
  bool active_ = false;
};

[[noreturn]] void raise_keyboard_interrupt() {
  PyErr_SetNone(PyExc_KeyboardInterrupt);
  throw py::error_already_set();
}

gfmd::CaseResult solve(const gfmd::Config& cfg) {
  gfmd::CaseResult r;
  {
    SigintToFlag guard;
    gfmd::RunOptions ro;
    ro.stop_request = [] { return g_interrupted.load(); };
    try {
      py::gil_scoped_release release;
      r = gfmd::run_case(cfg, ro);
    } catch (const gfmd::Interrupted&) {
      g_interrupted.store(false);
      raise_keyboard_interrupt();
    }
  }
  if (!r.info.converged) throw gfmd::SolveError(r.info.status);
  return r;
}

// scripts/plot_maps.py beside this module: <build>/share/gfmd/scripts next to
// <build>/python/gfmd*.so (or <prefix>/share/gfmd/scripts). Empty if not found.
std::string find_plot_maps() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&find_plot_maps), &info) == 0 || info.dli_fname == nullptr) return "";
  std::error_code ec;
  const auto dir = std::filesystem::absolute(info.dli_fname, ec).parent_path();
  for (const auto& cand : {dir / ".." / "share" / "gfmd" / "scripts" / "plot_maps.py",
                           dir / "share" / "gfmd" / "scripts" / "plot_maps.py"})
    if (std::filesystem::is_regular_file(cand, ec)) return cand.lexically_normal().string();
  return "";
}

// The maps and profiles.png of a run directory (output.png), drawn as `gfmd run` draws them:
// plot_maps.py in a separate interpreter ($GFMD_PYTHON, else this one), so that matplotlib's
// backend and state in the caller's process stay untouched. A failure only warns on stderr:
// the data files are complete. The staging file of the maps (output.fields off) is removed.
// Called with the GIL released.
void draw_maps(const std::string& dir) {
  const auto staging = std::filesystem::path(dir) / gfmd::kMapsStagingFile;
  std::string problem;
  {
    py::gil_scoped_acquire acquire;
    try {
      const std::string script = find_plot_maps();
      if (script.empty()) {
        problem = "plot_maps.py not found next to the gfmd module";
      } else {
        const char* env = std::getenv("GFMD_PYTHON");
        std::string python =
            env && *env ? env : py::module_::import("sys").attr("executable").cast<std::string>();
        if (python.empty()) python = "/usr/bin/python3";
        py::list args;
        for (const auto& a : {python, script, std::string("--profiles")}) args.append(a);
        std::error_code ec;
        if (std::filesystem::is_regular_file(staging, ec)) {
          args.append("--fields");
          args.append(staging.string());
        }
        args.append("--");
        args.append(dir);
        const py::module_ subprocess = py::module_::import("subprocess");
        const py::object p =
            subprocess.attr("run")(args, py::arg("stdout") = subprocess.attr("DEVNULL"),
                                   py::arg("stderr") = subprocess.attr("PIPE"), py::arg("text") = true);
        if (const int rc = p.attr("returncode").cast<int>(); rc != 0)
          problem = python + " " + script + " failed (exit status " + std::to_string(rc) +
                    "): " + p.attr("stderr").cast<std::string>();
      }
    } catch (py::error_already_set& e) {
      problem = e.what();
    } catch (const std::exception& e) {
      problem = e.what();
    }
    if (!problem.empty()) {
      while (!problem.empty() && problem.back() == '\n') problem.pop_back();
      PySys_WriteStderr("gfmd: warning: the PNG maps of %.200s were not (all) drawn: %.1500s\n", dir.c_str(),
                        problem.c_str());
    }
  }
  std::error_code ec;
  std::filesystem::remove(staging, ec);
}

// Writes a run directory as `gfmd run -o` does: one writer (the lock), no stale files of an
// earlier run, status.json, the maps (output.png); a write error (disk full, permissions)
// raises OSError naming the file and leaves no half-written set.
void write_run(const gfmd::CaseResult& r, const std::string& dir) {
  try {
    py::gil_scoped_release release;
    const gfmd::DirectoryLock lock(dir);
    gfmd::clear_run_outputs(dir);
    gfmd::publish_outputs(r, dir, [&] {
      if (r.config.output.png) draw_maps(dir);
    });
  } catch (const gfmd::InputError&) {
    throw;
  } catch (const std::exception& e) {
    PyErr_SetString(PyExc_OSError, e.what());
    throw py::error_already_set();
  }
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
        if (!output.empty()) write_run(r, output);
        return result(r);
      },
      py::arg("case"), py::arg("set") = std::vector<std::string>{}, py::arg("output") = "",
      "Solve a case file; returns {'summary': dict, 'fields': {name: ndarray(ny, nx)}}. "
      "`set` takes 'section.key=value' overrides; `output` also writes the usual files there "
      "(with output.png the PNG maps and profiles.png, drawn by plot_maps.py in a separate Python).");
  m.def(
      "run_toml",
      [](const std::string& text, const std::vector<std::string>& set) {
        return result(solve(gfmd::parse_config(text, "<string>", set)));
      },
      py::arg("toml"), py::arg("set") = std::vector<std::string>{}, "Solve a case given as TOML text.");
}
