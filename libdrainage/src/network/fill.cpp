#include "drainage/fill.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <utility>
#include <vector>

#include "drainage/d8.hpp"

namespace drainage {

namespace {

// Breaching's queue: lowest elevation first, ties by cell index. Not FloodQueue's radix
// heap: a breach pushes cells it has lowered below the one it took.
struct BreachItem {
  float z;
  std::uint32_t i;
  bool operator>(const BreachItem& o) const { return z > o.z || (z == o.z && i > o.i); }
};
using BreachQueue =
    std::priority_queue<BreachItem, std::vector<BreachItem>, std::greater<BreachItem>>;

// Samples on the grid edge or beside no-data, ascending; marks them and no-data closed.
std::vector<std::uint32_t> flood_seeds(const terrain::Grid& g,
                                       terrain::BigVector<std::uint8_t>& closed) {
  const long rows = long(g.rows), cols = long(g.cols);
  const Neighbours around{rows, cols};
  std::vector<std::uint32_t> seeds;
  const bool voids = std::any_of(g.z.begin(), g.z.end(), [](float v) { return std::isnan(v); });
  for (long r = 0; r < rows; ++r)
    for (long c = 0; c < cols; ++c) {
      const std::size_t i = std::size_t(r * cols + c);
      if (std::isnan(g.z[i])) {
        closed[i] = 1;
        continue;
      }
      bool seed = r == 0 || c == 0 || r == rows - 1 || c == cols - 1;
      if (!seed && voids)
        around.each(r, c, [&](std::size_t j, int) { seed = seed || std::isnan(g.z[j]); });
      if (seed) {
        closed[i] = 1;
        seeds.push_back(std::uint32_t(i));
      }
    }
  return seeds;
}

}  // namespace

std::size_t priority_flood_fill(terrain::Grid& g) {
  const long rows = long(g.rows), cols = long(g.cols);
  auto& z = g.z;
  terrain::BigVector<std::uint8_t> closed(g.size(), 0);
  const std::vector<std::uint32_t> seeds = flood_seeds(g, closed);
  return priority_flood(z, rows, cols, seeds, [&](std::uint32_t, std::uint32_t j) {
    if (closed[j]) return false;
    closed[j] = 1;
    return true;
  });
}

BreachStats breach_depressions(terrain::Grid& g, double max_depth) {
  const long rows = long(g.rows), cols = long(g.cols);
  const Neighbours nb{rows, cols};
  auto& z = g.z;
  const terrain::BigVector<float> original = z;
  terrain::BigVector<std::uint8_t> closed(g.size(), 0);
  terrain::BigVector<std::uint32_t> from(g.size(), kNone);  // the sample each was reached from
  BreachQueue open;
  for (const std::uint32_t i : flood_seeds(g, closed)) open.push({z[i], i});
  constexpr float kUp = std::numeric_limits<float>::infinity(), kDown = -kUp;
  std::vector<std::pair<std::uint32_t, float>> cut;  // the path to lower and its new elevations
  while (!open.empty()) {
    const std::uint32_t i = open.top().i;
    open.pop();
    nb.each(i, [&](std::size_t jj, int) {
      const std::uint32_t j = std::uint32_t(jj);
      if (closed[j]) return;
      closed[j] = 1;
      from[j] = i;
      if (z[j] < z[i]) {
        // The path back from i while it is not below z[j], then the sample e it reaches.
        cut.clear();
        std::uint32_t e = i;
        for (; e != kNone && z[e] >= z[j]; e = from[e]) cut.emplace_back(e, 0.0f);
        float prev = z[j];
        const double drop = e != kNone ? double(z[j]) - double(z[e]) : 0.0;
        for (std::size_t n = 0; n < cut.size(); ++n) {
          const float even =
              e != kNone ? float(double(z[j]) - drop * double(n + 1) / double(cut.size() + 1))
                         : kUp;
          prev = cut[n].second = std::min(even, std::nextafter(prev, kDown));
        }
        // Float rounding can leave e no lower than the path's end: go on lowering.
        for (; e != kNone && z[e] >= prev; e = from[e]) {
          prev = std::nextafter(prev, kDown);
          cut.emplace_back(e, prev);
        }
        bool within = true;
        for (const auto& [p, v] : cut)
          within = within && double(original[p]) - double(v) <= max_depth;
        if (within) {
          for (const auto& pv : cut) z[pv.first] = pv.second;
        } else {
          z[j] = z[i];
        }
      }
      open.push({z[j], j});
    });
  }
  BreachStats st;
  for (std::size_t i = 0; i < z.size(); ++i) {
    if (z[i] < original[i])
      ++st.carved, st.max_carve = std::max(st.max_carve, double(original[i]) - double(z[i]));
    if (z[i] > original[i]) ++st.raised;
  }
  return st;
}

}  // namespace drainage
