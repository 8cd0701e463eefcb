#pragma once
// Per-pass timings of a frame and the paper's summaries (GL-free).
// Passes, as in Mower's Creases paper (Appendix A): TFT toward-facing surface, AFT
// away-facing surface, DM drainage creases, SIL silhouettes, LAY composite; and PEL,
// photic extremum lines, and EDGE, object-space edges (their own columns; not part of
// the paper's frame rates).
// Frame rates (the paper's equation 7, from per-frame times in ms):
//   CREASEfps = 1000 / (TFT + DM + LAY), SILHfps = 1000 / (TFT + AFT + SIL + LAY),
//   TOTALfps = 1000 / (TFT + AFT + DM + SIL + LAY), averaged over frames.
#include <array>
#include <string>
#include <vector>

namespace renderer {

enum Pass { TFT, AFT, DM, SIL, LAY, PEL, EDGE, kPassCount };
const char* pass_name(int pass);

struct FrameTimings {
  std::array<double, kPassCount> gpu_ms{};   // GL_TIME_ELAPSED queries
  std::array<double, kPassCount> wall_ms{};  // wall clock around each pass + glFinish
};

struct Fps {
  double crease = 0, silhouette = 0, total = 0;
};
Fps frame_fps(const std::array<double, kPassCount>& ms);

// Mean per-pass ms and mean fps over frames [begin, end) (the paper's Tables 3 and 4 use
// all frames, frames 1-3 and frames 4-N).
struct TimingSummary {
  std::size_t frames = 0;
  std::array<double, kPassCount> mean_ms{};
  Fps mean_fps;
};
TimingSummary summarize(const std::vector<FrameTimings>& t, std::size_t begin, std::size_t end,
                        bool wall);

// timings.csv: frame, the five GPU-timer ms, the five wall ms, PEL (GPU timer and wall
// ms), EDGE (GPU timer and wall ms), the three fps (from the GPU timer times, as the paper) and the
// three fps from the wall times; one row per frame.
std::string timings_csv(const std::vector<FrameTimings>& t);

// The human summary printed after a batch: Table 3 (ms per pass) and Table 4 (fps) for
// all frames, the first 3 and the rest, from the GPU timers and from the wall clock.
std::string timing_tables(const std::vector<FrameTimings>& t);

}  // namespace renderer
