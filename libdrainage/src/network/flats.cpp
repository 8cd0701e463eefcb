#include "drainage/flats.hpp"

#include <algorithm>
#include <limits>
#include <unordered_map>

#include "drainage/d8.hpp"

namespace drainage {

namespace {

// Barnes, Lehman and Mulla (2014)'s flat resolution on the cells involved: no-flow cells and
// their equal-elevation neighbours with a direction (the low edges). They are few on most
// terrain, so per-cell state lives in compact arrays indexed through a hash map, not in
// grid-sized arrays. Each step a member, in the order resolve_flats calls them.
class FlatResolver {
 public:
  FlatResolver(const terrain::Grid& g, D8Codes& dirs)
      : z_(g.z), dirs_(dirs), nb_{long(g.rows), long(g.cols)} {}

  // The no-flow cells; false when there are none.
  bool find_cells() {
    for (std::uint32_t i = 0; i < z_.size(); ++i)
      if (dirs_[i] == kNoFlow) cells_.push_back(i);
    if (cells_.empty()) return false;
    n_flat_ = cells_.size();
    id_.reserve(2 * n_flat_);
    for (std::uint32_t k = 0; k < n_flat_; ++k) id_.emplace(cells_[k], k);
    return true;
  }

  // 1-2. High edges (no flow, beside a strictly higher sample) and low edges (a
  // direction, beside a no-flow sample of equal elevation), in ascending cell order.
  void find_edges() {
    for (std::uint32_t k = 0; k < n_flat_; ++k) {
      const std::uint32_t i = cells_[k];
      bool is_high = false;
      nb_.each_in_try_order(i, [&](std::uint32_t j, int) {
        if (dirs_[j] == kNodata) return;
        if (z_[j] > z_[i]) is_high = true;
        if (dirs_[j] != kNoFlow && z_[j] == z_[i] && id_.find(j) == id_.end()) {
          id_.emplace(j, std::uint32_t(cells_.size()));
          cells_.push_back(j);
        }
      });
      if (is_high) high_.push_back(k);
    }
    for (std::uint32_t k = std::uint32_t(n_flat_); k < cells_.size(); ++k) low_.push_back(k);
    std::sort(low_.begin(), low_.end(),
              [&](std::uint32_t a, std::uint32_t b) { return cells_[a] < cells_[b]; });
  }

  // 3. Label flats by flood fill over equal elevation: first from the low edges
  // (drainable flats, low edges included), then from the remaining no-flow cells
  // (undrainable flats).
  void label_flats(FlatStats& stats) {
    label_.assign(cells_.size(), kNone);
    for (std::uint32_t k : low_)
      if (label_[k] == kNone) {
        flood(k, next_++);
        drainable_.push_back(1);
      }
    for (std::uint32_t k = 0; k < n_flat_; ++k)
      if (label_[k] == kNone) {
        flood(k, next_++);
        drainable_.push_back(0);
      }
    for (std::uint32_t l = 1; l < next_; ++l) {
      if (size_[l] >= 2) ++stats.flats;
      if (!drainable_[l] && size_[l] >= 2) ++stats.undrainable;
    }
  }

  // 4. Away-from-higher gradient: breadth-first levels from the high edges, within a flat.
  void away_from_higher() {
    away_.assign(cells_.size(), 0);
    height_.assign(next_, 0);  // H: largest A per flat
    std::vector<std::uint32_t> frontier, following;
    for (std::uint32_t k : high_) {
      away_[k] = 1;
      frontier.push_back(k);
    }
    for (std::int32_t level = 1; !frontier.empty(); ++level) {
      following.clear();
      for (std::uint32_t k : frontier) {
        height_[label_[k]] = std::max(height_[label_[k]], level);
        nb_.each_in_try_order(cells_[k], [&](std::uint32_t j, int) {
          const std::uint32_t kj = id_of(j);
          if (kj != kNone && is_flat(kj) && away_[kj] == 0 && label_[kj] == label_[k]) {
            away_[kj] = level + 1;
            following.push_back(kj);
          }
        });
      }
      frontier.swap(following);
    }
  }

  // Undrainable flats: one pit each, the cell farthest from higher ground (largest A,
  // then lowest cell index).
  void pick_pits() {
    pit_of_.assign(next_, kNone);
    for (std::uint32_t k = 0; k < n_flat_; ++k) {
      const std::uint32_t l = label_[k];
      if (drainable_[l]) continue;
      if (pit_of_[l] == kNone || away_[k] > away_[pit_of_[l]] ||
          (away_[k] == away_[pit_of_[l]] && cells_[k] < cells_[pit_of_[l]]))
        pit_of_[l] = k;
    }
  }

