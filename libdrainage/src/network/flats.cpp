#include "drainage/flats.hpp"

#include <algorithm>
#include <limits>
#include <unordered_map>

#include "drainage/d8.hpp"

namespace drainage {

FlatStats resolve_flats(const terrain::Grid& g, D8Codes& dirs) {
  FlatStats stats;
  const std::size_t n = g.size();
  const Neighbours nb{long(g.rows), long(g.cols)};
  const auto& z = g.z;

  // The cells involved: no-flow cells and their equal-elevation neighbours with a
  // direction (the low edges). They are few on most terrain, so per-cell state lives in
  // compact arrays indexed through a hash map, not in grid-sized arrays.
  std::vector<std::uint32_t> cells;
  for (std::uint32_t i = 0; i < n; ++i)
    if (dirs[i] == kNoFlow) cells.push_back(i);
  if (cells.empty()) return stats;
  const std::size_t n_flat = cells.size();
  std::unordered_map<std::uint32_t, std::uint32_t> id;
  id.reserve(2 * n_flat);
  for (std::uint32_t k = 0; k < n_flat; ++k) id.emplace(cells[k], k);
  auto id_of = [&](std::uint32_t i) {
    const auto it = id.find(i);
    return it == id.end() ? kNone : it->second;
  };

  // 1-2. High edges (no flow, beside a strictly higher sample) and low edges (a
  // direction, beside a no-flow sample of equal elevation), in ascending cell order.
  std::vector<std::uint32_t> high, low;  // compact ids
  for (std::uint32_t k = 0; k < n_flat; ++k) {
    const std::uint32_t i = cells[k];
    bool is_high = false;
    nb.each_in_try_order(i, [&](std::uint32_t j, int) {
      if (dirs[j] == kNodata) return;
      if (z[j] > z[i]) is_high = true;
      if (dirs[j] != kNoFlow && z[j] == z[i] && id.find(j) == id.end()) {
        id.emplace(j, std::uint32_t(cells.size()));
        cells.push_back(j);
      }
    });
    if (is_high) high.push_back(k);
  }
  for (std::uint32_t k = std::uint32_t(n_flat); k < cells.size(); ++k) low.push_back(k);
  std::sort(low.begin(), low.end(), [&](std::uint32_t a, std::uint32_t b) { return cells[a] < cells[b]; });
  const std::size_t m = cells.size();
  auto is_flat = [&](std::uint32_t k) { return k < n_flat; };  // no-flow cell

  // 3. Label flats by flood fill over equal elevation: first from the low edges
  // (drainable flats, low edges included), then from the remaining no-flow cells
  // (undrainable flats).
  std::vector<std::uint32_t> label(m, kNone);
  std::vector<std::uint8_t> drainable{0};  // by label; label 0 unused
  std::vector<std::uint32_t> size{0};
  std::vector<std::uint32_t> stack;
  auto flood = [&](std::uint32_t seed, std::uint32_t lab) {
    label[seed] = lab;
    std::uint32_t count = is_flat(seed) ? 1 : 0;
    stack.assign(1, seed);
    while (!stack.empty()) {
      const std::uint32_t k = stack.back();
      stack.pop_back();
      nb.each_in_try_order(cells[k], [&](std::uint32_t j, int) {
        const std::uint32_t kj = id_of(j);  // no-flow cells and low edges
        if (kj != kNone && label[kj] == kNone && z[j] == z[cells[k]]) {
          label[kj] = lab;
          if (is_flat(kj)) ++count;
          stack.push_back(kj);
        }
      });
    }
    size.push_back(count);
  };
  std::uint32_t next = 1;
  for (std::uint32_t k : low)
    if (label[k] == kNone) {
      flood(k, next++);
      drainable.push_back(1);
    }
  for (std::uint32_t k = 0; k < n_flat; ++k)
    if (label[k] == kNone) {
      flood(k, next++);
      drainable.push_back(0);
    }
  for (std::uint32_t l = 1; l < next; ++l) {
    if (size[l] >= 2) ++stats.flats;
    if (!drainable[l] && size[l] >= 2) ++stats.undrainable;
  }

  // 4. Away-from-higher gradient: breadth-first levels from the high edges, within a flat.
  std::vector<std::int32_t> away(m, 0);
  std::vector<std::int32_t> height(next, 0);  // H: largest A per flat
  std::vector<std::uint32_t> frontier, following;
  for (std::uint32_t k : high) {
    away[k] = 1;
    frontier.push_back(k);
  }
  for (std::int32_t level = 1; !frontier.empty(); ++level) {
    following.clear();
    for (std::uint32_t k : frontier) {
      height[label[k]] = std::max(height[label[k]], level);
      nb.each_in_try_order(cells[k], [&](std::uint32_t j, int) {
        const std::uint32_t kj = id_of(j);
        if (kj != kNone && is_flat(kj) && away[kj] == 0 && label[kj] == label[k]) {
          away[kj] = level + 1;
          following.push_back(kj);
        }
      });
    }
    frontier.swap(following);
  }

  // Undrainable flats: one pit each, the cell farthest from higher ground (largest A,
  // then lowest cell index).
  std::vector<std::uint32_t> pit_of(next, kNone);
  for (std::uint32_t k = 0; k < n_flat; ++k) {
    const std::uint32_t l = label[k];
    if (drainable[l]) continue;
    if (pit_of[l] == kNone || away[k] > away[pit_of[l]] || (away[k] == away[pit_of[l]] && cells[k] < cells[pit_of[l]]))
      pit_of[l] = k;
  }

  // 5-6. Towards-lower gradient from the low edges (and the chosen pits), combined mask.
  std::vector<std::int32_t> mask(m, 0);
  frontier.assign(low.begin(), low.end());
  for (std::uint32_t l = 1; l < next; ++l)
    if (!drainable[l]) frontier.push_back(pit_of[l]);
  auto combined = [&](std::uint32_t k, std::int32_t t) {
    return away[k] > 0 ? 2 * t + (height[label[k]] - away[k]) : 2 * t;
  };
  for (std::uint32_t k : frontier) mask[k] = combined(k, 1);
  for (std::int32_t t = 1; !frontier.empty(); ++t) {
    following.clear();
    for (std::uint32_t k : frontier)
      nb.each_in_try_order(cells[k], [&](std::uint32_t j, int) {
        const std::uint32_t kj = id_of(j);
        if (kj != kNone && is_flat(kj) && mask[kj] == 0 && label[kj] == label[k]) {
          mask[kj] = combined(kj, t + 1);
          following.push_back(kj);
        }
      });
    frontier.swap(following);
  }

  // 7. Directions down the mask, within the flat. Decided for all cells first, then
  // applied, because the loop looks up neighbours by their no-flow state.
  std::vector<std::pair<std::uint32_t, std::uint8_t>> decided;
  for (std::uint32_t k = 0; k < n_flat; ++k) {
    if (k == pit_of[label[k]]) continue;
    std::int32_t best = mask[k];
    int best_k = -1;
    nb.each_in_try_order(cells[k], [&](std::uint32_t j, int dir) {
      const std::uint32_t kj = id_of(j);
      if (kj != kNone && label[kj] == label[k] && mask[kj] > 0 && mask[kj] < best) {
        best = mask[kj];
        best_k = dir;
      }
    });
    if (best_k >= 0) decided.emplace_back(cells[k], std::uint8_t(best_k));
  }
  for (const auto& [i, d] : decided) dirs[i] = d;
  stats.cells_resolved = decided.size();
  return stats;
}

}  // namespace drainage
