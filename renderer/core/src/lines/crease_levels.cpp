// The creases' levels of detail: runs of segments merged within a tolerance, the coarser
// levels, and the level a view draws.
#include "renderer/core/crease.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "renderer/core/camera.hpp"
#include "renderer/core/line_stats.hpp"
#include "terrain/error.hpp"
#include "terrain/pn_surface.hpp"

namespace renderer {

namespace {

// The distance of p from the segment a-b.
float segment_distance(const Eigen::Vector3f& p, const Eigen::Vector3f& a,
                       const Eigen::Vector3f& b) {
  const Eigen::Vector3f ab = b - a;
  const float u = std::clamp((p - a).dot(ab) / std::max(ab.squaredNorm(), 1e-12f), 0.0f, 1.0f);
  return (a + u * ab - p).norm();
}

// Each vertex's segments in and out, and the segment leaving it.
struct Runs {
  std::vector<std::uint32_t> in, out, leaving;
  bool is_break(std::uint32_t v) const { return in[v] != 1 || out[v] != 1; }
};
Runs runs_of(const CreaseGeometry& g) {
  const std::size_t nv = g.positions.size(), ns = g.n_segments();
  Runs r{std::vector<std::uint32_t>(nv, 0), std::vector<std::uint32_t>(nv, 0),
         std::vector<std::uint32_t>(nv, kNoSegment)};
  for (std::uint32_t s = 0; s < ns; ++s) {
    ++r.out[g.segments[2 * s]], ++r.in[g.segments[2 * s + 1]];
    r.leaving[g.segments[2 * s]] = s;
  }
  return r;
}

// The vertices kept: the breaks; along each run, from its first vertex, the farthest
// vertex within `step` segments whose dropped vertices all lie within `tolerance` of the
// segment to it, in turn. A vertex no run reaches (on a cycle, which D8 does not make) is kept.
std::vector<std::uint8_t> kept_vertices(const CreaseGeometry& g, const Runs& runs, int step,
                                        double tolerance) {
  const std::size_t nv = g.positions.size(), ns = g.n_segments();
  const std::vector<std::uint32_t>& leaving = runs.leaving;
  const auto is_break = [&](std::uint32_t v) { return runs.is_break(v); };
  std::vector<std::uint8_t> kept(nv, 1);
  std::vector<std::uint32_t> run;
  for (std::uint32_t s = 0; s < ns; ++s) {
    if (!is_break(g.segments[2 * s])) continue;
    run.assign({g.segments[2 * s], g.segments[2 * s + 1]});
    while (!is_break(run.back())) run.push_back(g.segments[2 * leaving[run.back()] + 1]);
    for (std::size_t k = 1; k + 1 < run.size(); ++k) kept[run[k]] = 0;
    for (std::size_t a = 0; a + 1 < run.size();) {
      std::size_t b = std::min(a + std::size_t(step), run.size() - 1);
      const auto within = [&](std::size_t e) {
        for (std::size_t k = a + 1; k < e; ++k)
          if (segment_distance(g.positions[run[k]], g.positions[run[a]], g.positions[run[e]]) >
              tolerance)
            return false;
        return true;
      };
      while (b > a + 1 && !within(b)) --b;
      kept[run[b]] = 1;
      a = b;
    }
  }
  return kept;
}

}  // namespace

CreaseLevel merge_crease_runs(const CreaseGeometry& g, int step, double tolerance) {
  if (step < 1) throw terrain::Error("merge_crease_runs: the step must be at least 1");
  const std::size_t nv = g.positions.size(), ns = g.n_segments();
  const Runs runs = runs_of(g);
  const std::vector<std::uint32_t>& leaving = runs.leaving;
  const std::vector<std::uint8_t> kept = kept_vertices(g, runs, step, tolerance);
  CreaseLevel level;
  level.step = step;
  std::vector<std::uint32_t> index(nv, kNoSegment);  // fine vertex -> kept vertex
  CreaseGeometry& c = level.geometry;
  const auto keep = [&](std::uint32_t v) {
    if (index[v] != kNoSegment) return index[v];
    index[v] = std::uint32_t(c.positions.size());
    c.positions.push_back(g.positions[v]);
    c.normals.push_back(g.normals[v]);
    c.flow.push_back(g.flow[v]);
    if (!g.source.empty()) c.source.push_back(g.source[v]);  // optional, as area and share
    if (!g.share.empty()) c.share.push_back(g.share[v]);
    if (!g.area.empty()) c.area.push_back(g.area[v]);
    return index[v];
  };
  std::vector<std::uint32_t> dropped;
  for (std::uint32_t s = 0; s < ns; ++s) {
    const std::uint32_t a = g.segments[2 * s];
    if (!kept[a]) continue;
    std::uint32_t t = s, b = g.segments[2 * s + 1];
    dropped.clear();
    while (!kept[b]) {
      dropped.push_back(b);
      t = leaving[b];
      b = g.segments[2 * t + 1];
    }
    for (const std::uint32_t v : dropped)
      level.error_metres =
          std::max(level.error_metres,
                   double(segment_distance(g.positions[v], g.positions[a], g.positions[b])));
    c.segments.push_back(keep(a));
    c.segments.push_back(keep(b));
    if (!dropped.empty()) {  // scored where the run it replaces is, at its middle vertex
      const std::uint32_t m = dropped[(dropped.size() - 1) / 2], k = index[a];
      c.normals[k] = g.normals[m];
      c.flow[k] = g.flow[m];
      if (!g.area.empty()) c.area[k] = g.area[m];
    }
    level.first.push_back(s);
    level.last.push_back(t);
  }
  c.median_surface_offset = g.median_surface_offset;
  level.chains = segment_chains(c);
  return level;
}

std::vector<CreaseLevel> coarser_crease_levels(const CreaseGeometry& g) {
  std::vector<CreaseLevel> levels;
  std::vector<double> length = segment_metres(g);
  if (length.empty()) return levels;
  std::nth_element(length.begin(), length.begin() + std::ptrdiff_t(length.size() / 2),
                   length.end());
  const double median = length[length.size() / 2];
  std::size_t previous = g.n_segments();
  for (int step = 2; step <= kMaxCreaseStep; step *= 2) {
    CreaseLevel l = merge_crease_runs(g, step, kCreaseTolerance * step * median);
    if (double(l.geometry.n_segments()) > kCreaseLevelShrink * double(previous)) break;
    previous = l.geometry.n_segments();
    levels.push_back(std::move(l));
  }
  return levels;
}

int select_crease_level(const std::vector<double>& error_metres, double pixel_metres,
                        double bound_px) {
  int l = 0;
  while (pixel_metres > 0 && std::size_t(l) < error_metres.size() &&
         error_metres[std::size_t(l)] <= bound_px * pixel_metres)
    ++l;
  return l;
}

}  // namespace renderer
