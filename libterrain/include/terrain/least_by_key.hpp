#pragma once
// For each 64-bit key, the least value offered (the first of equals), in an open-addressed
// table: linear probing, at most half full, Fibonacci hashing. For many offers to few keys
// (a tiled flood's label meetings, a frame's seed cells), where a node per key would cost
// more than the work.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace terrain {

template <class V, class Less = std::less<V>>
class LeastByKey {
 public:
  // v kept for `key` when the key is new or v is less than the value kept.
  void offer(std::uint64_t key, const V& v) {
    std::size_t s = slot(key);
    if (used_[s]) {
      if (Less{}(v, values_[s])) values_[s] = v;
      return;
    }
    if (2 * (size_ + 1) > used_.size()) grow(), s = slot(key);
    keys_[s] = key, values_[s] = v, used_[s] = 1, ++size_;
  }
  std::size_t size() const { return size_; }
  // f(key, value) for each key kept, in the table's order.
  template <class F>
  void for_each(F&& f) const {
    for (std::size_t s = 0; s < used_.size(); ++s)
      if (used_[s]) f(keys_[s], values_[s]);
  }

 private:
  std::size_t slot(std::uint64_t key) const {
    const std::size_t mask = used_.size() - 1;
    std::size_t s = std::size_t((key * 0x9E3779B97F4A7C15ull) >> 24) & mask;
    while (used_[s] && keys_[s] != key) s = (s + 1) & mask;
    return s;
  }
  void grow() {
    std::vector<std::uint64_t> keys(2 * used_.size());
    std::vector<V> values(keys.size());
    std::vector<std::uint8_t> used(keys.size(), 0);
    keys.swap(keys_), values.swap(values_), used.swap(used_);
    for (std::size_t k = 0; k < used.size(); ++k)
      if (used[k]) {
        const std::size_t s = slot(keys[k]);
        keys_[s] = keys[k], values_[s] = values[k], used_[s] = 1;
      }
  }
  std::vector<std::uint64_t> keys_ = std::vector<std::uint64_t>(1024);
  std::vector<V> values_ = std::vector<V>(1024);
  std::vector<std::uint8_t> used_ = std::vector<std::uint8_t>(1024, 0);
  std::size_t size_ = 0;
};

}  // namespace terrain
