// GFMD_HD marks a function for the host and, compiled by nvcc, the CUDA device too: the
// arithmetic that both backends share is written once (e.g. src/elastic/principal_point.hpp).
#pragma once

#ifdef __CUDACC__
#define GFMD_HD __host__ __device__
#else
#define GFMD_HD
#endif
