#pragma once
// The tiled fill's spill graph edges (tiled_fill.cpp; Barnes, Lehman & Mulla 2016): the
// whole grid's, and one tile's while it floods. Not installed.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace drainage::tiled {

// The spill graph's edges: pairs of labels and the lowest elevation at which they meet. A
// tile's own edges are gathered in TileEdges while it floods (each pair many times), the
// whole grid's in a flat list, merged (sorted, each pair once with its least elevation)
// whenever it doubles: 16 bytes an edge instead of a hash node's 50 or more.
class SpillEdges {
 public:
  struct Entry {
    std::uint64_t key;  // the two labels, smaller first
    float z;
  };
  static std::uint64_t key(std::uint32_t a, std::uint32_t b) {
    return a < b ? (std::uint64_t(a) << 32 | b) : (std::uint64_t(b) << 32 | a);
  }
  void add(std::uint32_t a, std::uint32_t b, float z) { add(Entry{key(a, b), z}); }
  void add(const Entry& e) {
    list_.push_back(e);
    if (list_.size() >= 2 * merged_ + 1024) merge();
  }
  // Each pair once, with its least elevation.
  const std::vector<Entry>& entries() {
    merge();
    return list_;
  }
  void clear() { std::vector<Entry>().swap(list_), merged_ = 0; }

 private:
  void merge() {
    std::sort(list_.begin(), list_.end(), [](const Entry& x, const Entry& y) {
      return x.key < y.key || (x.key == y.key && x.z < y.z);
    });
    list_.erase(std::unique(list_.begin(), list_.end(),
                            [](const Entry& x, const Entry& y) { return x.key == y.key; }),
                list_.end());
    merged_ = list_.size();
  }
  std::vector<Entry> list_;
  std::size_t merged_ = 0;
};

// One tile's edges while it floods: each meeting of two labels, kept once per pair with its
// least elevation. A flood of 2048 x 2048 cells meets about 3.3 M times but only about 21 k
// pairs, so the pairs are kept in an open-addressed table (linear probing, at most half
// full), not a node per pair.
class TileEdges {
 public:
  void add(std::uint32_t a, std::uint32_t b, float z) {
    const std::uint64_t k = SpillEdges::key(a, b);  // never kEmpty: a != b
    for (std::size_t s = slot(k);; s = (s + 1) & mask_) {
      Slot& e = table_[s];
      if (e.key == k) {
        e.z = std::min(e.z, z);
        return;
      }
      if (e.key == kEmpty) {
        e = {k, z};
        if (2 * ++used_ > mask_) grow();
        return;
      }
    }
  }
  std::vector<SpillEdges::Entry> entries() const {
    std::vector<SpillEdges::Entry> all;
    all.reserve(used_);
    for (const Slot& e : table_)
      if (e.key != kEmpty) all.push_back({e.key, e.z});
    return all;
  }

 private:
  static constexpr std::uint64_t kEmpty = ~std::uint64_t(0);
  struct Slot {
    std::uint64_t key = kEmpty;
    float z = 0;
  };
  std::size_t slot(std::uint64_t k) const {  // Fibonacci hashing
    return std::size_t((k * 0x9E3779B97F4A7C15ull) >> 24) & mask_;
  }
  void grow() {
    std::vector<Slot> old(2 * table_.size());
    old.swap(table_);
    mask_ = table_.size() - 1, used_ = 0;
    for (const Slot& e : old)
      if (e.key != kEmpty) add(std::uint32_t(e.key >> 32), std::uint32_t(e.key), e.z);
  }
  std::vector<Slot> table_ = std::vector<Slot>(1024);
  std::size_t mask_ = 1023, used_ = 0;
};

}  // namespace drainage::tiled
