// The distribution seam in one process (core/placement.hpp): every call is the identity, a move
// or a direct rethrow, so that run_case's single-process path is the fields themselves. The
// split behaviour (slabs under mpirun) is tested end to end by tests/python/test_mpi.py and
// test_mpi_resume.py: the same bits as one process on 2 to 4 ranks.
#include <gtest/gtest.h>

#include <stdexcept>

#include "gfmd/core/error.hpp"
#include "gfmd/core/placement.hpp"

namespace gfmd {
namespace {

Grid placement_grid() {
  Grid g;
  g.nx = 8;
  g.ny = 4;
  g.lx = 2.0;
  g.ly = 1.0;
  return g;
}

RealField ramp(std::size_t n) {
  RealField f(n);
  for (std::size_t i = 0; i < n; ++i) f[i] = 0.5 * static_cast<double>(i) - 3.0;
  return f;
}

TEST(Placement, OneProcessHoldsTheWholeCellAndLeads) {
  const Placement p = Placement::of(placement_grid());
  EXPECT_FALSE(p.split());
  EXPECT_TRUE(p.lead());
  EXPECT_EQ(p.processes(), 1);
  EXPECT_EQ(p.here().local_size(), placement_grid().size());
  EXPECT_EQ(p.here().y0, 0);
  EXPECT_EQ(p.whole().ny, 4);
}

TEST(Placement, OneProcessKeepsValuesAndFields) {
  const Placement p = Placement::of(placement_grid());
  EXPECT_TRUE(p.agreed(true));
  EXPECT_FALSE(p.agreed(false));
  EXPECT_EQ(p.agreed(7), 7);
  EXPECT_EQ(p.agreed(std::string("numbers 1 2")), "numbers 1 2");
  EXPECT_TRUE(p.any(true));
  EXPECT_FALSE(p.any(false));
  const RealField f = ramp(32);
  EXPECT_EQ(p.spread(f), f);
  EXPECT_EQ(p.rows(f), f);
  EXPECT_EQ(p.whole_of(f), f);
  RealField a = f, empty;
  p.collect({&a, &empty});
  EXPECT_EQ(a, f);
  EXPECT_TRUE(empty.empty());
  std::vector<unsigned char> flags = {1, 0, 1};
  p.collect(flags);
  EXPECT_EQ(flags, (std::vector<unsigned char>{1, 0, 1}));
}

TEST(Placement, OneProcessHandsTheFieldsThemselvesInOrder) {
  const Placement p = Placement::of(placement_grid());
  const RealField a = ramp(32), b = ramp(32);
  std::vector<const RealField*> seen;
  std::vector<std::size_t> order;
  p.each_whole({&a, &b}, [&](std::size_t k, const RealField& f) {
    order.push_back(k);
    seen.push_back(&f);
  });
  ASSERT_EQ(order, (std::vector<std::size_t>{0, 1}));
  EXPECT_EQ(seen[0], &a);  // no copy of the field in one process
  EXPECT_EQ(seen[1], &b);
}

TEST(Placement, OneProcessRethrowsTheFailureItself) {
  const Placement p = Placement::of(placement_grid());
  EXPECT_NO_THROW(p.settle(nullptr));
  EXPECT_NO_THROW(p.settle_any(nullptr));
  const auto input = std::make_exception_ptr(InputError("grid.nx", "too small"));
  EXPECT_THROW(p.settle(input), InputError);
  EXPECT_THROW(p.settle_any(std::make_exception_ptr(SolveError("no convergence"))), SolveError);
  int ran = 0;
  p.on_lead([&] { ++ran; });
  EXPECT_EQ(ran, 1);
  EXPECT_THROW(p.on_lead([] { throw Interrupted("stop"); }), Interrupted);
  // rethrow_from_root does nothing in one process: the caller rethrows its own error.
  EXPECT_NO_THROW(rethrow_from_root(input));
}

}  // namespace
}  // namespace gfmd
