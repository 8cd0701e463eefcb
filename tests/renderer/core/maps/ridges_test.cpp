// Which ridge lines a page draws (select_ridges): the basin and relief thresholds, pieces
// joined where they share an end, and whole lines shorter than kRidgeMinPixels on the page
// dropped.
#include <gtest/gtest.h>

#include <vector>

#include "renderer/core/ridges.hpp"

namespace renderer {
namespace {

SceneRidge ridge(std::vector<Eigen::Vector3f> points, float area = 5e6f, float relief = 200.0f) {
  return SceneRidge{std::move(points), area, relief};
}

TEST(Ridges, SelectionJoinsPiecesAndDropsStubs) {
  const std::vector<SceneRidge> ridges = {
      ridge({{0, 0, 10}, {100, 0, 12}}),                 // 0: joined with 1 at (100, 0)
      ridge({{100, 0, 12}, {200, 0, 11}}),               // 1
      ridge({{1000, 1000, 5}, {1010, 1000, 5}}),         // 2: 10 m alone
      ridge({{0, 500, 5}, {300, 500, 5}}, 1e5f),         // 3: a small basin
      ridge({{0, 900, 5}, {300, 900, 5}}, 5e6f, 20.0f),  // 4: little relief
      ridge({{200, 0, 11}, {205, 0, 11}}),               // 5: a 5 m piece joined to 0 and 1
      ridge({{50, 50, 5}}),                              // 6: one point
  };
  // 1 m a pixel: the 205 m crest of 0, 1 and 5 is kept whole; 2 (10 px) is a stub.
  EXPECT_EQ(select_ridges(ridges, 1.0, 1e6, 100.0), (std::vector<std::size_t>{0, 1, 5}));
  // No thresholds on the basin or relief: 3 and 4 as well (300 px each).
  EXPECT_EQ(select_ridges(ridges, 1.0, 0.0, 0.0), (std::vector<std::size_t>{0, 1, 3, 4, 5}));
  // 17 m a pixel: the crest is 12.06 px, kept; at 18 m, 11.4 px, dropped.
  EXPECT_EQ(select_ridges(ridges, 17.0, 1e6, 100.0), (std::vector<std::size_t>{0, 1, 5}));
  EXPECT_TRUE(select_ridges(ridges, 18.0, 1e6, 100.0).empty());
}

}  // namespace
}  // namespace renderer
