// gfmd._core's listings of the registered parts: friction laws, kinds of body, interaction
// models and indenter types, each with its purpose and keys (what Python's gfmd.friction_laws()
// and the others return).
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>
#include <vector>

#include "_core_detail.hpp"
#include "gfmd/case/config.hpp"
#include "gfmd/contact/friction_law.hpp"
#include "gfmd/contact/interaction.hpp"
#include "gfmd/elastic/body.hpp"

namespace gfmd_python {

void bind_registries(py::module_& m) {
  m.def(
      "friction_laws",
      [] {
        py::list out;
        for (const gfmd::FrictionLawType* t : gfmd::friction_law_types()) {
          py::dict d;
          d["name"] = t->name;
          d["purpose"] = t->purpose;
          std::vector<std::string> keys;
          for (const auto& k : t->keys) keys.push_back(k.name);
          d["keys"] = keys;
          d["set_valued_stick"] = t->set_valued_stick;
          d["on_device"] = t->on_device;
          out.append(d);
        }
        return out;
      },
      "The friction laws (friction.law): [{'name', 'purpose', 'keys', 'set_valued_stick', 'on_device'}]");
  m.def(
      "body_types",
      [] {
        py::list out;
        for (const gfmd::BodyType* t : gfmd::body_types()) {
          py::dict d;
          d["name"] = t->name;
          d["purpose"] = t->purpose;
          std::vector<std::string> keys;
          for (const auto& k : t->keys) keys.push_back(k.name);
          d["keys"] = keys;
          out.append(d);
        }
        return out;
      },
      "The kinds of body the [elastic] keys select (elastic/body.hpp): [{'name', 'purpose', 'keys'}]");
  m.def(
      "interaction_models",
      [] {
        py::list out;
        for (const gfmd::InteractionType* t : gfmd::interaction_types()) {
          py::dict d;
          d["name"] = t->name;
          d["purpose"] = t->purpose;
          std::vector<std::string> keys;
          for (const auto& k : t->keys) keys.push_back(k.name);
          if (t->repulsion_key) keys.emplace_back("repulsion");
          d["keys"] = keys;
          d["repulsion_key"] = t->repulsion_key;
          d["on_device"] = t->on_device;
          out.append(d);
        }
        return out;
      },
      "The interaction models (interaction.model): [{'name', 'purpose', 'keys', 'repulsion_key', "
      "'on_device'}]");
  m.def(
      "indenter_types",
      [] {
        py::list out;
        for (const gfmd::IndenterTypeInfo& t : gfmd::indenter_types()) {
          py::dict d;
          d["name"] = t.name;
          d["purpose"] = t.purpose;
          d["keys"] = t.keys;
          out.append(d);
        }
        return out;
      },
      "The indenter types a case file may give: [{'name', 'purpose', 'keys'}]");
}

}  // namespace gfmd_python
