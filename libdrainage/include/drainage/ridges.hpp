#pragma once
// Ridge lines (docs/algorithms.md 9.7): the crests a drainage network implies, as the
// divides between the catchments of its channel branches. Imhof's crest lines, the
// heaviest lines of a relief drawing, selected as a map selects its rivers: by the size
// of the basins they part.
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "terrain/drainage_links.hpp"

namespace drainage {

// One ridge line: points in the links' frame (x east, y north, metres; point 0 of the
// network at 0, 0), smoothed from the staircase of cell edges the divide follows, with
// the height of the higher point beside each (the crest's side); the area of the smaller
// basin it parts (the area draining through that branch's outlet, m^2) and its relief
// (its highest point above that outlet, m).
struct RidgeLine {
  std::vector<Eigen::Vector3d> points;
  double basin_area = 0, relief = 0;
};

// The ridge lines of `links`:
// - channels: points through which at least channel_area m^2 drains; a branch runs from a
//   channel head or a junction (a channel point with two or more channel points draining
//   into it) down to the next junction; every point belongs to the branch its flow first
//   reaches (or, if it reaches none, to its own outlet's basin);
// - a divide between two branches' catchments is kept when the smaller basin parted drains
//   at least min_basin_area m^2 through its outlet; its chains of cell edges
//   (chain_divide_edges) are resampled at the network's spacing and smoothed (three
//   passes of (1, 2, 1) / 4, the ends kept), and cut where they fall lower than a quarter
//   of their relief above the smaller basin's outlet (the spur ends at confluences).
// Deterministic: ordered by the basins' ids, then as chain_divide_edges lists the chains.
std::vector<RidgeLine> ridge_lines(const terrain::DrainageLinks& links, double channel_area,
                                   double min_basin_area);

}  // namespace drainage
