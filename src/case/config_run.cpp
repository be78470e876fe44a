// The run sections of a case file: [solver], [sweep], [stress], [flow] and [output], each
// read into the Config and checked key by key (private to the config part; src/case/config.cpp
// runs them in order).
#include <algorithm>
#include <cmath>
#include <string>
#include <toml.hpp>
#include <vector>

#include "config_section.hpp"
#include "gfmd/contact/friction_law.hpp"
#include "gfmd/core/backend.hpp"
#include "gfmd/flow/flow.hpp"

namespace gfmd::config_detail {

void read_solver(Section& so, Config& c) {
  c.solver.tolerance = so.number("tolerance", 1e-8);
  c.solver.max_iterations = static_cast<int>(so.integer("max_iterations", 20000, 1, 1000000000));
  c.solver.max_outer = static_cast<int>(so.integer("max_outer", 2000, 1, 1000000000));
  c.solver.max_tangential = static_cast<int>(so.integer("max_tangential", 20000, 1, 100000000));
  c.solver.anderson = static_cast<int>(so.integer("anderson", 10, 0, 50));
  c.solver.mixing = so.number("mixing", 0.5);
  if (!(c.solver.mixing > 0 && c.solver.mixing <= 1)) so.error("mixing", "must be in (0, 1]");
  c.threads = static_cast<int>(so.integer("threads", 0, 0, kMaxThreads));
  c.backend = so.string("backend", c.backend);
  if (find_backend(c.backend) == nullptr) {
    std::string names;
    for (const auto& b : backend_names()) names += (names.empty() ? "\"" : ", \"") + b + "\"";
    so.error("backend", "must be one of " + names + " (got \"" + c.backend + "\")");
  }
  {
    const std::string planner = so.string("fft_planner", "estimate");
    if (planner == "estimate") {
      c.solver.fft_planner = Planner::Estimate;
    } else if (planner == "measure") {
      c.solver.fft_planner = Planner::Measure;
    } else {
      so.error("fft_planner", "must be \"estimate\" or \"measure\" (got \"" + planner + "\")");
    }
  }
  {
    const std::string method = so.string("viscoelastic_method", "auto");
    if (method == "auto") {
      c.solver.visco_method = ViscoMethod::Auto;
    } else if (method == "active_set") {
      c.solver.visco_method = ViscoMethod::ActiveSet;
    } else if (method == "splitting") {
      c.solver.visco_method = ViscoMethod::Splitting;
    } else {
      so.error("viscoelastic_method",
               "must be \"auto\", \"active_set\" or \"splitting\" (got \"" + method + "\")");
    }
  }
  if (!(c.solver.tolerance > 0 && c.solver.tolerance < 1)) so.error("tolerance", "must be in (0, 1)");
  so.finish();
}

void read_sweep(Section& sw, Config& c) {
  if (sw.present()) {
    c.sweep.parameter = sw.string("parameter", "");
    c.sweep.plot = sw.string("plot", c.sweep.plot);
    if (const toml::value* v = sw.raw("values")) {
      if (!v->is_array()) {
        sw.error("values", "must be an array of numbers");
      } else if (v->as_array().size() > static_cast<std::size_t>(kMaxSweepPoints)) {
        sw.error("values", "at most " + std::to_string(kMaxSweepPoints) + " values, got " +
                               std::to_string(v->as_array().size()));
      } else {
        for (const auto& e : v->as_array()) {
          if (e.is_floating() && std::isfinite(e.as_floating()))
            c.sweep.values.push_back(e.as_floating());
          else if (e.is_integer())
            c.sweep.values.push_back(static_cast<double>(e.as_integer()));
          else
            sw.error("values", "must be an array of finite numbers" + where(e));
        }
      }
    }
    const double from = sw.number("from", 0.0), to = sw.number("to", 0.0);
    const long long points = sw.integer("points", 0, 0, kMaxSweepPoints);
    const std::string spacing = sw.string("spacing", "log");
    if (points > 0) {
      if (!c.sweep.values.empty()) sw.error("points", "give either values or from/to/points, not both");
      if (spacing != "log" && spacing != "linear") sw.error("spacing", "must be \"log\" or \"linear\"");
      if (spacing == "log" && !(from > 0 && to > 0))
        sw.error("from", "log spacing needs positive from and to");
      for (long long i = 0; i < points; ++i) {
        const double t = points == 1 ? 0.0 : static_cast<double>(i) / static_cast<double>(points - 1);
        c.sweep.values.push_back(spacing == "log" ? from * std::pow(to / from, t) : from + (to - from) * t);
      }
    }
    if (c.sweep.parameter.empty() || c.sweep.parameter.find('.') == std::string::npos)
      sw.error("parameter", "name the swept key as \"section.key\", e.g. \"load.force\"");
    if (c.sweep.values.empty()) sw.error("values", "give the values (or from, to, points)");
  }
  sw.finish();
}

void read_stress(Section& st, Config& c) {
  if (const toml::value* v = st.raw("post_analysis")) {
    // false | true (= "consistent") | "paper" | "consistent" | a list of those.
    const auto kind = [&](const toml::value& e) {
      if (e.is_string() && (e.as_string() == "paper" || e.as_string() == "consistent")) {
        const std::string k = e.as_string();
        if (std::find(c.stress.post_analysis.begin(), c.stress.post_analysis.end(), k) ==
            c.stress.post_analysis.end())
          c.stress.post_analysis.push_back(k);
      } else {
        st.error("post_analysis",
                 "must be false, true, \"paper\", \"consistent\" or a list of those" + where(e));
      }
    };
    if (v->is_boolean()) {
      if (v->as_boolean()) c.stress.post_analysis = {"consistent"};
    } else if (v->is_array()) {
      for (const auto& e : v->as_array()) kind(e);
    } else {
      kind(*v);
    }
  }
  if (!c.stress.post_analysis.empty() && c.friction.law.kind != FrictionLawKind::Coulomb &&
      c.friction.coefficient > 0)
    st.error("post_analysis",
             "adds Coulomb's traction mu_c p e_s to the frictionless solution: not defined for "
             "friction.law = \"" +
                 friction_law_type(c.friction.law.kind).name +
                 "\" (the solve's own stresses are: stress.depths, fields.nc)");
  if (!c.stress.post_analysis.empty() && c.interaction.adhesive() && c.friction.coefficient > 0)
    st.error(
        "post_analysis",
        "adds Coulomb's traction mu_c p e_s to the frictionless solution: not defined with adhesion (the law "
        "reads the repulsion, the pressure is tensile in the cohesive zone; the solve's own stresses are: "
        "stress.depths, fields.nc)");
  c.stress.high_tension_fraction = st.number("high_tension_fraction", 0.9);
  c.stress.profiles = st.boolean("profiles", true);
  if (!(c.stress.high_tension_fraction > 0 && c.stress.high_tension_fraction <= 1))
    st.error("high_tension_fraction", "must be in (0, 1]");
  if (const toml::value* v = st.raw("depths")) {
    if (!v->is_array()) {
      st.error("depths", "must be an array of depths below the surface");
    } else if (v->as_array().size() > kMaxStressDepths) {
      st.error("depths", "at most " + std::to_string(kMaxStressDepths) + " depths, got " +
                             std::to_string(v->as_array().size()));
    } else {
      for (const auto& e : v->as_array()) {
        const double d = e.is_floating()  ? e.as_floating()
                         : e.is_integer() ? static_cast<double>(e.as_integer())
                                          : -1.0;
        if (!(d >= 0) || !std::isfinite(d) || d > c.elastic.depth_of_base())
          st.error("depths",
                   "each depth must be a number in [0, " +
                       std::string(c.elastic.layers.empty() ? "thickness" : "the layers' total thickness") +
                       "]" + where(e));
        else
          c.stress.depths.push_back(d);
      }
    }
  }
  st.finish();
}

void read_flow(Section& fl, Config& c) {
  if (fl.present()) {
    c.flow.enabled = fl.boolean("enabled", true);
    c.flow.tolerance = fl.number("tolerance", 1e-10);
    if (!(c.flow.tolerance > 0 && c.flow.tolerance < 1)) fl.error("tolerance", "must be in (0, 1)");
    const std::string solver = fl.string("solver", "auto");
    if (!parse_flow_solver(solver, c.flow.solver))
      fl.error("solver", "must be \"auto\", \"amg\" or \"boomeramg\", got \"" + solver + "\"");
    // "x", "y", "both", or an angle in degrees (a number, or a string holding one).
    const std::string expected = "must be \"x\", \"y\", \"both\" or an angle in degrees, got ";
    const toml::value* dv = fl.raw("direction");
    if (dv && (dv->is_floating() || dv->is_integer())) {
      const double a = fl.number("direction", 0.0);
      if (std::isfinite(a)) c.flow.angles = {a};
    } else if (dv && !dv->is_string()) {
      fl.error("direction", expected + Section::type_name(*dv));
    } else {
      const std::string dir = fl.string("direction", "both");
      c.flow.angles = parse_flow_directions(dir);
      if (c.flow.angles.empty()) fl.error("direction", expected + "\"" + dir + "\"");
    }
  }
  fl.finish();
}

void read_output(Section& out, Config& c) {
  c.output.fields = out.boolean("fields", true);
  c.output.png = out.boolean("png", true);
  c.output.analysis = out.boolean("analysis", true);
  out.finish();
}

}  // namespace gfmd::config_detail
