#include "drainage/flats.hpp"

#include <algorithm>
#include <limits>

#include "drainage/d8.hpp"

namespace drainage {

namespace {

struct Neighbours {
  long rows, cols;
  // Calls f(j, k) for each in-grid neighbour j of i in direction k, in kTryOrder.
  template <class F>
  void each(std::uint32_t i, F&& f) const {
    const long r = long(i) / cols, c = long(i) % cols;
    for (int k : kTryOrder) {
      const long rr = r + kDRow[std::size_t(k)], cc = c + kDCol[std::size_t(k)];
      if (rr >= 0 && cc >= 0 && rr < rows && cc < cols) f(std::uint32_t(rr * cols + cc), k);
    }
  }
};

}  // namespace

FlatStats resolve_flats(const terrain::Grid& g, std::vector<std::uint8_t>& dirs) {
  FlatStats stats;
  const std::size_t n = g.size();
  const Neighbours nb{long(g.rows), long(g.cols)};
  const auto& z = g.z;
  const std::uint32_t none = kNone;

  // 1-2. Low edges (a direction, beside a no-flow sample of equal elevation) and high
  // edges (no flow, beside a strictly higher sample).
  std::vector<std::uint32_t> low, high;
  for (std::uint32_t i = 0; i < n; ++i) {
    if (dirs[i] == kNodata) continue;
    const bool flat = dirs[i] == kNoFlow;
    bool is_low = false, is_high = false;
    nb.each(i, [&](std::uint32_t j, int) {
      if (dirs[j] == kNodata) return;
      if (!flat && dirs[j] == kNoFlow && z[j] == z[i]) is_low = true;
      if (flat && z[j] > z[i]) is_high = true;
    });
    if (is_low) low.push_back(i);
    if (is_high) high.push_back(i);
  }
  bool any_flat = false;
  for (std::uint32_t i = 0; i < n && !any_flat; ++i) any_flat = dirs[i] == kNoFlow;
  if (!any_flat) return stats;

  // 3. Label flats by flood fill over equal elevation: first from the low edges
  // (drainable flats, low edges included), then from the remaining no-flow samples
  // (undrainable flats).
  std::vector<std::uint32_t> label(n, none);
  std::vector<std::uint8_t> drainable{0};  // by label; label 0 unused
  std::vector<std::uint32_t> stack;
  auto flood = [&](std::uint32_t seed, std::uint32_t id) {
    label[seed] = id;
    stack.assign(1, seed);
    while (!stack.empty()) {
      const std::uint32_t i = stack.back();
      stack.pop_back();
      nb.each(i, [&](std::uint32_t j, int) {
        if (label[j] == none && dirs[j] == kNoFlow && z[j] == z[i]) {
          label[j] = id;
          stack.push_back(j);
        }
      });
    }
  };
  std::uint32_t next = 1;
  for (std::uint32_t i : low)
    if (label[i] == none) {
      flood(i, next++);
      drainable.push_back(1);
    }
  for (std::uint32_t i = 0; i < n; ++i)
    if (dirs[i] == kNoFlow && label[i] == none) {
      flood(i, next++);
      drainable.push_back(0);
    }
  stats.flats = next - 1;

  // 4. Away-from-higher gradient: breadth-first levels from the high edges, within a flat.
  std::vector<std::int32_t> away(n, 0);
  std::vector<std::int32_t> height(next, 0);  // H: largest A per flat
  std::vector<std::uint32_t> frontier, following;
  for (std::uint32_t i : high) {
    away[i] = 1;
    frontier.push_back(i);
  }
  for (std::int32_t level = 1; !frontier.empty(); ++level) {
    following.clear();
    for (std::uint32_t i : frontier) {
      height[label[i]] = std::max(height[label[i]], level);
      nb.each(i, [&](std::uint32_t j, int) {
        if (away[j] == 0 && dirs[j] == kNoFlow && label[j] == label[i]) {
          away[j] = level + 1;
          following.push_back(j);
        }
      });
    }
    frontier.swap(following);
  }

  // Undrainable flats: one pit each, the sample farthest from higher ground.
  std::vector<std::uint32_t> pit_of(next, none);
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t l = label[i];
    if (l == none || drainable[l] || dirs[i] != kNoFlow) continue;
    if (pit_of[l] == none || away[i] > away[pit_of[l]]) pit_of[l] = i;
  }

  // 5-6. Towards-lower gradient from the low edges (and the chosen pits), combined mask.
  std::vector<std::int32_t> mask(n, 0);
  frontier.clear();
  for (std::uint32_t i : low) frontier.push_back(i);
  for (std::uint32_t l = 1; l < next; ++l)
    if (!drainable[l]) {
      frontier.push_back(pit_of[l]);
      ++stats.undrainable;
    }
  auto combined = [&](std::uint32_t i, std::int32_t t) {
    return away[i] > 0 ? 2 * t + (height[label[i]] - away[i]) : 2 * t;
  };
  for (std::uint32_t i : frontier) mask[i] = combined(i, 1);
  for (std::int32_t t = 1; !frontier.empty(); ++t) {
    following.clear();
    for (std::uint32_t i : frontier)
      nb.each(i, [&](std::uint32_t j, int) {
        if (mask[j] == 0 && dirs[j] == kNoFlow && label[j] == label[i]) {
          mask[j] = combined(j, t + 1);
          following.push_back(j);
        }
      });
    frontier.swap(following);
  }

  // 7. Directions down the mask, within the flat.
  // (In place: the loop reads only labels and masks of neighbours.)
  for (std::uint32_t i = 0; i < n; ++i) {
    if (dirs[i] != kNoFlow || i == pit_of[label[i]]) continue;
    std::int32_t best = mask[i];
    int best_k = -1;
    nb.each(i, [&](std::uint32_t j, int k) {
      if (label[j] == label[i] && mask[j] > 0 && mask[j] < best) {
        best = mask[j];
        best_k = k;
      }
    });
    if (best_k >= 0) {
      dirs[i] = std::uint8_t(best_k);
      ++stats.cells_resolved;
    }
  }
  return stats;
}

}  // namespace drainage
