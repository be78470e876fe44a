// Run directories' checkpoints: the solver state with its input, written and read back (its
// status, lock and finished result: run_dir_state.cpp). See include/gfmd/case/run_dir.hpp.
#include "gfmd/case/run_dir.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <numbers>
#include <set>
#include <sstream>

#include "gfmd/case/run_directory.hpp"
#include "gfmd/contact/solver.hpp"
#include "gfmd/core/error.hpp"
#include "gfmd/core/files.hpp"
#include "gfmd/io/netcdf.hpp"
#include "gfmd/version.hpp"
namespace gfmd {

namespace fs = std::filesystem;

namespace {
// Version 2 adds the iterations and wall time done so far (a resumed run reports totals);
// version 3 the solves' state (SolveResume) after the three fields: the length of its
// numbers, the numbers (encode_resume_numbers), its fields (resume_fields).
constexpr char kCheckpointMagic[8] = {'G', 'F', 'M', 'D', 'C', 'K', 'P', '3'};

// Bytes of plain numbers, appended and read back in order.
struct Bytes {
  std::string buf;
  template <class T>
  void put(const T& v) {
    buf.append(reinterpret_cast<const char*>(&v), sizeof(T));
  }
  template <class T>
  void put_vector(const std::vector<T>& v) {
    put(static_cast<std::uint64_t>(v.size()));
    for (const T& x : v) put(x);
  }
};
struct Unbytes {
  const std::string& data;
  std::size_t pos = 0;
  template <class T>
  bool get(T& v) {
    if (pos + sizeof(T) > data.size()) return false;
    std::memcpy(&v, data.data() + pos, sizeof(T));
    pos += sizeof(T);
    return true;
  }
  bool get(bool& v) {
    std::uint8_t b = 0;
    if (!get(b) || b > 1) return false;
    v = b != 0;
    return true;
  }
  template <class T>
  bool get_vector(std::vector<T>& v) {
    std::uint64_t len = 0;
    if (!get(len) || len > (data.size() - pos) / sizeof(T)) return false;
    v.resize(len);
    for (T& x : v)
      if (!get(x)) return false;
    return true;
  }
};
void put_bool(Bytes& b, bool v) { b.put(static_cast<std::uint8_t>(v ? 1 : 0)); }

bool derivative_from(std::int32_t v, SlipDerivative& d) {
  if (v < 0 || v > static_cast<std::int32_t>(SlipDerivative::Upwind2)) return false;
  d = static_cast<SlipDerivative>(v);
  return true;
}

// The kinds of the state's fields in order (resume_fields): F whole, S the support (whole;
// says which points the C fields are stored at), C on the support only.
std::string field_kinds(bool reference, bool adhesive, const FrictionRestart* fr,
                        const AdhesiveRestart* ar = nullptr) {
  std::string k = reference ? "F" : "";
  if (adhesive) k += reference ? "FF" : "F";
  if (ar) k += std::string(2 + (ar->mixer ? 2 + 2 * ar->mixer_slots.size() : 0), 'F');
  if (!fr) return k;
  k += 'S';
  if (fr->have_z) k += "FF";
  if (fr->mixer) k += std::string(4 + 2 * fr->mixer_slots.size(), 'C');
  return k;
}

template <class Field, class Restart, class AdhRestart>
std::vector<Field*> fields_of(Field* reference_pressure, Field* reference_adhesion, Field* adhesion,
                              Restart* fr, AdhRestart* ar) {
  std::vector<Field*> out;
  if (reference_pressure) out.push_back(reference_pressure);
  if (reference_pressure && reference_adhesion) out.push_back(reference_adhesion);
  if (adhesion) out.push_back(adhesion);
  if (ar) {
    out.push_back(&ar->repulsion);
    out.push_back(&ar->kept);
    if (ar->mixer) {
      out.push_back(&ar->xprev);
      out.push_back(&ar->fprev);
      for (std::size_t k = 0; k < ar->df.size() && k < ar->dx.size(); ++k) {
        out.push_back(&ar->df[k]);
        out.push_back(&ar->dx[k]);
      }
    }
  }
  if (!fr) return out;
  out.push_back(&fr->support);
  if (fr->have_z) {
    out.push_back(&fr->zx);
    out.push_back(&fr->zy);
  }
  if (fr->mixer) {
    for (Field* f : {&fr->xprev_x, &fr->xprev_y, &fr->fprev_x, &fr->fprev_y}) out.push_back(f);
    for (std::size_t k = 0; k < fr->df.size() && k < fr->dx.size(); ++k) {
      out.push_back(&fr->df[k]);
      out.push_back(&fr->dx[k]);
    }
  }
  return out;
}
}  // namespace

std::vector<const RealField*> resume_fields(const RealField* reference_pressure,
                                            const RealField* reference_adhesion, const RealField* adhesion,
                                            const FrictionRestart* friction,
                                            const AdhesiveRestart* adhesive_restart) {
  return fields_of<const RealField>(reference_pressure, reference_adhesion, adhesion, friction,
                                    adhesive_restart);
}
std::vector<RealField*> resume_fields(RealField* reference_pressure, RealField* reference_adhesion,
                                      RealField* adhesion, FrictionRestart* friction,
                                      AdhesiveRestart* adhesive_restart) {
  return fields_of<RealField>(reference_pressure, reference_adhesion, adhesion, friction, adhesive_restart);
}
namespace {
template <class State>
auto fields_of_state(State& st) {
  auto* ref = st.reference ? &*st.reference : nullptr;
  return resume_fields(ref ? &ref->pressure : nullptr, ref && st.adhesive ? &ref->adhesion : nullptr,
                       st.adhesive ? &st.adhesion : nullptr, st.friction ? &*st.friction : nullptr,
                       st.adhesive_restart ? &*st.adhesive_restart : nullptr);
}
}  // namespace
std::vector<RealField*> resume_fields(SolveResume& st) { return fields_of_state(st); }
std::vector<const RealField*> resume_fields(const SolveResume& st) { return fields_of_state(st); }

std::string encode_resume_numbers(const SolveInfo* ref, const FrictionRestart* fr, bool adhesive,
                                  const AdhesiveRestart* ar) {
  Bytes b;
  // Flags: 1 a reference, 2 a friction restart, 4 adhesive tractions among the fields, 8 the
  // restart's adhesive step count at the end (checkpoints before it lack it: 0 steps), 16 an
  // adhesive restart point (frictionless, with 4; its numbers last).
  b.put(static_cast<std::uint32_t>((ref ? 1u : 0u) | (fr ? 2u | 8u : 0u) | (adhesive ? 4u : 0u) |
                                   (ar && adhesive ? 16u : 0u)));
  if (ref) {
    b.put(static_cast<std::int32_t>(ref->iterations));
    b.put(static_cast<std::int32_t>(ref->outer_iterations));
    b.put(static_cast<std::int32_t>(ref->tangential_iterations));
    b.put(static_cast<std::int32_t>(ref->slip_derivative));
    for (double v : {ref->approach, ref->pk_error, ref->friction_error, ref->wall_time_s, ref->fft_seconds,
                     ref->stiffness})
      b.put(v);
    b.put(static_cast<std::uint64_t>(ref->transforms));
  }
  if (fr) {
    for (std::int32_t v : {fr->outer, fr->iterations, fr->tangential_iterations}) b.put(v);
    for (double v : {fr->error, fr->mixing, fr->stick_points}) b.put(v);
    for (bool v : {fr->tangential_ok, fr->have_slip, fr->have_z}) put_bool(b, v);
    b.put(static_cast<std::int32_t>(fr->derivative));
    put_bool(b, fr->steps.stick_mode);
    b.put(static_cast<std::int32_t>(fr->steps.turn));
    b.put(static_cast<std::int32_t>(fr->steps.near_stick));
    b.put(fr->steps.best);
    b.put(static_cast<std::int32_t>(fr->steps.since_best));
    b.put(fr->gw_mean_ref);
    b.put(fr->g_mean_ref);
    b.put(fr->pk_iterations);
    b.put(fr->pk_error);
    b.put(fr->pk_delta);
    put_bool(b, fr->pk_converged);
    b.put_vector(fr->history_change);
    b.put_vector(fr->history_force);
    put_bool(b, fr->mixer);
    put_bool(b, fr->mixer_have_prev);
    b.put_vector(fr->mixer_slots);
    b.put_vector(fr->mixer_gram);
    b.put(fr->adhesion_steps);
  }
  if (ar && adhesive) {
    for (std::int32_t v : {ar->step, ar->used, ar->pre_iterations, ar->iterations, ar->adhesion_steps,
                           ar->viscoelastic_steps, ar->guard.rejected, ar->guard.plain_left})
      b.put(v);
    for (double v : {ar->change, ar->capped_delta, ar->guard.kept_change, ar->gw_mean_ref, ar->g_mean_ref})
      b.put(v);
    for (bool v : {ar->capped_found, ar->capped_acted, ar->guard.mixed, ar->mixer, ar->mixer_have_prev})
      put_bool(b, v);
    b.put_vector(ar->mixer_slots);
    b.put_vector(ar->mixer_gram);
  }
  return b.buf;
}

bool decode_resume_numbers(const std::string& bytes, SolveResume& state) {
  Unbytes u{bytes};
  std::uint32_t flags = 0;
  if (!u.get(flags) || flags > 31 || ((flags & 8u) && !(flags & 2u)) ||
      ((flags & 16u) && (!(flags & 4u) || (flags & 2u))))
    return false;
  state = SolveResume{};
  state.adhesive = (flags & 4u) != 0;
  if (flags & 1u) {
    SolveInfo& i = state.reference.emplace().info;
    std::int32_t it = 0, outer = 0, tang = 0, deriv = 0;
    std::uint64_t transforms = 0;
    if (!u.get(it) || !u.get(outer) || !u.get(tang) || !u.get(deriv) ||
        !derivative_from(deriv, i.slip_derivative))
      return false;
    for (double* v :
         {&i.approach, &i.pk_error, &i.friction_error, &i.wall_time_s, &i.fft_seconds, &i.stiffness})
      if (!u.get(*v)) return false;
    if (!u.get(transforms) || it < 0 || outer < 0 || tang < 0) return false;
    i.iterations = it;
    i.outer_iterations = outer;
    i.tangential_iterations = tang;
    i.transforms = transforms;
    i.converged = true;
    i.status = "converged";
  }
  if (flags & 2u) {
    FrictionRestart& f = state.friction.emplace();
    std::int32_t deriv = 0, turn = 0, near = 0, since = 0;
    bool ok = u.get(f.outer) && u.get(f.iterations) && u.get(f.tangential_iterations) && u.get(f.error) &&
              u.get(f.mixing) && u.get(f.stick_points) && u.get(f.tangential_ok) && u.get(f.have_slip) &&
              u.get(f.have_z) && u.get(deriv) && derivative_from(deriv, f.derivative) &&
              u.get(f.steps.stick_mode) && u.get(turn) && u.get(near) && u.get(f.steps.best) &&
              u.get(since) && u.get(f.gw_mean_ref) && u.get(f.g_mean_ref) && u.get(f.pk_iterations) &&
              u.get(f.pk_error) && u.get(f.pk_delta) && u.get(f.pk_converged) &&
              u.get_vector(f.history_change) && u.get_vector(f.history_force) && u.get(f.mixer) &&
              u.get(f.mixer_have_prev) && u.get_vector(f.mixer_slots) && u.get_vector(f.mixer_gram);
    if (!ok || f.outer < 0 || f.iterations < 0 || f.tangential_iterations < 0 || !(f.mixing > 0) ||
        !std::isfinite(f.error) || !std::isfinite(f.gw_mean_ref) || !std::isfinite(f.g_mean_ref) ||
        f.history_change.size() != f.history_force.size())
      return false;
    f.steps.turn = turn;
    f.steps.near_stick = near;
    f.steps.since_best = since;
    for (const std::int32_t sl : f.mixer_slots)
      if (sl < 0 || static_cast<std::size_t>(sl) * static_cast<std::size_t>(sl) >= f.mixer_gram.size())
        return false;
    if (f.mixer) {
      f.df.resize(f.mixer_slots.size());
      f.dx.resize(f.mixer_slots.size());
    }
    if ((flags & 8u) && (!u.get(f.adhesion_steps) || f.adhesion_steps < 0)) return false;
  }
  if (flags & 16u) {
    AdhesiveRestart& a = state.adhesive_restart.emplace();
    bool ok = true;
    for (std::int32_t* v : {&a.step, &a.used, &a.pre_iterations, &a.iterations, &a.adhesion_steps,
                            &a.viscoelastic_steps, &a.guard.rejected, &a.guard.plain_left})
      ok = ok && u.get(*v) && *v >= 0;
    for (double* v : {&a.change, &a.capped_delta, &a.guard.kept_change, &a.gw_mean_ref, &a.g_mean_ref})
      ok = ok && u.get(*v);
    for (bool* v : {&a.capped_found, &a.capped_acted, &a.guard.mixed, &a.mixer, &a.mixer_have_prev})
      ok = ok && u.get(*v);
    ok = ok && u.get_vector(a.mixer_slots) && u.get_vector(a.mixer_gram);
    if (!ok || !std::isfinite(a.change) || !std::isfinite(a.capped_delta) ||
        std::isnan(a.guard.kept_change) || !std::isfinite(a.gw_mean_ref) || !std::isfinite(a.g_mean_ref))
      return false;
    for (const std::int32_t sl : a.mixer_slots)
      if (sl < 0 || static_cast<std::size_t>(sl) * static_cast<std::size_t>(sl) >= a.mixer_gram.size())
        return false;
    if (a.mixer) {
      a.df.resize(a.mixer_slots.size());
      a.dx.resize(a.mixer_slots.size());
    }
  }
  return u.pos == bytes.size();
}

CheckpointStream::CheckpointStream(const std::string& path, const Config& cfg,
                                   const CheckpointProgress& progress)
    : file_(path), n_(cfg.grid.size()) {
  const std::string input = cfg.to_json().dump();
  std::string buf(kCheckpointMagic, 8);
  const auto put = [&buf](const void* p, std::size_t n) { buf.append(static_cast<const char*>(p), n); };
  const std::uint64_t len = input.size();
  const std::int32_t nx = cfg.grid.nx, ny = cfg.grid.ny;
  put(&nx, 4);
  put(&ny, 4);
  put(&len, 8);
  buf += input;
  put(&progress.iterations, 8);
  put(&progress.wall_time_s, 8);
  file_.append_bytes(buf.data(), buf.size());
}

void CheckpointStream::add(const RealField& field) {
  if (added_ < 3) {
    ++added_;
    if (field.size() == n_) {
      file_.append_bytes(field.data(), n_ * sizeof(double));
      return;
    }
    const std::vector<double> zeros(n_, 0.0);
    file_.append_bytes(zeros.data(), n_ * sizeof(double));
    return;
  }
  if (!state_ || kinds_.empty()) throw std::logic_error("CheckpointStream: a field more than the state has");
  if (field.size() != n_) throw std::logic_error("CheckpointStream: a state field of the wrong size");
  const char kind = kinds_.front();
  kinds_.erase(0, 1);
  if (kind == 'S') {
    on_support_.assign(n_, 0);
    support_points_ = 0;
    for (std::size_t i = 0; i < n_; ++i)
      if (field[i] >= 0) {
        on_support_[i] = 1;
        ++support_points_;
      }
  }
  if (kind != 'C') {
    file_.append_bytes(field.data(), n_ * sizeof(double));
    return;
  }
  std::vector<double> packed;
  packed.reserve(support_points_);
  for (std::size_t i = 0; i < n_; ++i)
    if (on_support_[i]) packed.push_back(field[i]);
  file_.append_bytes(packed.data(), packed.size() * sizeof(double));
}

void CheckpointStream::add_state(const SolveInfo* reference_info, const FrictionRestart* friction,
                                 bool adhesive, const AdhesiveRestart* adhesive_restart) {
  if (added_ != 3 || state_)
    throw std::logic_error("CheckpointStream: the state goes after the three fields");
  state_ = true;
  const AdhesiveRestart* ar = adhesive ? adhesive_restart : nullptr;
  const std::string numbers = encode_resume_numbers(reference_info, friction, adhesive, ar);
  const std::uint64_t len = numbers.size();
  file_.append_bytes(&len, 8);
  file_.append_bytes(numbers.data(), numbers.size());
  kinds_ = field_kinds(reference_info != nullptr, adhesive, friction, ar);
}

void CheckpointStream::commit() {
  if (added_ != 3) throw std::logic_error("CheckpointStream: pressure, tx and ty are needed");
  if (!state_) add_state(nullptr, nullptr);
  if (!kinds_.empty()) throw std::logic_error("CheckpointStream: the state's fields are missing");
  file_.sync_tmp();
  file_.commit();
}

void write_checkpoint(const std::string& path, const Config& cfg, const ContactFields& f,
                      const CheckpointProgress& progress) {
  CheckpointStream s(path, cfg, progress);
  for (const RealField* fld : {&f.pressure, &f.tx, &f.ty}) s.add(*fld);
  if (progress.state) {
    const SolveResume& st = *progress.state;
    s.add_state(st.reference ? &st.reference->info : nullptr, st.friction ? &*st.friction : nullptr,
                st.adhesive, st.adhesive_restart ? &*st.adhesive_restart : nullptr);
    for (const RealField* fld : resume_fields(st)) s.add(*fld);
  }
  s.commit();
}

namespace {
// The keys whose values differ between a checkpoint's input and the case now (at most four
// named), e.g. "friction.coefficient (0.5 in the checkpoint, now 1)".
std::string input_difference(const std::string& old_text, const Config& cfg) {
  nlohmann::json old_json;
  try {
    old_json = nlohmann::json::parse(old_text);
  } catch (const std::exception&) {
    return "its input record is damaged";
  }
  const nlohmann::json a = old_json.flatten(), b = cfg.to_json().flatten();
  std::vector<std::string> keys;
  const auto key = [](const std::string& pointer) {
    std::string k = pointer.substr(1);
    std::replace(k.begin(), k.end(), '/', '.');
    return k;
  };
  for (const auto& [k, v] : b.items())
    if (!a.contains(k) || a[k] != v)
      keys.push_back(key(k) + " (" + (a.contains(k) ? a[k].dump() : std::string("absent")) +
                     " in the checkpoint, now " + v.dump() + ")");
  for (const auto& [k, v] : a.items())
    if (!b.contains(k)) keys.push_back(key(k) + " (" + v.dump() + " in the checkpoint, now absent)");
  if (keys.empty()) return "it was written for another input";
  std::string s = "it was written for another case: ";
  for (std::size_t i = 0; i < keys.size() && i < 4; ++i) s += (i ? "; " : "") + keys[i];
  if (keys.size() > 4) s += "; and " + std::to_string(keys.size() - 4) + " more";
  return s;
}
}  // namespace

bool read_checkpoint(const std::string& path, const Config& cfg, ContactFields& f,
                     CheckpointProgress* progress, std::string* why) {
  // Past the input's check, a refusal means a damaged or truncated file.
  const auto refused = [why](const std::string& reason) {
    if (why) *why = reason;
    return false;
  };
  if (why) *why = "the checkpoint is damaged or incomplete";
  std::ifstream in(path, std::ios::binary);
  if (!in) return refused(fs::exists(path) ? "the checkpoint cannot be read" : "there is no checkpoint");
  std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::size_t pos = 0;
  const auto get = [&](void* p, std::size_t n) {
    if (n > data.size() - pos) return false;
    std::memcpy(p, data.data() + pos, n);
    pos += n;
    return true;
  };
  char magic[8] = {};
  std::int32_t nx = 0, ny = 0;
  std::uint64_t len = 0;
  if (!get(magic, 8) || std::memcmp(magic, kCheckpointMagic, 8) != 0)
    return refused(std::memcmp(magic, kCheckpointMagic, 6) == 0
                       ? "it was written by another version of gfmd (another checkpoint format)"
                       : "the checkpoint is not a gfmd checkpoint");
  if (!get(&nx, 4) || !get(&ny, 4) || !get(&len, 8)) return false;
  if (nx != cfg.grid.nx || ny != cfg.grid.ny)
    return refused("it was written for a " + std::to_string(nx) + " x " + std::to_string(ny) +
                   " grid, the case has " + std::to_string(cfg.grid.nx) + " x " +
                   std::to_string(cfg.grid.ny));
  if (len > data.size() - pos) return false;
  const std::string input = data.substr(pos, len);
  pos += len;
  if (input != cfg.to_json().dump()) return refused(input_difference(input, cfg));
  CheckpointProgress done;
  if (!get(&done.iterations, 8) || !get(&done.wall_time_s, 8)) return false;
  if (done.iterations < 0 || !(done.wall_time_s >= 0) || !std::isfinite(done.wall_time_s)) return false;
  const std::size_t n = cfg.grid.size();
  const auto read_field = [&](RealField& fld, std::size_t count) {
    if (count > (data.size() - pos) / sizeof(double)) return false;
    fld.resize(count);
    return get(fld.data(), count * sizeof(double));
  };
  const auto finite = [](const RealField& fld) {
    return std::all_of(fld.begin(), fld.end(), [](double v) { return std::isfinite(v); });
  };
  ContactFields read;
  for (RealField* fld : {&read.pressure, &read.tx, &read.ty})
    if (!read_field(*fld, n) || !finite(*fld)) return false;
  // The state: its numbers, then its fields (those of kind C on the support only).
  std::uint64_t nlen = 0;
  if (!get(&nlen, 8) || nlen > data.size() - pos) return false;
  auto state = std::make_shared<SolveResume>();
  if (!decode_resume_numbers(data.substr(pos, nlen), *state)) return false;
  pos += nlen;
  if (state->friction && state->friction->mixer) {
    // solver.anderson's history, or the deeper one a stalled solve went on with.
    const std::size_t g = state->friction->mixer_gram.size();
    const auto m = static_cast<std::size_t>(std::lround(std::sqrt(static_cast<double>(g))));
    if (m * m != g || !history_depth_fits(cfg.solver.anderson, static_cast<int>(m))) return false;
  }
  FrictionRestart* fr = state->friction ? &*state->friction : nullptr;
  const std::vector<RealField*> fields = resume_fields(*state);
  const std::string kinds = field_kinds(state->reference.has_value(), state->adhesive, fr,
                                        state->adhesive_restart ? &*state->adhesive_restart : nullptr);
  if (kinds.size() != fields.size()) return false;
  std::vector<std::size_t> support;
  for (std::size_t k = 0; k < fields.size(); ++k) {
    RealField& fld = *fields[k];
    if (kinds[k] != 'C') {
      if (!read_field(fld, n)) return false;
    } else {
      RealField packed;
      if (!read_field(packed, support.size())) return false;
      fld.assign(n, 0.0);
      for (std::size_t j = 0; j < support.size(); ++j) fld[support[j]] = packed[j];
    }
    if (kinds[k] == 'S') {
      for (std::size_t i = 0; i < n; ++i) {
        const double v = fld[i];
        if (!(v == -1.0 || (v >= 0 && v <= 1e9 && v == std::floor(v)))) return false;
        if (v >= 0) support.push_back(i);
      }
    } else if (fr && fr->mixer && k + 2 * fr->mixer_slots.size() >= fields.size()) {
      // df and dx: two floats packed per point.
      for (const double v : fld) {
        float x, y;
        unpack_floats(v, x, y);
        if (!std::isfinite(x) || !std::isfinite(y)) return false;
      }
    } else if (!finite(fld)) {
      return false;
    }
  }
  if (pos != data.size()) return false;
  f.pressure = std::move(read.pressure);
  f.tx = std::move(read.tx);
  f.ty = std::move(read.ty);
  if (progress) {
    if (state->reference || state->friction || state->adhesive) done.state = std::move(state);
    *progress = std::move(done);
  }
  return true;
}

}  // namespace gfmd
