// Distributed runs over MPI: joining, slabs, gathers and the FFTW-MPI engine. See
// include/gfmd/core/mpi.hpp. Without GFMD_WITH_MPI every function is its one-process form.
#include "gfmd/core/mpi.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <utility>

#ifdef GFMD_WITH_MPI
#include <fftw3-mpi.h>
#include <mpi.h>

#include "fft_lines.hpp"
#endif

namespace gfmd::mpi {

namespace {
// neighbour_rows of a whole grid: its last and first rows.
NeighbourRows neighbour_rows_whole(const Grid& g, const RealField& whole) {
  const auto nx = static_cast<std::ptrdiff_t>(g.nx);
  NeighbourRows out;
  out.below.assign(whole.end() - nx, whole.end());
  out.above.assign(whole.begin(), whole.begin() + nx);
  return out;
}

std::vector<double> pick_whole(const RealField& whole, const std::vector<std::size_t>& points) {
  std::vector<double> values(points.size());
  for (std::size_t k = 0; k < points.size(); ++k) values[k] = whole.at(points[k]);
  return values;
}
}  // namespace

bool launched() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE", "MPI_LOCALNRANKS"})
    if (const char* s = std::getenv(v); s && *s) return true;
  return false;
}

int processes_on_this_machine() {
  for (const char* v : {"OMPI_COMM_WORLD_LOCAL_SIZE", "MPI_LOCALNRANKS", "PMI_LOCAL_SIZE"})
    if (const char* s = std::getenv(v); s && *s) {
      const int n = std::atoi(s);
      if (n > 0) return n;
    }
  return 1;
}

double peak_resident_bytes() {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("VmHWM:", 0) == 0) return 1024.0 * std::strtod(line.c_str() + 6, nullptr);
  return 0.0;
}

#ifdef GFMD_WITH_MPI

namespace {
bool g_joined = false;  // init joined MPI (and so finalize leaves it)
int g_rank = 0, g_size = 1;
double g_reduction_seconds = 0.0;

// Adds the wall time of its scope to the reductions' total (benchmarks).
struct ReductionTimer {
  double t0 = MPI_Wtime();
  ~ReductionTimer() { g_reduction_seconds += MPI_Wtime() - t0; }
};

void check(int rc, const char* what) {
  if (rc != MPI_SUCCESS) throw std::runtime_error(std::string("MPI: ") + what + " failed");
}
}  // namespace

bool built() { return true; }

int init(int* argc, char*** argv) {
  if (g_joined || !launched()) return g_size;
  int initialised = 0;
  MPI_Initialized(&initialised);
  if (!initialised) {
    int provided = 0;
    check(MPI_Init_thread(argc, argv, MPI_THREAD_SERIALIZED, &provided), "MPI_Init_thread");
  }
  g_joined = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &g_rank);
  MPI_Comm_size(MPI_COMM_WORLD, &g_size);
  // FFTW-MPI needs FFTW's threads first (plans inside a rank use its OpenMP threads).
  fftw_init_threads();
  fftw_mpi_init();
  return g_size;
}

void finalize() {
  if (!g_joined) return;
  g_joined = false;
  int finalised = 0;
  MPI_Finalized(&finalised);
  if (!finalised) {
    fftw_mpi_cleanup();
    MPI_Finalize();
  }
  g_rank = 0;
  g_size = 1;
}

int rank() { return g_rank; }
int size() { return g_size; }
double reduction_seconds() { return g_reduction_seconds; }

namespace {
// This process's rows of FFTW-MPI's distribution of the r2c half spectrum (ny x nxh), which is
// also that of the real field; and the complex elements its plans need.
struct Local {
  std::ptrdiff_t rows = 0, start = 0, alloc = 0;
};
Local local_rows(const Grid& whole) {
  Local l;
  l.alloc = fftw_mpi_local_size_2d(whole.ny, whole.nxh(), MPI_COMM_WORLD, &l.rows, &l.start);
  return l;
}
}  // namespace

Grid slab_of(const Grid& whole) {
  Grid g = whole.whole();
  if (g_size == 1) return g;
  const Local l = local_rows(whole);
  g.y0 = static_cast<int>(l.start);
  g.slab_rows = static_cast<int>(l.rows);
  return g;
}

