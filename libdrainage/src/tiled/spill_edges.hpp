#pragma once
// The tiled fill's spill graph edges (tiled_fill.cpp; Barnes, Lehman & Mulla 2016): the
// whole grid's, and one tile's while it floods. Not installed.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "terrain/least_by_key.hpp"

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
// pairs: an open-addressed table, not a node per pair.
class TileEdges {
 public:
  void add(std::uint32_t a, std::uint32_t b, float z) { least_.offer(SpillEdges::key(a, b), z); }
  std::vector<SpillEdges::Entry> entries() const {
    std::vector<SpillEdges::Entry> all;
    all.reserve(least_.size());
    least_.for_each([&](std::uint64_t key, float z) { all.push_back({key, z}); });
    return all;
  }

 private:
  terrain::LeastByKey<float> least_;
};

}  // namespace drainage::tiled
