// Distributed runs: the processes started by mpirun and the slabs of rows they hold.
//
// One program serves serial and distributed runs. Started by mpirun (or any launcher that
// sets OpenMPI's or PMI's rank variables), gfmd joins MPI (init) and a case's fields are
// split into slabs of whole rows, the block distribution FFTW-MPI uses for its r2c
// transforms (slab_of): every grid pass then runs on the rows a process holds, every FFT
// runs line by line with FFTW-MPI's transposes (one process's bits), and every reduction
// gathers the row partials of all processes and adds them in row order (all_rows), so that
// sums do not depend on the number of processes. Without mpirun, or in a build without MPI
// (GFMD_WITH_MPI off), there is one process and nothing here communicates.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "gfmd/core/fft.hpp"
#include "gfmd/core/grid.hpp"

namespace gfmd::mpi {

// Whether this build can run distributed.
bool built();
// Whether a launcher started this process as one of several ranks (its environment says so).
bool launched();
// Joins MPI when launched (thread support: funnelled), and readies FFTW-MPI. Idempotent.
// Returns the number of processes.
int init(int* argc, char*** argv);
// Leaves MPI if init joined it (called at exit by the program).
void finalize();
int rank();
int size();
// Wall time this process has spent in the reductions' collectives so far (benchmarks).
double reduction_seconds();
// True on the process that writes outputs (rank 0, or the only process).
inline bool root() { return rank() == 0; }
// True when a case's fields are split over more than one process.
inline bool distributed() { return size() > 1; }

// The slab of `whole` this process holds in a run over size() processes (FFTW-MPI's block
// distribution of ny rows; the last processes may hold fewer rows, or none when ny is not
// a multiple of the block). A whole grid when there is one process.
Grid slab_of(const Grid& whole);

// Row partials of a slab gathered from every process: `local` holds k values per row held
// here (slab.rows() rows); the result holds k values for each of the ny rows of the cell, in
// row order, on every process. The identity for a whole grid.
std::vector<double> all_rows(const Grid& slab, const std::vector<double>& local, std::size_t k);
// Over the processes that share the slab grid `g` (exact): the largest value, the sum of
// integer counts. v itself for a whole grid, which one process holds alone (rank 0's
// post-processing, or a run without mpirun).
double max_all(const Grid& g, double v);
std::uint64_t sum_all(const Grid& g, std::uint64_t v);
// Vectors of equal length from every process added element by element in rank order, on
// every process (a collective; v itself in one process).
std::vector<double> add_over_processes(const std::vector<double>& v);
// Every process's list, concatenated in rank order, on every process (a collective; the
// lists may differ in length, each below 2^31 entries). `local` itself in one process.
std::vector<std::int64_t> all_gather(const std::vector<std::int64_t>& local);
// Processes of this run on this machine (the launcher's local size; 1 without one).
int processes_on_this_machine();
// Every process's value, by rank, on every process.
std::vector<double> all_values(double v);
// Peak resident memory of this process so far (VmHWM), in bytes; 0 where unknown.
double peak_resident_bytes();
// The logical AND of `ok` over the processes (a collective; every process must call it).
bool all_ok(bool ok);
// The largest exit code over the processes: every rank exits with the same code.
int agree_exit(int code);
// The bitwise OR of `bits` over the processes (a collective): one call agrees several flags.
unsigned any_bits(unsigned bits);
// Rank 0's value on every process (a collective; the others' arguments are ignored): how rank
// 0 hands on what it alone decided or read (a directory's state, a study's results as JSON).
int from_root(int v);
std::string from_root(const std::string& text);

// The whole field on rank 0 from the slabs of every process (empty elsewhere); costs the
// whole field's memory on rank 0.
RealField gather(const Grid& slab, const RealField& local);
std::vector<unsigned char> gather(const Grid& slab, const std::vector<unsigned char>& local);
std::vector<unsigned char> scatter(const Grid& slab, const std::vector<unsigned char>& whole);
// The rows next to this process's slab (a collective on a slab): `below` is row y0 - 1,
// `above` row y0 + rows() (periodic; a whole grid's last and first rows). Empty on a process
// that holds no rows. What a pass that couples a row to its neighbours (a 5-point stencil)
// needs from the other processes.
struct NeighbourRows {
  RealField below, above;
};
NeighbourRows neighbour_rows(const Grid& slab, const RealField& local);
// The values of a field at the given points (global indices iy * nx + ix of the cell), on
// every process, exactly (a collective on a slab: each point's holder supplies its value).
// Cheap for a few points (a profile through the cell), never for a field.
std::vector<double> pick(const Grid& slab, const RealField& local, const std::vector<std::size_t>& points);
// This process's rows of a whole field (every process holds `whole`).
RealField rows_of(const Grid& slab, const RealField& whole);
// This process's rows of a whole field that only rank 0 holds (a collective; `whole` is read
// on rank 0 only): a warm start or a checkpoint rank 0 read, handed out without copying the
// whole field to every process.
RealField scatter(const Grid& slab, const RealField& whole);

// The transforms of a slab (the engine of every FFT made on a slab grid, core/fft.cpp): the
// rows, FFTW-MPI's transpose, the columns, the transpose back, each line through the one-line
// plan a whole grid uses (src/core/fft_lines.hpp), so the bits are one process's.
std::unique_ptr<FftEngine> make_fftw_mpi_engine(const Grid& slab, int threads);

}  // namespace gfmd::mpi
