// gfmd._core's shared pieces (python/_core.cpp, python/_core_studies.cpp): Ctrl-C as a stop
// request while a solve runs without the GIL, JSON handed to Python, the plotting helpers.
#pragma once

#include <pybind11/pybind11.h>
#include <signal.h>

#include <atomic>
#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "gfmd/case/result.hpp"
#include "gfmd/core/error.hpp"

// The SIGINT (and SIGTERM) handler SigintToFlag installs (python/_core.cpp): sets g_interrupted.
extern "C" void gfmd_python_on_sigint(int);

namespace gfmd_python {

namespace py = pybind11;

inline py::object json_to_py(const nlohmann::json& j) {
  return py::module_::import("json").attr("loads")(j.dump());
}

// A Python value of plain types (dict with str keys, list, tuple, bool, int, float, str; what
// the gfmd package builds a case from) as JSON, floats kept exactly (inf too); `key` names it in
// errors. Anything else is refused naming its key.
inline nlohmann::json py_to_json(const py::handle& v, const std::string& key, int depth = 0) {
  if (depth > 64) throw gfmd::InputError(key, "nested too deeply");
  if (py::isinstance<py::bool_>(v)) return v.cast<bool>();
  if (py::isinstance<py::int_>(v)) {
    try {
      return v.cast<std::int64_t>();
    } catch (const py::cast_error&) {
      throw gfmd::InputError(key, "an integer beyond the 64-bit range");
    }
  }
  if (py::isinstance<py::float_>(v)) return v.cast<double>();
  if (py::isinstance<py::str>(v)) return v.cast<std::string>();
  if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v)) {
    nlohmann::json a = nlohmann::json::array();
    std::size_t i = 0;
    for (const py::handle e : v) a.push_back(py_to_json(e, key + "[" + std::to_string(i++) + "]", depth + 1));
    return a;
  }
  if (py::isinstance<py::dict>(v)) {
    nlohmann::json o = nlohmann::json::object();
    for (const auto& [k, e] : v.cast<py::dict>()) {
      if (!py::isinstance<py::str>(k)) throw gfmd::InputError(key, "a table's keys must be strings");
      const std::string name = k.cast<std::string>();
      o[name] = py_to_json(e, key.empty() ? name : key + "." + name, depth + 1);
    }
    return o;
  }
  throw gfmd::InputError(key, "unsupported value " + py::repr(v).cast<std::string>());
}

// Ctrl-C during a solve: while the solve runs without the GIL, Python's own SIGINT handler
// cannot run, so a C handler sets a flag that the solver polls; the solve then stops within
// an iteration and KeyboardInterrupt is raised. SIGTERM is taken the same way where the
// program has a Python handler for it (a study driver stops cleanly on it); otherwise it keeps
// its default (the process ends). Installed only on the main thread (where Python receives
// signals), and the previous handlers are restored afterwards.
inline std::atomic<bool> g_interrupted{false};
inline std::atomic<int> g_stop_signal{0};  // the signal that set g_interrupted (0: none)

class SigintToFlag {
 public:
  SigintToFlag() {
    const py::module_ threading = py::module_::import("threading");
    if (!threading.attr("current_thread")().is(threading.attr("main_thread")())) return;
    g_interrupted.store(false);
    g_stop_signal.store(0);
    const py::module_ signal = py::module_::import("signal");
    const bool python_term = PyCallable_Check(signal.attr("getsignal")(SIGTERM).ptr()) != 0;
    struct sigaction sa {};
    sa.sa_handler = gfmd_python_on_sigint;
    sigemptyset(&sa.sa_mask);
    int_ = sigaction(SIGINT, &sa, &old_int_) == 0;
    term_ = python_term && sigaction(SIGTERM, &sa, &old_term_) == 0;
  }
  ~SigintToFlag() {
    if (int_) sigaction(SIGINT, &old_int_, nullptr);
    if (term_) sigaction(SIGTERM, &old_term_, nullptr);
  }
  SigintToFlag(const SigintToFlag&) = delete;
  SigintToFlag& operator=(const SigintToFlag&) = delete;

 private:
  struct sigaction old_int_ {};
  struct sigaction old_term_ {};
  bool int_ = false, term_ = false;
};

// After a call stopped by a stop request (its SigintToFlag gone): the signal that asked for it
// goes to Python's handler for it (PyErr_SetInterruptEx; a study driver's handler records it,
// the default SIGINT handler raises KeyboardInterrupt); KeyboardInterrupt unless that handler
// raised something itself.
[[noreturn]] inline void raise_keyboard_interrupt() {
  g_interrupted.store(false);
  if (const int sig = g_stop_signal.exchange(0); sig != 0) {
    PyErr_SetInterruptEx(sig);
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
  }
  PyErr_SetNone(PyExc_KeyboardInterrupt);
  throw py::error_already_set();
}

// After a call that finished although a stop signal came (after its last look at the stop
// request; its SigintToFlag gone): the signal goes to Python's handler, which runs at the next
// check, as if it had come just after the call (a study driver must not lose it).
inline void pass_on_late_signal() {
  g_interrupted.store(false);
  if (const int sig = g_stop_signal.exchange(0); sig != 0) PyErr_SetInterruptEx(sig);
}

// Runs f(stop) with the GIL released and Ctrl-C as its stop request (solves, flows, studies);
// gfmd::Interrupted becomes KeyboardInterrupt. f must not touch Python objects.
template <class F>
auto interruptible(F&& f) {
  std::optional<SigintToFlag> guard(std::in_place);
  try {
    auto result = [&] {
      py::gil_scoped_release release;
      return f(std::function<bool()>([] { return g_interrupted.load(); }));
    }();
    guard.reset();
    pass_on_late_signal();
    return result;
  } catch (const gfmd::Interrupted&) {
    guard.reset();
    raise_keyboard_interrupt();
  } catch (...) {  // another error (bad input, a solve that failed): raised, the signal kept too
    guard.reset();
    pass_on_late_signal();
    throw;
  }
}

// Runs the plotting helper `name` (share/gfmd/scripts beside the module) with args in a
// separate interpreter; "" or what went wrong. Needs the GIL (python/_core.cpp).
std::string run_plot_script(const std::string& name, const std::vector<std::string>& arguments);

// Draws the maps of run directories as the command line does (plot_maps.py with `options`, e.g.
// --profiles); a failure warns. Called with the GIL released (python/_core.cpp).
void draw_maps(const std::vector<std::string>& dirs, const std::vector<std::string>& options);
// {'summary': dict, 'fields': {name: ndarray}} of a solved case (copies of every field).
py::dict result(const gfmd::CaseResult& r);

// Registers sweep_case, percolation_case, curve_case and ensemble_case (python/_core_studies.cpp).
void bind_studies(py::module_& m);
// friction_laws, body_types, interaction_models, indenter_types (python/_core_registries.cpp).
void bind_registries(py::module_& m);

}  // namespace gfmd_python
