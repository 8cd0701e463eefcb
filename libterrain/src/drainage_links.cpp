#include "terrain/drainage_links.hpp"

#include <algorithm>

namespace terrain {

std::vector<std::uint8_t> strahler_orders(const std::vector<std::uint32_t>& down,
                                          const std::vector<char>& member) {
  const std::size_t n = down.size();
  std::vector<std::uint32_t> in(n, 0);
  for (std::size_t v = 0; v < n; ++v)
    if (member[v] && down[v] != DrainageLinks::kNone) ++in[down[v]];
  std::vector<std::uint8_t> order(n, 0), in_max(n, 0), in_n(n, 0);
  std::vector<std::uint32_t> ready;
  for (std::uint32_t v = 0; v < n; ++v)
    if (member[v] && in[v] == 0) ready.push_back(v);
  while (!ready.empty()) {
    const std::uint32_t v = ready.back();
    ready.pop_back();
    order[v] = in_max[v] == 0 ? 1 : std::uint8_t(std::min(255, in_max[v] + (in_n[v] >= 2)));
    const std::uint32_t d = down[v];
    if (d == DrainageLinks::kNone) continue;
    if (order[v] > in_max[d])
      in_max[d] = order[v], in_n[d] = 1;
    else if (order[v] == in_max[d])
      in_n[d] = std::uint8_t(std::min(2, in_n[d] + 1));
    if (--in[d] == 0) ready.push_back(d);
  }
  return order;
}

}  // namespace terrain
