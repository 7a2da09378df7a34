#pragma once

#include <memory>
#include <new>
#include <type_traits>
#include <utility>

namespace omnishadow {

// std::allocator, except that resize(n) and vector(n) leave new elements of a trivial type
// uninitialized instead of zeroing them. For buffers that are written whole right after they
// are sized: a 1280x720 float frame read back from GL is 14.7 MB, and zeroing it first cost
// about 1.3 ms of every such frame. resize(n, value) and vector(n, value) still fill.
template <class T>
struct DefaultInitAllocator : std::allocator<T> {
  using value_type = T;
  template <class U>
  struct rebind {
    using other = DefaultInitAllocator<U>;
  };

  DefaultInitAllocator() noexcept = default;
  template <class U>
  DefaultInitAllocator(const DefaultInitAllocator<U>&) noexcept {}

  template <class U>
  void construct(U* at) noexcept(std::is_nothrow_default_constructible_v<U>) {
    ::new (static_cast<void*>(at)) U;
  }
  template <class U, class... Args>
  void construct(U* at, Args&&... args) {
    ::new (static_cast<void*>(at)) U(std::forward<Args>(args)...);
  }
};

template <class T, class U>
bool operator==(const DefaultInitAllocator<T>&, const DefaultInitAllocator<U>&) noexcept {
  return true;
}

}  // namespace omnishadow