namespace {
// The first row and the row count of every process for `whole` (index = rank). Asked once per
// grid (one collective) and kept: every reduction on a slab needs it.
struct Layout {
  std::vector<int> starts, rows;
};
const Layout& layout(const Grid& whole) {
  static std::mutex mutex;
  static std::map<std::pair<int, int>, Layout> known;
  const std::lock_guard lock(mutex);
  const auto key = std::pair{whole.nx, whole.ny};
  if (const auto it = known.find(key); it != known.end()) return it->second;
  const Local l = local_rows(whole);
  const int mine[2] = {static_cast<int>(l.start), static_cast<int>(l.rows)};
  std::vector<int> all(2 * static_cast<std::size_t>(g_size));
  check(MPI_Allgather(mine, 2, MPI_INT, all.data(), 2, MPI_INT, MPI_COMM_WORLD), "MPI_Allgather");
  Layout lay;
  for (std::size_t r = 0; r < static_cast<std::size_t>(g_size); ++r) {
    lay.starts.push_back(all[2 * r]);
    lay.rows.push_back(all[2 * r + 1]);
  }
  return known.emplace(key, std::move(lay)).first->second;
}

// Counts and displacements of every process's rows, times `per_row` elements.
void row_layout(const Grid& slab, std::size_t per_row, std::vector<int>& counts, std::vector<int>& displs) {
  const Layout& lay = layout(slab.whole());
  counts.resize(lay.rows.size());
  displs.resize(lay.rows.size());
  for (std::size_t r = 0; r < lay.rows.size(); ++r) {
    const std::size_t c = static_cast<std::size_t>(lay.rows[r]) * per_row;
    const std::size_t d = static_cast<std::size_t>(lay.starts[r]) * per_row;
    if (c > static_cast<std::size_t>(INT32_MAX) || d > static_cast<std::size_t>(INT32_MAX))
      throw std::runtime_error("MPI: a slab of more than 2^31 elements (use more processes)");
    counts[r] = static_cast<int>(c);
    displs[r] = static_cast<int>(d);
  }
}
}  // namespace

std::vector<double> all_rows(const Grid& slab, const std::vector<double>& local, std::size_t k) {
  if (!slab.is_slab()) return local;
  const ReductionTimer timer;
  std::vector<int> counts, displs;
  row_layout(slab, k, counts, displs);
  std::vector<double> all(static_cast<std::size_t>(slab.ny) * k);
  check(MPI_Allgatherv(local.data(), counts[static_cast<std::size_t>(g_rank)], MPI_DOUBLE, all.data(),
                       counts.data(), displs.data(), MPI_DOUBLE, MPI_COMM_WORLD),
        "MPI_Allgatherv");
  return all;
}

double max_all(const Grid& g, double v) {
  if (!g.is_slab()) return v;
  const ReductionTimer timer;
  double m = v;
  check(MPI_Allreduce(&v, &m, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD), "MPI_Allreduce");
  return m;
}

std::uint64_t sum_all(const Grid& g, std::uint64_t v) {
  if (!g.is_slab()) return v;
  const ReductionTimer timer;
  std::uint64_t s = v;
  check(MPI_Allreduce(&v, &s, 1, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD), "MPI_Allreduce");
  return s;
}

std::vector<double> all_values(double v) {
  std::vector<double> all(static_cast<std::size_t>(g_size), v);
  if (g_size > 1)
    check(MPI_Allgather(&v, 1, MPI_DOUBLE, all.data(), 1, MPI_DOUBLE, MPI_COMM_WORLD), "MPI_Allgather");
  return all;
}

bool all_ok(bool ok) {
  if (g_size == 1) return ok;
  const ReductionTimer timer;
  int mine = ok ? 1 : 0, all = 0;
  check(MPI_Allreduce(&mine, &all, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD), "MPI_Allreduce");
  return all == 1;
}

int agree_exit(int code) {
  if (g_size == 1) return code;
  int all = code;
  if (MPI_Allreduce(&code, &all, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD) != MPI_SUCCESS) return code ? code : 1;
  return all;
}

unsigned any_bits(unsigned bits) {
  if (g_size == 1) return bits;
  const ReductionTimer timer;
  unsigned all = bits;
  check(MPI_Allreduce(&bits, &all, 1, MPI_UNSIGNED, MPI_BOR, MPI_COMM_WORLD), "MPI_Allreduce");
  return all;
}

int from_root(int v) {
  if (g_size > 1) check(MPI_Bcast(&v, 1, MPI_INT, 0, MPI_COMM_WORLD), "MPI_Bcast");
  return v;
}

