// The registry of a result's per-point fields (for_each_result_field, src/case/result_fields.cpp):
// fields.nc, Python's Result and the maps list exactly the fields it shows, each once, viewing the
// storage it names; the maps' subset is the registry's; a distributed run gathers the same list.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>
#include <vector>

#include "gfmd/case/outputs.hpp"
#include "test_util.hpp"

using namespace gfmd;
using gfmd::testing::solve;

namespace {

// Sliding with adhesion, stick flags, stresses with a post-analysis and a subsurface plane: every
// kind of field the registry holds.
CaseResult everything() {
  Config c =
      parse_config(gfmd::testing::kSmallHertz, "t.toml",
                   {"friction.coefficient=0.3", "interaction.model=\"adhesive\"",
                    "interaction.work_of_adhesion=1e-4", "interaction.range=0.05", "output.fields=false"});
  c.stress.post_analysis = {"consistent"};
  c.stress.depths = {0.1};
  CaseResult r = run_case(c);
  EXPECT_TRUE(r.info.converged) << r.info.status;
  return r;
}

}  // namespace

TEST(ResultFields, EveryShownFieldIsListedOnceViewingItsStorage) {
  const CaseResult r = everything();
  std::vector<std::string> shown, maps;
  std::set<const double*> storage;
  for_each_result_field(r, [&](const ResultField& info, const RealField* f) {
    EXPECT_FALSE(info.name.empty());
    EXPECT_FALSE(info.description.empty()) << info.name;
    EXPECT_FALSE(info.units.empty()) << info.name;
    if (!info.shown) return;
    shown.push_back(info.name);
    if (info.in_maps) maps.push_back(info.name);
    if (f) {
      EXPECT_EQ(f->size(), r.config.grid.size()) << info.name;
      storage.insert(f->data());
    }
  });
  // This case shows every kind: the friction's, adhesion's, the masks, stresses and the planes.
  for (const char* name :
       {"pressure", "traction_x", "dissipation", "adhesive_traction", "attraction", "contact", "stick",
        "sigma_1", "post_analysis_consistent_sigma_1", "sigma_1_depth_0"})
    EXPECT_NE(std::find(shown.begin(), shown.end(), name), shown.end()) << name;
  const FieldSet all = result_fields(r);
  ASSERT_EQ(all.fields.size(), shown.size() + 1);  // and the topography first
  EXPECT_EQ(all.fields.front().name, "topography");
  std::set<std::string> names;
  for (std::size_t k = 0; k < shown.size(); ++k) {
    const NamedField& nf = all.fields[k + 1];
    EXPECT_EQ(nf.name, shown[k]);
    EXPECT_TRUE(names.insert(nf.name).second) << nf.name << " twice";
    // A field views the registry's storage; a mask is the set's own.
    const bool own = std::any_of(all.masks.begin(), all.masks.end(),
                                 [&](const RealField& m) { return m.data() == nf.data; });
    EXPECT_NE(storage.count(nf.data) > 0, own) << nf.name;
  }
  const FieldSet on_maps = result_fields(r, true);
  ASSERT_EQ(on_maps.fields.size(), maps.size());
  for (std::size_t k = 0; k < maps.size(); ++k) EXPECT_EQ(on_maps.fields[k].name, maps[k]);
  // The masks hold what they say.
  for (const NamedField& nf : all.fields) {
    if (nf.name != "stick") continue;
    for (std::size_t i = 0; i < r.fields.stick.size(); ++i) {
      ASSERT_EQ(nf.data[i], r.fields.stick[i] ? 1.0 : 0.0);
    }
  }
}

TEST(ResultFields, AFrictionlessResultShowsNoFrictionFields) {
  const CaseResult r = solve(gfmd::testing::kSmallHertz, {"output.fields=false"});
  const FieldSet all = result_fields(r);
  for (const NamedField& nf : all.fields)
    for (const char* name : {"traction_x", "slip_longitudinal", "dissipation", "adhesive_traction", "stick"})
      EXPECT_NE(nf.name, name);
}
