// The kinds of body under the surface: what each supplies, one file each, registered by name.
//
// A body (one column of materials: a homogeneous half-space or layer, a stack of bonded layers
// on a rigid base or on a substrate, ...) answers for one surface-traction mode exp(i q x1), in
// the frame where q points along axis 1: its surface compliance (real; or complex, with its
// materials' moduli at the mode's frequency, a viscoelastic part by the correspondence
// principle), its q = 0 compliances, and its response at a depth (stresses and displacements per
// unit traction, what the stresses need). ElasticBody (elastic.hpp) turns these into the lab-
// frame tables the solvers use (the pair's, under an elastic indenter, and a viscoelastic body's
// complex ones); subsurface.cpp and stress.cpp read the depth response.
//
// Adding a kind: one file body_<name>.cpp with its Body subclass and its BodyType (its keys, read
// and written by the case files through `keys`; describes: which ElasticParams it is; make), one
// line in body.cpp's table, tests against a limit it shares with a registered kind
// (docs/architecture.md, "Adding a body").
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "gfmd/elastic/elastic.hpp"
#include "gfmd/elastic/stress.hpp"

namespace gfmd {

// The rotated compliance of one mode |q| > 0 (the frame of elastic.hpp's PhiRotated):
// u1 = c11 t1 + i c13 t3, u2 = c22 t2, u3 = -i c13 t1 + c33 t3.
struct RotatedCompliance {
  double c11, c22, c33, c13;
};
// The same with complex entries (the materials' moduli complex).
struct ComplexRotatedCompliance {
  cplx c11, c22, c33, c13;
};

class Body {
 public:
  virtual ~Body() = default;
  // The surface compliance at |q| = q > 0.
  [[nodiscard]] virtual RotatedCompliance compliance(double q) const = 0;
  // The same with each material's E* given (`moduli`: top layer, layers top to bottom, substrate,
  // as stack_moduli orders them; complex for a viscoelastic part), nu constant.
  [[nodiscard]] virtual ComplexRotatedCompliance compliance(double q,
                                                            const std::vector<cplx>& moduli) const = 0;
  // The q = 0 compliances (normal, in-plane): zero where the mean displacement is pinned at the
  // surface (a half-space or a substrate).
  [[nodiscard]] virtual std::pair<double, double> mean_compliances() const = 0;
  // The response at `depth` below the surface to one traction mode (stress.hpp's ModeResponse;
  // the real coupled body whatever coupling says); at depth 0 the displacement is compliance(q).
  [[nodiscard]] virtual ModeResponse mode_response(double q, double depth) const = 0;
  // The same with each material's E* given (as compliance's overload); at q = 0 the elastic one.
  [[nodiscard]] virtual ModeResponse mode_response(double q, double depth,
                                                   const std::vector<cplx>& moduli) const = 0;
};

// A number in each table of a Tables key (e.g. a layer's thickness): required, or its default.
struct BodyTableField {
  std::string name;
  bool required = true;
  double default_value = 0.0;
};

// A key of [elastic] (and of [indenter_body]) that belongs to a kind of body, beside the keys
// every body has (contact_modulus, poisson, thickness, coupling): the case file's reader and
// writer (case/config) take them from here, and gfmd.body_types() lists them.
struct BodyKey {
  enum class Kind {
    Number,       // a number; `member` holds it
    NumberOrInf,  // a number or "inf"
    Tables,       // an array of tables of numbers (`fields`); set_rows and rows move them in and out
  };
  std::string name;  // elastic.<name>
  Kind kind = Kind::Number;
  double ElasticParams::*member = nullptr;  // Number, NumberOrInf
  double default_value = 0.0;
  std::string doc;
  // Given alone it is refused: it belongs with this other key of the kind ("" = none).
  std::string needs;
  // Whether a body's value is written back (summary.json's input, config_out): e.g. the
  // substrate's keys only on a substrate. Always where null.
  bool (*written)(const ElasticParams& el) = nullptr;
  // Tables: the fields of each table, in the order of a row's values; the rows read (each checked
  // by the case reader: numbers, the required fields given, no other keys) go to set_rows, and
  // rows gives them back for writing. A new key of this shape needs no reader of its own.
  std::vector<BodyTableField> fields;
  void (*set_rows)(ElasticParams& el, const std::vector<std::vector<double>>& rows) = nullptr;
  std::vector<std::vector<double>> (*rows)(const ElasticParams& el) = nullptr;
};

struct BodyType {
  std::string name;           // "homogeneous", "layered"
  std::string purpose;        // one line (docs, gfmd.body_types())
  std::vector<BodyKey> keys;  // its own keys (read and written by case/config)
  // Whether these [elastic] parameters describe a body of this kind (exactly one kind does).
  bool (*describes)(const ElasticParams& el) = nullptr;
  std::unique_ptr<Body> (*make)(const ElasticParams& el) = nullptr;
};

const BodyType& homogeneous_body_type();
const BodyType& layered_body_type();

// Every registered kind, in the order the docs list them.
const std::vector<const BodyType*>& body_types();
// The keys of every kind, each once, in the table's order.
std::vector<const BodyKey*> body_keys();
// The kind that describes `el` (throws ParameterError if none does).
const BodyType& body_type_of(const ElasticParams& el);
// The body `el` describes (validated first: ParameterError naming the key).
std::unique_ptr<Body> make_body(const ElasticParams& el);

}  // namespace gfmd