std::string from_root(const std::string& text) {
  if (g_size == 1) return text;
  if (text.size() > static_cast<std::size_t>(INT32_MAX))
    throw std::runtime_error("MPI: a text of over 2 GiB");
  const int n = from_root(static_cast<int>(text.size()));
  std::string t = g_rank == 0 ? text : std::string(static_cast<std::size_t>(n), '\0');
  if (n > 0) check(MPI_Bcast(t.data(), n, MPI_CHAR, 0, MPI_COMM_WORLD), "MPI_Bcast");
  return t;
}

namespace {
template <class Vec>
Vec gather_impl(const Grid& slab, const Vec& local, MPI_Datatype type) {
  if (!slab.is_slab()) return local;
  std::vector<int> counts, displs;
  row_layout(slab, static_cast<std::size_t>(slab.nx), counts, displs);
  Vec all;
  if (g_rank == 0) all.resize(slab.size());
  check(MPI_Gatherv(local.data(), counts[static_cast<std::size_t>(g_rank)], type, all.data(), counts.data(),
                    displs.data(), type, 0, MPI_COMM_WORLD),
        "MPI_Gatherv");
  return all;
}

// This process's rows of a whole field rank 0 holds (the others' `whole` is not read).
template <class Vec>
Vec scatter_impl(const Grid& slab, const Vec& whole, MPI_Datatype type) {
  if (!slab.is_slab()) return whole;
  std::vector<int> counts, displs;
  row_layout(slab, static_cast<std::size_t>(slab.nx), counts, displs);
  if (g_rank == 0 && whole.size() != slab.size()) throw std::logic_error("mpi::scatter: not a whole field");
  Vec local(slab.local_size());
  check(MPI_Scatterv(g_rank == 0 ? whole.data() : nullptr, counts.data(), displs.data(), type, local.data(),
                     counts[static_cast<std::size_t>(g_rank)], type, 0, MPI_COMM_WORLD),
        "MPI_Scatterv");
  return local;
}
}  // namespace

RealField gather(const Grid& slab, const RealField& local) { return gather_impl(slab, local, MPI_DOUBLE); }

RealField scatter(const Grid& slab, const RealField& whole) { return scatter_impl(slab, whole, MPI_DOUBLE); }
std::vector<unsigned char> gather(const Grid& slab, const std::vector<unsigned char>& local) {
  return gather_impl(slab, local, MPI_UNSIGNED_CHAR);
}

std::vector<unsigned char> scatter(const Grid& slab, const std::vector<unsigned char>& whole) {
  return scatter_impl(slab, whole, MPI_UNSIGNED_CHAR);
}

std::vector<std::int64_t> all_gather(const std::vector<std::int64_t>& local) {
  if (g_size == 1) return local;
  const ReductionTimer timer;
  const int mine = static_cast<int>(local.size());
  std::vector<int> counts(static_cast<std::size_t>(g_size)), offsets(static_cast<std::size_t>(g_size), 0);
  check(MPI_Allgather(&mine, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD), "MPI_Allgather");
  std::size_t total = 0;
  for (std::size_t r = 0; r < counts.size(); ++r) {
    offsets[r] = static_cast<int>(total);
    total += static_cast<std::size_t>(counts[r]);
  }
  std::vector<std::int64_t> all(total);
  check(MPI_Allgatherv(local.data(), mine, MPI_INT64_T, all.data(), counts.data(), offsets.data(),
                       MPI_INT64_T, MPI_COMM_WORLD),
        "MPI_Allgatherv");
  return all;
}

std::vector<double> add_over_processes(const std::vector<double>& v) {
  if (g_size == 1) return v;
  const ReductionTimer timer;
  std::vector<double> all(v.size() * static_cast<std::size_t>(g_size));
  check(MPI_Allgather(v.data(), static_cast<int>(v.size()), MPI_DOUBLE, all.data(),
                      static_cast<int>(v.size()), MPI_DOUBLE, MPI_COMM_WORLD),
        "MPI_Allgather");
  std::vector<double> total(v.size(), 0.0);
  for (std::size_t r = 0; r < static_cast<std::size_t>(g_size); ++r)
    for (std::size_t j = 0; j < v.size(); ++j) total[j] += all[r * v.size() + j];
  return total;
}

