// Where a run's fields live: the distribution seam of the case pipeline.
//
// In one process a run's fields are whole and every call here is the identity (or a move).
// Under mpirun they are slabs of whole rows, one per process (mpi::slab_of), and the process
// that writes the outputs (the lead: rank 0) gathers what needs the whole cell. The pipeline
// (case/run.cpp) states what it needs where (this process's rows of a warm start the lead
// read, a result's fields whole on the lead, the lead's decision on every process, the
// outcome of a stage that may fail on some processes) and never tests which of the two it is
// in; the MPI calls behind it are core/mpi.hpp's.
#pragma once

#include <cstddef>
#include <exception>
#include <functional>
#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

#include "gfmd/core/fields.hpp"
#include "gfmd/core/grid.hpp"
#include "gfmd/core/mpi.hpp"

namespace gfmd {

// Rank 0's error, if it had one (a collective under mpirun): rethrown on rank 0, and on the
// others StoppedWithRoot with the exit code that error gives (rank 0 reports it). Nothing
// happens in a run of one process or when rank 0 had none.
void rethrow_from_root(const std::exception_ptr& failure);

// Runs f on rank 0 only (reading and writing a directory, where one writer is allowed) and
// agrees on its outcome with the others (rethrow_from_root). f itself in one process.
template <class F>
void on_root(F&& f) {
  if (!mpi::distributed()) {
    f();
    return;
  }
  std::exception_ptr failure;
  if (mpi::root()) try {
      f();
    } catch (...) {
      failure = std::current_exception();
    }
  rethrow_from_root(failure);
}

class Placement {
 public:
  // The placement of the fields of a cell `whole` in this run: slabs under mpirun, else whole.
  static Placement of(const Grid& whole);

  const Grid& whole() const { return whole_; }
  // The grid of the fields this process holds (its slab, or the whole cell).
  const Grid& here() const { return here_; }
  // Whether the fields are split over several processes.
  bool split() const { return split_; }
  // Whether this process writes the outputs and holds what is gathered (rank 0; the only one).
  bool lead() const { return lead_; }
  int processes() const;

  // The lead's value on every process (a collective when split; the others' values are
  // ignored). How the lead hands on what it alone read or decided.
  bool agreed(bool v) const;
  int agreed(int v) const;
  std::string agreed(const std::string& v) const;
  // Whether any process says so (a collective when split).
  bool any(bool v) const;

  // This process's rows of a field the lead holds whole (a collective when split: read on the
  // lead only). The field itself in one process.
  RealField spread(const RealField& whole_on_lead) const;
  // This process's rows of a field every process holds whole (no communication).
  RealField rows(const RealField& whole) const;

  // Makes each field that any process holds whole on the lead and empty on the others (a
  // collective when split, in the list's order). Nothing in one process.
  void collect(std::initializer_list<RealField*> fields) const;
  void collect(std::vector<unsigned char>& flags) const;
  // The whole field on the lead, an empty one elsewhere (a collective when split); a copy of
  // `local` in one process.
  RealField whole_of(const RealField& local) const;
  // Hands each field whole to `take` on the lead, one at a time and in the list's order (a
  // collective when split: the lead holds one gathered field at a time); in one process the
  // fields themselves, uncopied.
  void each_whole(const std::vector<const RealField*>& fields,
                  const std::function<void(std::size_t, const RealField&)>& take) const;

  // The outcome of a step only the lead runs (reading or writing a directory, where one writer
  // is allowed): its error, if any, on every process (rethrow_from_root).
  void settle(const std::exception_ptr& lead_failure) const;
  // The outcome of a step every process runs, any of which may fail: the lead's error where it
  // had one; else a failed process rethrows its own and the others stop (StoppedWithRoot 1).
  void settle_any(const std::exception_ptr& failure) const;

  // Runs f on the lead only and agrees on its outcome with the others (on_root: the lead is
  // rank 0, and the fields are split exactly when there are several processes).
  template <class F>
  void on_lead(F&& f) const {
    on_root(std::forward<F>(f));
  }

 private:
  Grid whole_, here_;
  bool split_ = false, lead_ = true;
};

}  // namespace gfmd
