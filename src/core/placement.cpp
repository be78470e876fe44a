// Where a run's fields live: the distribution seam. See include/gfmd/core/placement.hpp.
#include "gfmd/core/placement.hpp"

#include "gfmd/core/error.hpp"
#include "gfmd/core/mpi.hpp"

namespace gfmd {

void rethrow_from_root(const std::exception_ptr& failure) {
  if (!mpi::distributed()) return;
  enum Kind : int { kNone, kInput, kSolve, kInterrupted, kOther };
  int kind = kNone;
  if (failure) try {
      std::rethrow_exception(failure);
    } catch (const InputError&) {
      kind = kInput;
    } catch (const Interrupted&) {
      kind = kInterrupted;
    } catch (const SolveError&) {
      kind = kSolve;
    } catch (...) {
      kind = kOther;
    }
  kind = mpi::from_root(kind);
  if (kind == kNone) return;
  if (failure) std::rethrow_exception(failure);
  throw StoppedWithRoot(kind == kInput ? 2 : kind == kSolve ? 3 : kind == kInterrupted ? 4 : 1);
}

Placement Placement::of(const Grid& whole) {
  Placement p;
  p.whole_ = whole;
  p.split_ = mpi::distributed();
  p.lead_ = mpi::root();
  p.here_ = p.split_ ? mpi::slab_of(whole) : whole;
  return p;
}

int Placement::processes() const { return split_ ? mpi::size() : 1; }

bool Placement::agreed(bool v) const { return split_ ? mpi::from_root(v ? 1 : 0) == 1 : v; }
int Placement::agreed(int v) const { return split_ ? mpi::from_root(v) : v; }
std::string Placement::agreed(const std::string& v) const { return split_ ? mpi::from_root(v) : v; }
bool Placement::any(bool v) const { return split_ ? mpi::any_bits(v ? 1u : 0u) != 0 : v; }

RealField Placement::spread(const RealField& whole_on_lead) const {
  return split_ ? mpi::scatter(here_, whole_on_lead) : whole_on_lead;
}

RealField Placement::rows(const RealField& whole) const {
  return split_ ? mpi::rows_of(here_, whole) : whole;
}

void Placement::collect(std::initializer_list<RealField*> fields) const {
  if (!split_) return;
  for (RealField* f : fields)
    if (any(!f->empty())) *f = mpi::gather(here_, *f);
}

void Placement::collect(std::vector<unsigned char>& flags) const {
  if (split_ && any(!flags.empty())) flags = mpi::gather(here_, flags);
}

RealField Placement::whole_of(const RealField& local) const {
  return split_ ? mpi::gather(here_, local) : local;
}

void Placement::each_whole(const std::vector<const RealField*>& fields,
                           const std::function<void(std::size_t, const RealField&)>& take) const {
  for (std::size_t k = 0; k < fields.size(); ++k) {
    if (!split_) {
      take(k, *fields[k]);
      continue;
    }
    const RealField whole = mpi::gather(here_, *fields[k]);
    if (lead_) take(k, whole);
  }
}

void Placement::settle(const std::exception_ptr& lead_failure) const {
  if (!split_) {
    if (lead_failure) std::rethrow_exception(lead_failure);
    return;
  }
  rethrow_from_root(lead_failure);
}

void Placement::settle_any(const std::exception_ptr& failure) const {
  if (!split_) {
    if (failure) std::rethrow_exception(failure);
    return;
  }
  if (!any(failure != nullptr)) return;
  rethrow_from_root(lead_ ? failure : nullptr);
  // The lead went through: a process of its own failed (it reports), the others stop.
  if (failure) std::rethrow_exception(failure);
  throw StoppedWithRoot(1);
}

}  // namespace gfmd
