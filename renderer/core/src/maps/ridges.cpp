#include "renderer/core/ridges.hpp"

#include <cmath>
#include <map>
#include <numeric>

#include "drainage/dv_views.hpp"
#include "drainage/ridges.hpp"

namespace renderer {

terrain::DrainageLinks links_under(const std::string& dv_path, const terrain::GridMesh& grid) {
  const terrain::MeshGeoref& g = grid.geo;
  const terrain::GridTopology& t = grid.topo;
  return drainage::drainage_links_in(dv_path, g.origin_x, g.origin_y - double(t.rows - 1) * g.dy,
                                     g.origin_x + double(t.cols - 1) * g.dx, g.origin_y);
}

std::vector<SceneRidge> scene_ridges(const terrain::DrainageLinks& links,
                                     const terrain::MeshGeoref& g) {
  std::vector<SceneRidge> out;
  const Eigen::Vector3d shift = links.origin - Eigen::Vector3d(g.origin_x, g.origin_y, g.origin_z);
  for (drainage::RidgeLine& l : drainage::ridge_lines(links, kRidgeChannelArea, kRidgeMinBasin)) {
    SceneRidge ridge{{}, float(l.basin_area), float(l.relief)};
    for (const Eigen::Vector3d& p : l.points) ridge.points.push_back((p + shift).cast<float>());
    out.push_back(std::move(ridge));
  }
  return out;
}

std::vector<SceneRidge> read_ridges(const std::string& dv_path, const terrain::GridMesh& mesh) {
  return scene_ridges(links_under(dv_path, mesh), mesh.geo);
}

std::vector<std::size_t> select_ridges(const std::vector<SceneRidge>& ridges, double scale,
                                       double min_area, double min_relief) {
  // The ridges kept, joined where they share an end (a crest is chained in pieces between
  // the corners where three basins meet): a line shorter than kRidgeMinPixels in plan on the
  // page is a stub, no crest.
  std::vector<std::size_t> kept;
  for (std::size_t i = 0; i < ridges.size(); ++i)
    if (ridges[i].basin_area >= min_area && ridges[i].relief >= min_relief &&
        ridges[i].points.size() >= 2)
      kept.push_back(i);
  std::vector<std::size_t> root(kept.size());
  std::iota(root.begin(), root.end(), std::size_t(0));
  auto find = [&](std::size_t x) {
    while (root[x] != x) x = root[x] = root[root[x]];
    return x;
  };
  std::map<std::pair<long, long>, std::size_t>
      ends;  // an end, to the centimetre -> the first piece there
  for (std::size_t k = 0; k < kept.size(); ++k) {
    const auto& pts = ridges[kept[k]].points;
    for (const Eigen::Vector3f& p : {pts.front(), pts.back()}) {
      const auto key = std::make_pair(std::lround(p.x() * 100.0), std::lround(p.y() * 100.0));
      const auto [it, fresh] = ends.try_emplace(key, k);
      if (!fresh) root[find(k)] = find(it->second);
    }
  }
  std::vector<double> length(kept.size(), 0.0);
  for (std::size_t k = 0; k < kept.size(); ++k) {
    const auto& pts = ridges[kept[k]].points;
    for (std::size_t j = 0; j + 1 < pts.size(); ++j)
      length[find(k)] += (pts[j + 1] - pts[j]).head<2>().norm();
  }
  std::vector<std::size_t> out;
  for (std::size_t k = 0; k < kept.size(); ++k)
    if (length[find(k)] >= kRidgeMinPixels * scale) out.push_back(kept[k]);
  return out;
}

}  // namespace renderer
