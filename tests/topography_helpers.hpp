// Helpers shared by the topography tests (test_topography.cpp, test_topography_files.cpp).
#pragma once

#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "gfmd/core/error.hpp"
#include "gfmd/surface/topography.hpp"

namespace topo_test {

using gfmd::InputError;
using gfmd::SelfAffineParams;

// Whether two fields hold the same bits.
inline bool bit_identical(const gfmd::RealField& a, const gfmd::RealField& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

// The paper-like self-affine parameters on a cell of size L.
inline SelfAffineParams paper_like(double L) {
  SelfAffineParams p;
  p.hurst = 0.8;
  p.lambda_long = L / 2;
  p.lambda_short = L / 32;
  p.rms_height = 0.01 * L / 2;
  p.seed = 12345;
  return p;
}

template <class F>
void expect_input_error(F&& f, const std::string& where, const std::string& fragment) {
  try {
    f();
    ADD_FAILURE() << "expected InputError mentioning '" << where << "' and '" << fragment << "'";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(where), std::string::npos) << "message: " << msg;
    EXPECT_NE(msg.find(fragment), std::string::npos) << "message: " << msg;
  }
}

}  // namespace topo_test
