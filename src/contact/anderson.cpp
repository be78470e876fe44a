// Anderson acceleration: the ring of differences and the small least-squares solve.
#include "gfmd/contact/anderson.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace gfmd {

AndersonMixer::AndersonMixer(int depth) : m_(depth) {
  if (depth < 1) throw std::invalid_argument("AndersonMixer: depth must be >= 1");
  df_.resize(static_cast<std::size_t>(m_));
  dx_.resize(static_cast<std::size_t>(m_));
  gram_.assign(static_cast<std::size_t>(m_) * static_cast<std::size_t>(m_), 0.0);
}

GuardedAnderson::GuardedAnderson(int depth, const Grid& grid) {
  if (depth <= 0) return;
  const std::size_t n = grid.local_size();
  mixer_ = std::make_unique<AndersonMixer>(depth);
  mixer_->resize(n);
  const auto rows = static_cast<std::size_t>(grid.rows());
  start_.resize(rows + 1);
  for (std::size_t r = 0; r <= rows; ++r) start_[r] = static_cast<std::uint32_t>(r * grid.nx);
  order_.resize(n);
  for (std::size_t e = 0; e < n; ++e) order_[e] = static_cast<std::uint32_t>(e);
  mixer_->group_by_rows(&grid, &start_, &order_);
}

void GuardedAnderson::restart() {
  if (mixer_) mixer_->restart();
  guard_.restart();
}

void GuardedAnderson::advance(RealField& x, const RealField& image, double change, double lo, double hi) {
  const auto n = static_cast<std::ptrdiff_t>(x.size());
  switch (guard_.next(change, mixer_ != nullptr)) {
    case AndersonGuard::Step::Plain:
      parallel_for(n, [&](std::ptrdiff_t i) { x[i] = image[i]; });
      return;
    case AndersonGuard::Step::Reject:
      parallel_for(n, [&](std::ptrdiff_t i) { x[i] = kept_[i]; });
      mixer_->restart();
      return;
    case AndersonGuard::Step::Mix:
      break;
  }
  kept_.assign(image.begin(), image.end());
  mixer_->step(
      1.0, [&](std::size_t e) { return x[e]; }, [&](std::size_t e) { return image[e]; },
      [&](std::size_t e, double v) { x[e] = std::clamp(v, lo, hi); });
  guard_.mixed(mixer_->history() > 0);
}

void AndersonMixer::resize(std::size_t len) {
  grow(xprev_, len);
  grow(fprev_, len);
  for (std::size_t sl : slots_) {
    grow(df_[sl], len);
    grow(dx_[sl], len);
  }
}

void AndersonMixer::restore(bool have_prev, const std::vector<std::size_t>& slots,
                            const std::vector<double>& gram) {
  const auto mm = static_cast<std::size_t>(m_);
  if (slots.size() > mm || gram.size() != mm * mm)
    throw std::invalid_argument("AndersonMixer::restore: a state of another depth");
  std::vector<bool> used(mm, false);
  for (std::size_t sl : slots) {
    if (sl >= mm || used[sl]) throw std::invalid_argument("AndersonMixer::restore: bad slots");
    used[sl] = true;
  }
  have_prev_ = have_prev;
  slots_ = slots;
  gram_ = gram;
  for (std::size_t sl : slots_) {
    grow(df_[sl], xprev_.size());
    grow(dx_[sl], xprev_.size());
  }
}

std::size_t AndersonMixer::next_slot() {
  std::size_t slot = 0;
  if (slots_.size() == static_cast<std::size_t>(m_)) {
    slot = slots_.front();
    slots_.erase(slots_.begin());
  } else {
    std::vector<bool> used(static_cast<std::size_t>(m_), false);
    for (std::size_t sl : slots_) used[sl] = true;
    while (used[slot]) ++slot;
  }
  slots_.push_back(slot);
  return slot;
}

std::vector<double> AndersonMixer::coefficients(const std::vector<double>& rhs) const {
  const std::size_t h = rhs.size();
  if (h == 0) return {};
  const auto mm = static_cast<std::size_t>(m_);
  std::vector<double> M(h * h);
  for (std::size_t r = 0; r < h; ++r)
    for (std::size_t c = 0; c < h; ++c) M[r * h + c] = gram_[slots_[r] * mm + slots_[c]];
  return anderson_solve_small(std::move(M), rhs);
}

std::vector<double> anderson_solve_small(std::vector<double> M, std::vector<double> rhs) {
  // Tikhonov shift relative to the trace, then Gaussian elimination with partial pivoting.
  const std::size_t h = rhs.size();
  double trace = 0;
  for (std::size_t a = 0; a < h; ++a) trace += M[a * h + a];
  for (std::size_t a = 0; a < h; ++a) M[a * h + a] += 1e-10 * trace + 1e-300;
  for (std::size_t c = 0; c < h; ++c) {
    std::size_t piv = c;
    for (std::size_t r = c + 1; r < h; ++r)
      if (std::abs(M[r * h + c]) > std::abs(M[piv * h + c])) piv = r;
    if (piv != c) {
      for (std::size_t k = 0; k < h; ++k) std::swap(M[c * h + k], M[piv * h + k]);
      std::swap(rhs[c], rhs[piv]);
    }
    for (std::size_t r = c + 1; r < h; ++r) {
      const double fct = M[r * h + c] / M[c * h + c];
      for (std::size_t k = c; k < h; ++k) M[r * h + k] -= fct * M[c * h + k];
      rhs[r] -= fct * rhs[c];
    }
  }
  std::vector<double> x(h);
  for (std::size_t c = h; c-- > 0;) {
    double v = rhs[c];
    for (std::size_t k = c + 1; k < h; ++k) v -= M[c * h + k] * x[k];
    x[c] = v / M[c * h + c];
  }
  return x;
}

}  // namespace gfmd
