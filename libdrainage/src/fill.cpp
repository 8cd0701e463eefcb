#include "drainage/fill.hpp"

#include <cmath>
#include <queue>
#include <vector>

#include "drainage/d8.hpp"

namespace drainage {

std::size_t priority_flood_fill(terrain::Grid& g) {
  const long rows = long(g.rows), cols = long(g.cols);
  auto& z = g.z;
  struct Item {
    float z;
    std::uint32_t i;
    bool operator>(const Item& o) const { return z > o.z || (z == o.z && i > o.i); }
  };
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> open;
  std::vector<std::uint32_t> pit;  // FIFO of depression cells, with a head index
  std::size_t pit_head = 0;
  terrain::BigVector<std::uint8_t> closed(g.size(), 0);

  auto inside = [&](long r, long c) { return r >= 0 && c >= 0 && r < rows && c < cols; };
  for (long r = 0; r < rows; ++r)
    for (long c = 0; c < cols; ++c) {
      const std::size_t i = std::size_t(r * cols + c);
      if (std::isnan(z[i])) {
        closed[i] = 1;
        continue;
      }
      bool seed = r == 0 || c == 0 || r == rows - 1 || c == cols - 1;
      for (int k = 0; k < 8 && !seed; ++k) seed = std::isnan(z[std::size_t((r + kDRow[k]) * cols + c + kDCol[k])]);
      if (seed) {
        closed[i] = 1;
        open.push({z[i], std::uint32_t(i)});
      }
    }

  std::size_t raised = 0;
  while (!open.empty() || pit_head < pit.size()) {
    std::uint32_t i;
    if (pit_head < pit.size()) {
      i = pit[pit_head++];
      if (pit_head == pit.size()) pit.clear(), pit_head = 0;
    } else {
      i = open.top().i;
      open.pop();
    }
    const long r = long(i) / cols, c = long(i) % cols;
    for (int k = 0; k < 8; ++k) {
      const long rr = r + kDRow[k], cc = c + kDCol[k];
      if (!inside(rr, cc)) continue;
      const std::size_t j = std::size_t(rr * cols + cc);
      if (closed[j]) continue;
      closed[j] = 1;
      if (z[j] <= z[i]) {
        if (z[j] < z[i]) ++raised;
        z[j] = z[i];
        pit.push_back(std::uint32_t(j));
      } else {
        open.push({z[j], std::uint32_t(j)});
      }
    }
  }
  return raised;
}

}  // namespace drainage
