// The tiled run (tiled_pipeline.cpp): its tile size for a memory budget, and the whole run
// through the library (fill, flats joined across tiles, network, .dv blocks) against the
// single-grid pipeline on the same DEM.
#include <gtest/gtest.h>

#include <string>

#include "drainage/dv_file.hpp"
#include "drainage/pipeline.hpp"
#include "drainage/tiled_pipeline.hpp"
#include "terrain/dem_io.hpp"
#include "test_support.hpp"

namespace drainage {
namespace {

// --memory: untiled while the grid fits at 40 bytes per point, else the largest multiple
// of 256 whose tiles fit at 100 bytes per point besides 64 MiB, at least 256.
TEST(TiledRun, TileSizeForMemory) {
  terrain::DemInfo info;
  info.rows = 4000, info.cols = 5000;  // 20 M points: 800 MB untiled
  EXPECT_EQ(tile_size_for_memory(info, 800e6), 0u);
  // The largest multiple of 256 whose run fits: 64 MiB + 100 side^2 + 190 * 4 * 20e6 / side.
  for (const double budget : {799e6, 200.0 * (1 << 20)})
    for (const int threads : {1, 2}) {
      const std::size_t side = tile_size_for_memory(info, budget, threads);
      EXPECT_LE(tiled_run_bytes(info, side, threads), budget) << budget << " " << threads;
      EXPECT_GT(tiled_run_bytes(info, side + 256, threads), budget) << budget << " " << threads;
    }
  EXPECT_EQ(tile_size_for_memory(info, 799e6), 2560u);     // 64 MiB + 655 MB + 5.9 MB
  EXPECT_EQ(tile_size_for_memory(info, 799e6, 2), 1792u);  // two threads hold two tiles
  EXPECT_EQ(tile_size_for_memory(info, 800e6, 2), 0u);     // untiled: one grid whatever the threads
  // Too little for any side: the side that needs least, not the smallest.
  const std::size_t least = tile_size_for_memory(info, 1e6);
  for (std::size_t side = 256; side <= 16384; side += 256)
    EXPECT_LE(tiled_run_bytes(info, least, 1), tiled_run_bytes(info, side, 1)) << side;
}

// MED (656 x 456) in tiles of 100, filled: every point's class, accumulation, basin, order
// and direction as compute_drainage gives them on the whole grid; the summary's counts;
// one .dv block per tile; nothing but the .dv left in the output's folder.
TEST(TiledRun, TheLibraryRunEqualsTheSingleGridPipeline) {
  terrain::test::ScratchDir dir;
  TiledRun run;
  run.dem = terrain::test::data("med_01_01_10m.tif");
  run.tile = 100;
  run.fill = true;
  const TiledSummary s = run_tiled_drainage(run, dir.path("t.dv"));
  DrainageOptions options;
  options.fill = true;
  const DrainageResult whole = compute_drainage(terrain::read_dem(run.dem), options);
  EXPECT_EQ(s.rows, whole.surface.rows);
  EXPECT_EQ(s.cols, whole.surface.cols);
  EXPECT_EQ(s.tiles, 35u);  // 7 x 5 tiles of 100
  EXPECT_EQ(s.filled, whole.filled);
  EXPECT_EQ(s.totals.points, whole.net.points);
  EXPECT_EQ(s.totals.branches, whole.net.branch_count);
  EXPECT_EQ(s.totals.pits.size(), whole.net.pits.size());
  const DrainageDb db = read_dv(dir.path("t.dv"));
  EXPECT_EQ(db.header.block_rows, 100u);
  ASSERT_EQ(db.vertices.size(), whole.dirs.size());
  std::size_t differ = 0;
  for (std::size_t i = 0; i < db.vertices.size(); ++i) {
    const DvVertex& v = db.vertices[i];
    if (whole.dirs[i] == kNodata) {
      differ += v.d8 != kNodata;
      continue;
    }
    differ += v.d8 != whole.dirs[i] || v.accumulated != whole.net.accumulated[i] ||
              v.basin != whole.net.basin[i] || v.order != whole.net.order[i] ||
              v.point_class != whole.net.point_class[i];
  }
  EXPECT_EQ(differ, 0u);
  EXPECT_EQ(dir.n_entries(), 1u) << "scratch files left beside the .dv";
}

}  // namespace
}  // namespace drainage
