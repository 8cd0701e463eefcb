#pragma once
// The ridge lines of a .dv (drainage::ridge_lines) under a mesh, and which of them a page
// draws: the frames' ridges layer (renderer/scene/scene.hpp) and the plan-view maps'
// (plan_map.hpp). GL-free.
#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "terrain/drainage_links.hpp"
#include "terrain/grid_mesh.hpp"

namespace renderer {

// A ridge line of the scene's .dv (drainage::ridge_lines), in the mesh's local frame (not
// exaggerated), with what selects it for a page.
struct SceneRidge {
  std::vector<Eigen::Vector3f> points;
  float basin_area = 0, relief = 0;  // m^2, m
};

// The database's points under a mesh's grid (a large tiled .dv is read block by block).
terrain::DrainageLinks links_under(const std::string& dv_path, const terrain::GridMesh& grid);

inline constexpr double kRidgeChannelArea = 1e6, kRidgeMinBasin = 2e6;  // m^2
inline constexpr double kRidgeMinPixels = 12;
// The ridge lines of a database's links (drainage::ridge_lines at kRidgeChannelArea and
// kRidgeMinBasin), in the local frame of a mesh georeferenced by `g`.
std::vector<SceneRidge> scene_ridges(const terrain::DrainageLinks& links,
                                     const terrain::MeshGeoref& g);
// The ridge lines of the .dv at `dv_path` under `mesh`'s grid, in its local frame.
std::vector<SceneRidge> read_ridges(const std::string& dv_path, const terrain::GridMesh& mesh);
// Which of `ridges` a page of `scale` metres a pixel draws (Topfer's law, as the creases'):
// those parting a smaller basin of at least `min_area` m^2 and rising `min_relief` m above
// its outlet, joined where they share an end, whole lines under kRidgeMinPixels on the page
// dropped (stubs, no crests). Indices, in order.
std::vector<std::size_t> select_ridges(const std::vector<SceneRidge>& ridges, double scale,
                                       double min_area, double min_relief);

}  // namespace renderer
