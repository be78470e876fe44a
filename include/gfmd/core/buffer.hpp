// Vectors whose elements are left uninitialised when they are created or grown.
//
// A std::vector<double>(n) writes n zeros on the calling thread before any parallel loop
// fills it, so that thread alone faults in every page of a fresh grid-sized array (on a
// virtual machine that is the dominant cost of touching new memory). With Buffer<T> the
// parallel loop that fills the array touches it first and the page faults are shared
// among the threads. Only for arithmetic types; every element must be written before it
// is read (assign(n, v) and the other value-taking members still initialise).
#pragma once

#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

namespace gfmd {

template <class T>
struct DefaultInitAllocator : std::allocator<T> {
  using value_type = T;
  template <class U>
  struct rebind {
    using other = DefaultInitAllocator<U>;
  };
  DefaultInitAllocator() = default;
  template <class U>
  DefaultInitAllocator(const DefaultInitAllocator<U>&) noexcept {}  // NOLINT
  template <class U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
    ::new (static_cast<void*>(p)) U;  // default-initialisation: no value for arithmetic U
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

template <class T>
using Buffer = std::vector<T, DefaultInitAllocator<T>>;

}  // namespace gfmd
