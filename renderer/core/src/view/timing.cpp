#include "renderer/core/timing.hpp"

#include <fmt/format.h>

namespace renderer {

const char* pass_name(int pass) {
  static const char* names[kPassCount] = {"TFT", "AFT", "DM", "SIL", "LAY", "PEL", "EDGE"};
  return names[pass];
}

Fps frame_fps(const std::array<double, kPassCount>& ms) {
  auto fps = [](double total) { return total > 0 ? 1000.0 / total : 0.0; };
  return {fps(ms[TFT] + ms[DM] + ms[LAY]), fps(ms[TFT] + ms[AFT] + ms[SIL] + ms[LAY]),
          fps(ms[TFT] + ms[AFT] + ms[DM] + ms[SIL] + ms[LAY])};
}

TimingSummary summarize(const std::vector<FrameTimings>& t, std::size_t begin, std::size_t end,
                        bool wall) {
  TimingSummary s;
  end = std::min(end, t.size());
  for (std::size_t i = begin; i < end; ++i) {
    const auto& ms = wall ? t[i].wall_ms : t[i].gpu_ms;
    for (int p = 0; p < kPassCount; ++p) s.mean_ms[p] += ms[p];
    const Fps f = frame_fps(ms);
    s.mean_fps.crease += f.crease;
    s.mean_fps.silhouette += f.silhouette;
    s.mean_fps.total += f.total;
    ++s.frames;
  }
  if (s.frames > 0) {
    const double n = double(s.frames);
    for (auto& m : s.mean_ms) m /= n;
    s.mean_fps.crease /= n;
    s.mean_fps.silhouette /= n;
    s.mean_fps.total /= n;
  }
  return s;
}

std::string timings_csv(const std::vector<FrameTimings>& t) {
  std::string out =
      "frame,TFT_ms,AFT_ms,DM_ms,SIL_ms,LAY_ms,TFT_wall_ms,AFT_wall_ms,DM_wall_ms,SIL_wall_ms,LAY_"
      "wall_ms,"
      "PEL_ms,PEL_wall_ms,EDGE_ms,EDGE_wall_ms,CREASEfps,SILHfps,TOTALfps,CREASEfps_wall,SILHfps_"
      "wall,TOTALfps_wall\n";
  for (std::size_t i = 0; i < t.size(); ++i) {
    const auto& g = t[i].gpu_ms;
    const auto& w = t[i].wall_ms;
    const Fps fg = frame_fps(g), fw = frame_fps(w);
    out += fmt::format(
        "{},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:."
        "4f},{:.4f},"
        "{:.3f},{:.3f},{:.3f},{:.3f},{:.3f},{:.3f}\n",
        i, g[0], g[1], g[2], g[3], g[4], w[0], w[1], w[2], w[3], w[4], g[PEL], w[PEL], g[EDGE],
        w[EDGE], fg.crease, fg.silhouette, fg.total, fw.crease, fw.silhouette, fw.total);
  }
  return out;
}

std::string timing_tables(const std::vector<FrameTimings>& t) {
  const std::size_t n = t.size();
  struct Range {
    const char* label;
    std::size_t b, e;
  };
  const Range ranges[] = {
      {"all frames", 0, n}, {"frames 1-3", 0, std::min<std::size_t>(3, n)}, {"frames 4-N", 3, n}};
  std::string out;
  for (bool wall : {false, true}) {
    out += fmt::format("Table 3 - mean ms per pass ({})\n",
                       wall ? "wall clock around glFinish" : "GL timer queries");
    out += fmt::format("  {:<12}{:>7}{:>10}{:>10}{:>10}{:>10}{:>10}{:>10}{:>10}\n", "frames",
                       "count", "TFT", "AFT", "DM", "SIL", "LAY", "PEL", "EDGE");
    for (const auto& r : ranges) {
      if (r.b >= r.e) continue;
      const auto s = summarize(t, r.b, r.e, wall);
      out += fmt::format(
          "  {:<12}{:>7}{:>10.2f}{:>10.2f}{:>10.2f}{:>10.2f}{:>10.2f}{:>10.2f}{:>10.2f}\n", r.label,
          s.frames, s.mean_ms[0], s.mean_ms[1], s.mean_ms[2], s.mean_ms[3], s.mean_ms[4],
          s.mean_ms[5], s.mean_ms[6]);
    }
    out += fmt::format("Table 4 - mean frames per second ({})\n",
                       wall ? "wall clock" : "GL timer queries");
    out += fmt::format("  {:<12}{:>7}{:>12}{:>12}{:>12}\n", "frames", "count", "CREASEfps",
                       "SILHfps", "TOTALfps");
    for (const auto& r : ranges) {
      if (r.b >= r.e) continue;
      const auto s = summarize(t, r.b, r.e, wall);
      out += fmt::format("  {:<12}{:>7}{:>12.2f}{:>12.2f}{:>12.2f}\n", r.label, s.frames,
                         s.mean_fps.crease, s.mean_fps.silhouette, s.mean_fps.total);
    }
  }
  return out;
}

}  // namespace renderer