NeighbourRows neighbour_rows(const Grid& slab, const RealField& local) {
  if (!slab.is_slab()) return neighbour_rows_whole(slab, local);
  const auto nx = static_cast<std::size_t>(slab.nx);
  NeighbourRows out;
  // Every process hands on its first and last rows; each takes the rows next to its slab.
  const Layout& lay = layout(slab.whole());
  const std::size_t p = lay.rows.size();
  std::vector<int> counts(p), displs(p);
  int at = 0;
  for (std::size_t r = 0; r < p; ++r) {
    counts[r] = lay.rows[r] > 0 ? static_cast<int>(2 * nx) : 0;
    displs[r] = at;
    at += counts[r];
  }
  std::vector<double> mine;
  if (slab.rows() > 0) {
    mine.assign(local.begin(), local.begin() + static_cast<std::ptrdiff_t>(nx));
    mine.insert(mine.end(), local.end() - static_cast<std::ptrdiff_t>(nx), local.end());
  }
  std::vector<double> all(static_cast<std::size_t>(at));
  check(MPI_Allgatherv(mine.data(), counts[static_cast<std::size_t>(g_rank)], MPI_DOUBLE, all.data(),
                       counts.data(), displs.data(), MPI_DOUBLE, MPI_COMM_WORLD),
        "MPI_Allgatherv");
  if (slab.rows() == 0) return out;
  // The row of the cell `row` (global, periodic) from the boundary rows of its holder.
  const auto row_of = [&](int row, RealField& to) {
    for (std::size_t r = 0; r < p; ++r)
      if (lay.rows[r] > 0 && row >= lay.starts[r] && row < lay.starts[r] + lay.rows[r]) {
        const std::size_t first = static_cast<std::size_t>(displs[r]) + (row == lay.starts[r] ? 0 : nx);
        to.assign(all.begin() + static_cast<std::ptrdiff_t>(first),
                  all.begin() + static_cast<std::ptrdiff_t>(first + nx));
        return;
      }
  };
  row_of((slab.y0 + slab.ny - 1) % slab.ny, out.below);
  row_of((slab.y0 + slab.rows()) % slab.ny, out.above);
  return out;
}

std::vector<double> pick(const Grid& slab, const RealField& local, const std::vector<std::size_t>& points) {
  if (!slab.is_slab()) return pick_whole(local, points);
  // The holder of each point puts its bits, the others zero bits: a bitwise OR gives every
  // value exactly (signed zeros and NaNs included).
  const std::size_t lo = static_cast<std::size_t>(slab.y0) * slab.nx, n = slab.local_size();
  std::vector<std::uint64_t> bits(points.size(), 0);
  for (std::size_t k = 0; k < points.size(); ++k)
    if (points[k] >= lo && points[k] - lo < n) std::memcpy(&bits[k], &local[points[k] - lo], sizeof(double));
  if (!bits.empty())
    check(MPI_Allreduce(MPI_IN_PLACE, bits.data(), static_cast<int>(bits.size()), MPI_UINT64_T, MPI_BOR,
                        MPI_COMM_WORLD),
          "MPI_Allreduce");
  std::vector<double> values(points.size());
  std::memcpy(values.data(), bits.data(), bits.size() * sizeof(double));
  return values;
}

namespace {
// The transforms of a slab as lines (fft_lines.hpp): this process's rows, FFTW-MPI's
// transpose of the half spectrum (each process then holds whole columns), the columns,
// the transpose back. Every line goes through the one-line plan a whole grid uses, so the
// bits are those of one process for any process count. The transposes run on two buffers
// of FFTW-MPI's local size (each about the slab's half spectrum).
class FftwMpiEngine final : public FftEngine {
 public:
  FftwMpiEngine(const Grid& g, int threads) : g_(g), plans_(g.nx, g.ny, threads) {
    const std::ptrdiff_t n[2] = {g.ny, g.nxh()};
    std::ptrdiff_t rows = 0, start = 0, cols = 0, col0 = 0;
    const std::ptrdiff_t alloc = fftw_mpi_local_size_many_transposed(
        2, n, 2, FFTW_MPI_DEFAULT_BLOCK, FFTW_MPI_DEFAULT_BLOCK, MPI_COMM_WORLD, &rows, &start, &cols, &col0);
    if (rows != g.rows() || start != g.y0)
      throw std::logic_error("FFTW-MPI: the grid's slab is not this process's rows");
    cols_ = static_cast<int>(cols);
    const auto doubles = static_cast<std::size_t>(std::max<std::ptrdiff_t>(alloc, 2));
    a_ = fftw_alloc_real(doubles);
    b_ = fftw_alloc_real(doubles);
    if (!a_ || !b_) {
      destroy();
      throw std::bad_alloc();
    }
    fftw_plan_with_nthreads(threads);
    to_columns_ = fftw_mpi_plan_many_transpose(g.ny, g.nxh(), 2, FFTW_MPI_DEFAULT_BLOCK,
                                               FFTW_MPI_DEFAULT_BLOCK, a_, b_, MPI_COMM_WORLD, FFTW_ESTIMATE);
    to_rows_ = fftw_mpi_plan_many_transpose(g.nxh(), g.ny, 2, FFTW_MPI_DEFAULT_BLOCK, FFTW_MPI_DEFAULT_BLOCK,
                                            b_, a_, MPI_COMM_WORLD, FFTW_ESTIMATE);
    if (!to_columns_ || !to_rows_) {
      destroy();
      throw std::runtime_error("FFTW-MPI could not make a transpose plan");
    }
  }
  ~FftwMpiEngine() override { destroy(); }
  FftwMpiEngine(const FftwMpiEngine&) = delete;
  FftwMpiEngine& operator=(const FftwMpiEngine&) = delete;