  // 5-6. Towards-lower gradient from the low edges (and the chosen pits), combined mask.
  void towards_lower() {
    mask_.assign(cells_.size(), 0);
    std::vector<std::uint32_t> frontier(low_.begin(), low_.end()), following;
    for (std::uint32_t l = 1; l < next_; ++l)
      if (!drainable_[l]) frontier.push_back(pit_of_[l]);
    auto combined = [&](std::uint32_t k, std::int32_t t) {
      return away_[k] > 0 ? 2 * t + (height_[label_[k]] - away_[k]) : 2 * t;
    };
    for (std::uint32_t k : frontier) mask_[k] = combined(k, 1);
    for (std::int32_t t = 1; !frontier.empty(); ++t) {
      following.clear();
      for (std::uint32_t k : frontier)
        nb_.each_in_try_order(cells_[k], [&](std::uint32_t j, int) {
          const std::uint32_t kj = id_of(j);
          if (kj != kNone && is_flat(kj) && mask_[kj] == 0 && label_[kj] == label_[k]) {
            mask_[kj] = combined(kj, t + 1);
            following.push_back(kj);
          }
        });
      frontier.swap(following);
    }
  }

  // 7. Directions down the mask, within the flat. Decided for all cells first, then
  // applied, because the loop looks up neighbours by their no-flow state.
  std::size_t set_directions() {
    std::vector<std::pair<std::uint32_t, std::uint8_t>> decided;
    for (std::uint32_t k = 0; k < n_flat_; ++k) {
      if (k == pit_of_[label_[k]]) continue;
      std::int32_t best = mask_[k];
      int best_k = -1;
      nb_.each_in_try_order(cells_[k], [&](std::uint32_t j, int dir) {
        const std::uint32_t kj = id_of(j);
        if (kj != kNone && label_[kj] == label_[k] && mask_[kj] > 0 && mask_[kj] < best) {
          best = mask_[kj];
          best_k = dir;
        }
      });
      if (best_k >= 0) decided.emplace_back(cells_[k], std::uint8_t(best_k));
    }
    for (const auto& [i, d] : decided) dirs_[i] = d;
    return decided.size();
  }

 private:
  std::uint32_t id_of(std::uint32_t i) const {
    const auto it = id_.find(i);
    return it == id_.end() ? kNone : it->second;
  }
  bool is_flat(std::uint32_t k) const { return k < n_flat_; }  // a no-flow cell

  // Labels the cells of equal elevation connected to `seed` (no-flow cells and low edges).
  void flood(std::uint32_t seed, std::uint32_t lab) {
    label_[seed] = lab;
    std::uint32_t count = is_flat(seed) ? 1 : 0;
    stack_.assign(1, seed);
    while (!stack_.empty()) {
      const std::uint32_t k = stack_.back();
      stack_.pop_back();
      nb_.each_in_try_order(cells_[k], [&](std::uint32_t j, int) {
        const std::uint32_t kj = id_of(j);
        if (kj != kNone && label_[kj] == kNone && z_[j] == z_[cells_[k]]) {
          label_[kj] = lab;
          if (is_flat(kj)) ++count;
          stack_.push_back(kj);
        }
      });
    }
    size_.push_back(count);
  }

  const terrain::BigVector<float>& z_;
  D8Codes& dirs_;
  const Neighbours nb_;
  std::vector<std::uint32_t> cells_;  // compact id -> cell: the no-flow cells, then the low edges
  std::unordered_map<std::uint32_t, std::uint32_t> id_;
  std::size_t n_flat_ = 0;
  std::vector<std::uint32_t> high_, low_, label_, stack_, pit_of_;
  std::vector<std::uint8_t> drainable_{0};  // by label; label 0 unused
  std::vector<std::uint32_t> size_{0};
  std::uint32_t next_ = 1;
  std::vector<std::int32_t> away_, height_, mask_;
};

}  // namespace

FlatStats resolve_flats(const terrain::Grid& g, D8Codes& dirs) {
  FlatStats stats;
  FlatResolver r(g, dirs);
  if (!r.find_cells()) return stats;
  r.find_edges();
  r.label_flats(stats);
  r.away_from_higher();
  r.pick_pits();
  r.towards_lower();
  stats.cells_resolved = r.set_directions();
  return stats;
}

}  // namespace drainage
