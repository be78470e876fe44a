// The registry of a result's per-point fields: each field's name (fields.nc, Python's Result,
// the maps), description and units, once, with where it is stored; result_fields lists those a
// result shows, and a distributed run gathers their storage on rank 0 from the same list.
#include <algorithm>
#include <set>
#include <string>

#include "gfmd/case/leakage.hpp"
#include "gfmd/case/outputs.hpp"
#include "gfmd/contact/patches.hpp"

namespace gfmd {

namespace {

// Every per-point field of r in fields.nc's order: visit(info, storage), storage null for a mask
// result_fields derives (contact, attraction, stick). R is CaseResult or const CaseResult.
template <class R, class Visit>
void each_field(R& r, Visit&& visit) {
  const std::string length = length_units(r.config.length_unit);
  const std::size_t n = r.config.grid.size();
  const bool friction = r.config.friction.coefficient > 0;
  auto& f = r.fields;
  auto& d = r.derived;
  const auto field = [&](const char* name, auto& storage, std::string description, const std::string& units,
                         bool in_maps, bool shown = true) {
    visit(ResultField{name, std::move(description), units, in_maps, shown}, &storage);
  };
  const auto mask = [&](const char* name, std::string description, bool shown) {
    visit(ResultField{name, std::move(description), "1", true, shown}, nullptr);
  };
  field("pressure", f.pressure, "contact pressure on the body (compressive positive)", "E*", true);
  field("gap", f.gap, "gap between indenter and deformed surface", length, true);
  field("ux", f.ux, "surface displacement along x", length, false);
  field("uy", f.uy, "surface displacement along y", length, false);
  field("uz", f.uz, "surface displacement along z (out of the body)", length, false);
  mask("contact", "contact mask (1 = in contact)", true);
  field("traction_x", f.tx, "friction traction on the body along x", "E*", false, friction);
  field("traction_y", f.ty, "friction traction on the body along y", "E*", false, friction);
  field("slip_longitudinal", d.slip_longitudinal,
        "relative longitudinal slip velocity v_l^rel/v0 - 1 = (e_s.grad) u_s", "1", true, friction);
  field("slip_transverse", d.slip_transverse, "transverse slip velocity / v0 = (e_s.grad) u_perp", "1", true,
        friction);
  field("dissipation", d.dissipation,
        r.config.friction.law.kind == FrictionLawKind::Coulomb
            ? "dissipated power density / v0 = tau . v_slip / v0 (mu_c p |v|/v0 where slipping)"
            : "dissipated power density / v0 = tau . v_slip / v0 (mu(|v|) p |v|/v0 where slipping)",
        "E*", true, friction);
  const bool adhesive = f.adhesion.size() == n;
  field(
      "adhesive_traction", f.adhesion,
      "adhesive (tensile) traction the indenter exerts on the body: the Maugis-Dugdale stress where the gap "
      "is below interaction.range, 0 elsewhere",
      "E*", true, adhesive);
  mask("attraction", "attraction mask (1 = under adhesive traction: contact or cohesive zone)", adhesive);
  field("plastic_displacement", d.plastic_displacement,
        "plastic displacement: the indenter's overlap beyond the elastic one where p is at "
        "interaction.hardness",
        length, true, d.plastic_displacement.size() == n);
  mask("stick", "stick mask (1 = contact point that sticks: zero slip velocity)", f.stick.size() == n);
  const bool stresses = !r.principal.s1.empty();
  auto& st = r.stress;
  auto& pr = r.principal;
  field("sigma_xx", st.xx, "surface stress xx (tensile positive)", "E*", false, stresses);
  field("sigma_yy", st.yy, "surface stress yy", "E*", false, stresses);
  field("sigma_zz", st.zz, "surface stress zz (= -p)", "E*", false, stresses);
  field("sigma_xy", st.xy, "surface stress xy", "E*", false, stresses);
  field("sigma_xz", st.xz, "surface stress xz (= friction traction x)", "E*", false, stresses);
  field("sigma_yz", st.yz, "surface stress yz", "E*", false, stresses);
  field("sigma_1", pr.s1, "maximum principal (most tensile) surface stress sigma_I", "E*", true, stresses);
  field("sigma_2", pr.s2, "middle principal surface stress", "E*", false, stresses);
  field("sigma_3", pr.s3, "minimum principal surface stress", "E*", false, stresses);
  field("e1_x", pr.e1x, "eigenvector of sigma_I, x", "1", false, stresses);
  field("e1_y", pr.e1y, "eigenvector of sigma_I, y", "1", false, stresses);
  field("e1_z", pr.e1z, "eigenvector of sigma_I, z", "1", false, stresses);
  field("von_mises", pr.von_mises, "von Mises surface stress", "E*", true, stresses);
  if (!r.post_analyses.empty()) {
    auto& front = r.post_analyses.front();
    visit(ResultField{"post_analysis_sigma_1",
                      "sigma_I of the post-analysis reference (" + front.kind +
                          "; the first of [stress] post_analysis)",
                      "E*", false, stresses},
          &front.s1);
    for (auto& pa : r.post_analyses)
      visit(
          ResultField{"post_analysis_" + pa.kind + "_sigma_1",
                      pa.kind == "paper"
                          ? "sigma_I of the paper's post-analysis (frictionless fields, sigma_az = mu p)"
                          : "sigma_I of the consistent post-analysis (frictionless p + mu p with its strain)",
                      "E*", false, stresses},
          &pa.s1);
  }
  for (std::size_t k = 0; k < r.subsurface.size(); ++k) {
    auto& ss = r.subsurface[k];
    const std::string depth = std::to_string(ss.depth);
    visit(ResultField{"von_mises_depth_" + std::to_string(k), "von Mises stress at depth " + depth, "E*",
                      false, stresses},
          &ss.von_mises);
    visit(ResultField{"sigma_1_depth_" + std::to_string(k), "maximum principal stress at depth " + depth,
                      "E*", false, stresses},
          &ss.s1);
  }
}

}  // namespace

void for_each_result_field(const CaseResult& r,
                           const std::function<void(const ResultField&, const RealField*)>& visit) {
  each_field(r, visit);
}

void for_each_result_field(CaseResult& r, const std::function<void(const ResultField&, RealField*)>& visit) {
  each_field(r, visit);
}

FieldSet result_fields(const CaseResult& r, bool maps_only) {
  FieldSet set;
  std::vector<NamedField>& fields = set.fields;
  const std::size_t n = r.config.grid.size();
  set.masks.reserve(3);  // the masks' storage must not move while the fields point into it
  if (!maps_only)
    fields.push_back({"topography", r.topography.h.data(), "indenter height towards the body",
                      length_units(r.config.length_unit)});
  for_each_result_field(r, [&](const ResultField& info, const RealField* storage) {
    if (!info.shown || (maps_only && !info.in_maps)) return;
    if (storage) {
      fields.push_back({info.name, storage->data(), info.description, info.units});
      return;
    }
    RealField& m = set.masks.emplace_back(n);
    if (info.name == "contact") {
      const std::vector<unsigned char> in_contact = contact_mask(r.fields);
      for (std::size_t i = 0; i < n; ++i) m[i] = in_contact[i];
    } else if (info.name == "attraction") {
      for (std::size_t i = 0; i < n; ++i) m[i] = r.fields.adhesion[i] > 0 ? 1.0 : 0.0;
    } else {  // stick
      for (std::size_t i = 0; i < n; ++i) m[i] = r.fields.stick[i] ? 1.0 : 0.0;
    }
    fields.push_back({info.name, m.data(), info.description, info.units});
  });
  // The current maps are drawn from flow.nc, which write_leakage writes with every flow.
  if (!maps_only && r.leakage) append_current_fields(*r.leakage, fields, r.config.length_unit);
  return set;
}

}  // namespace gfmd