  void forward(const double* in, cplx* out) override {
    plans_.rows_forward(in, spectrum(a_), g_.rows());
    columns(FFTW_FORWARD);
    if (g_.rows() > 0) std::memcpy(static_cast<void*>(out), a_, sizeof(cplx) * g_.spectral_size());
  }
  void backward_unscaled(cplx* in, double* out) override {
    if (g_.rows() > 0) std::memcpy(a_, static_cast<const void*>(in), sizeof(cplx) * g_.spectral_size());
    columns(FFTW_BACKWARD);
    plans_.rows_backward(spectrum(a_), out, g_.rows());
  }

 private:
  static cplx* spectrum(double* p) { return reinterpret_cast<cplx*>(p); }
  // The half spectrum in a_ (this slab's rows) transformed along y, back in a_.
  void columns(int sign) {
    fftw_execute(to_columns_);
    plans_.lines(spectrum(b_), cols_, sign);
    fftw_execute(to_rows_);
  }
  void destroy() {
    if (to_columns_) fftw_destroy_plan(to_columns_);
    if (to_rows_) fftw_destroy_plan(to_rows_);
    if (a_) fftw_free(a_);
    if (b_) fftw_free(b_);
    to_columns_ = to_rows_ = nullptr;
    a_ = b_ = nullptr;
  }
  Grid g_;
  detail::LinePlans plans_;
  int cols_ = 0;
  double* a_ = nullptr;
  double* b_ = nullptr;
  fftw_plan to_columns_ = nullptr, to_rows_ = nullptr;
};
}  // namespace

std::unique_ptr<FftEngine> make_fftw_mpi_engine(const Grid& slab, int threads) {
  return std::make_unique<FftwMpiEngine>(slab, threads);
}

#else  // one process

bool built() { return false; }
int init(int*, char***) { return 1; }
void finalize() {}
int rank() { return 0; }
int size() { return 1; }
double reduction_seconds() { return 0.0; }
Grid slab_of(const Grid& whole) { return whole.whole(); }
std::vector<double> all_rows(const Grid& slab, const std::vector<double>& local, std::size_t) {
  if (slab.is_slab()) throw std::logic_error("a slab grid in a build without MPI");
  return local;
}
double max_all(const Grid&, double v) { return v; }
std::vector<double> all_values(double v) { return {v}; }
std::uint64_t sum_all(const Grid&, std::uint64_t v) { return v; }
bool all_ok(bool ok) { return ok; }
int agree_exit(int code) { return code; }
unsigned any_bits(unsigned bits) { return bits; }
int from_root(int v) { return v; }
std::string from_root(const std::string& text) { return text; }
RealField scatter(const Grid&, const RealField& whole) { return whole; }
RealField gather(const Grid&, const RealField& local) { return local; }
std::vector<unsigned char> gather(const Grid&, const std::vector<unsigned char>& local) { return local; }
std::vector<unsigned char> scatter(const Grid&, const std::vector<unsigned char>& whole) { return whole; }
std::vector<double> add_over_processes(const std::vector<double>& v) { return v; }
std::vector<std::int64_t> all_gather(const std::vector<std::int64_t>& local) { return local; }
NeighbourRows neighbour_rows(const Grid& slab, const RealField& local) {
  return neighbour_rows_whole(slab, local);
}
std::vector<double> pick(const Grid&, const RealField& local, const std::vector<std::size_t>& points) {
  return pick_whole(local, points);
}
std::unique_ptr<FftEngine> make_fftw_mpi_engine(const Grid&, int) {
  throw std::logic_error("a slab grid in a build without MPI");
}

#endif

RealField rows_of(const Grid& slab, const RealField& whole) {
  if (!slab.is_slab()) return whole;
  const auto first = whole.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(slab.y0) * slab.nx);
  return RealField(first, first + static_cast<std::ptrdiff_t>(slab.local_size()));
}

}  // namespace gfmd::mpi
