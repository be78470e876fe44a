// The body kinds' table: one line per kind (body_<name>.cpp). See include/gfmd/elastic/body.hpp.
#include "gfmd/elastic/body.hpp"

#include "gfmd/core/error.hpp"

namespace gfmd {

const std::vector<const BodyType*>& body_types() {
  static const std::vector<const BodyType*> table = {
      &homogeneous_body_type(),  //
      &layered_body_type(),      //
  };
  return table;
}

std::vector<const BodyKey*> body_keys() {
  std::vector<const BodyKey*> out;
  for (const BodyType* t : body_types())
    for (const BodyKey& k : t->keys) {
      bool seen = false;
      for (const BodyKey* o : out) seen = seen || o->name == k.name;
      if (!seen) out.push_back(&k);
    }
  return out;
}

const BodyType& body_type_of(const ElasticParams& el) {
  for (const BodyType* t : body_types())
    if (t->describes(el)) return *t;
  throw ParameterError("elastic", "no registered kind of body describes these parameters");
}

std::unique_ptr<Body> make_body(const ElasticParams& el) {
  el.validate();
  return body_type_of(el).make(el);
}

}  // namespace gfmd
