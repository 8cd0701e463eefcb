#pragma once
// BigVector: std::vector for grid-sized arrays (one element per sample or vertex).
//
// resize(n) default-initializes (leaves trivial elements uninitialized): use assign(n,
// value) when the values matter, resize when every element is written next. Zeroing a
// 10-100 M element array that is written next anyway costs as much as the algorithms
// that fill it, and first touch is the only touch.
//
// No transparent huge pages: on virtual machines with free page reporting a cold 2 MiB page
// costs several times more per byte than 4 KiB pages, and the first run after a pause pays
// for it (docs/build-drainage.md, "Speed against GRASS r.watershed").
#include <cstddef>
#include <memory>
#include <new>
#include <utility>
#include <vector>

namespace terrain {

template <class T>
struct BigAllocator {
  using value_type = T;

  BigAllocator() = default;
  template <class U>
  BigAllocator(const BigAllocator<U>&) noexcept {}

  T* allocate(std::size_t n) { return std::allocator<T>().allocate(n); }
  void deallocate(T* p, std::size_t n) noexcept { std::allocator<T>().deallocate(p, n); }
  template <class U>
  void construct(U* p) noexcept(noexcept(::new (static_cast<void*>(p)) U)) {
    ::new (static_cast<void*>(p)) U;  // default-initialization: no zeroing
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
  template <class U>
  bool operator==(const BigAllocator<U>&) const noexcept {
    return true;
  }
};

template <class T>
using BigVector = std::vector<T, BigAllocator<T>>;

}  // namespace terrain
