// The scene a tool draws from (load_scene): the mesh as the PLY holds it, the creases of the
// .dv's points under it, its ridge lines; none of either without a .dv.
#include <gtest/gtest.h>

#include "renderer/scene/frame_setup.hpp"
#include "renderer/scene/scene.hpp"
#include "terrain/error.hpp"
#include "terrain/mesh_digest.hpp"
#include "terrain/mesh_io.hpp"
#include "test_support.hpp"

namespace renderer {
namespace {

TEST(Scene, LoadsTheMeshTheCreasesAndTheRidges) {
  terrain::test::ScratchDir dir;
  const std::string mesh = dir.path("m.ply"), dv = dir.path("m.dv");
  ASSERT_TRUE(terrain::test::mesh_and_drainage("msh_2007_utm10n_10m.tif", mesh, dv, "--spacing 100",
                                               "--spacing 20"));
  const terrain::GridMesh ply = terrain::read_mesh_ply(mesh);

  const Scene bare = load_scene(mesh, "", CreaseRules{});
  EXPECT_EQ(terrain::mesh_digest(bare.mesh), terrain::mesh_digest(ply));
  EXPECT_FALSE(bare.creases.has_value());
  EXPECT_TRUE(bare.ridges.empty());

  const Scene s = load_scene(mesh, dv, CreaseRules{});
  EXPECT_EQ(terrain::mesh_digest(s.mesh), terrain::mesh_digest(ply));
  ASSERT_TRUE(s.creases.has_value());
  EXPECT_GT(s.creases->n_segments(), 100u);
  EXPECT_EQ(s.traits.valley.size(), s.creases->n_segments());
  // The ridge lines are the .dv's under the mesh, in its frame: those read_ridges gives.
  const std::vector<SceneRidge> ridges = read_ridges(dv, ply);
  ASSERT_FALSE(ridges.empty());
  ASSERT_EQ(s.ridges.size(), ridges.size());
  for (std::size_t i = 0; i < ridges.size(); ++i) {
    EXPECT_EQ(s.ridges[i].points, ridges[i].points) << i;
    EXPECT_EQ(s.ridges[i].basin_area, ridges[i].basin_area) << i;
  }
  // In the mesh's local frame: every ridge point lies over the grid.
  const double w = double(ply.topo.cols - 1) * ply.geo.dx,
               h = double(ply.topo.rows - 1) * ply.geo.dy;
  for (const SceneRidge& r : s.ridges)
    for (const Eigen::Vector3f& p : r.points) {
      EXPECT_GE(p.x(), -1e-3);
      EXPECT_LE(p.x(), w + 1e-3);
      EXPECT_LE(p.y(), 1e-3);
      EXPECT_GE(p.y(), -h - 1e-3);
    }
}

// The files a frame is written to follow the formats' table: a map's PNG (any case) gets
// its world file, a vector file or a view that is no map none; other extensions are refused.
TEST(Scene, FrameFilesFollowTheFormatsTable) {
  using V = std::vector<std::string>;
  EXPECT_EQ(frame_files("d/m.png", true), (V{"d/m.png", "d/m.pgw", "d/m.png.aux.xml"}));
  EXPECT_EQ(frame_files("d/m.PNG", true), (V{"d/m.PNG", "d/m.pgw", "d/m.PNG.aux.xml"}));
  EXPECT_EQ(frame_files("d/m.png", false), (V{"d/m.png"}));
  EXPECT_EQ(frame_files("d/m.svg", true), (V{"d/m.svg"}));
  EXPECT_EQ(frame_files("d/m.pdf", true), (V{"d/m.pdf"}));
  EXPECT_EQ(frame_files("d/m.tif", true), (V{"d/m.tif"}));  // its georeference inside
  for (const char* ok : {"m.png", "m.SVG", "m.Pdf", "m.TIF"})
    EXPECT_NO_THROW(check_frame_path(ok)) << ok;
  for (const char* bad : {"m.jpg", "m", "m.tiff"})
    EXPECT_THROW(check_frame_path(bad), terrain::Error);
}

}  // namespace
}  // namespace renderer
