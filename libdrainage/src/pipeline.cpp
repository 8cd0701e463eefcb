#include "drainage/pipeline.hpp"

#include "drainage/d8.hpp"
#include "drainage/dv_file.hpp"
#include "drainage/fill.hpp"

#include <chrono>

namespace drainage {

namespace {

// Records the wall time since the last call under `name`.
class StepClock {
 public:
  explicit StepClock(DrainageResult& r) : r_(r) {}
  void lap(const char* name) {
    const auto now = std::chrono::steady_clock::now();
    r_.timings.emplace_back(name, std::chrono::duration<double>(now - last_).count());
    last_ = now;
  }

 private:
  DrainageResult& r_;
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

}  // namespace

DrainageResult compute_drainage(terrain::Grid surface, const DrainageOptions& options,
                                const terrain::Progress& progress) {
  DrainageResult out;
  StepClock clock(out);
  out.dv_flags = kDvHasElevations;
  if (options.fill) {
    out.filled = priority_flood_fill(surface);
    out.dv_flags |= kDvFilled;
    clock.lap("fill");
  }
  terrain::report(progress, 0.15);
  out.dirs = d8_directions(surface);
  clock.lap("d8");
  terrain::report(progress, 0.3);
  if (options.resolve_flats) {
    out.flats = resolve_flats(surface, out.dirs);
    out.dv_flags |= kDvFlatsResolved;
    clock.lap("flats");
  }
  terrain::report(progress, 0.45);
  out.net = analyze_network(out.dirs, surface.rows, surface.cols, terrain::sub_progress(progress, 0.45, 1.0));
  clock.lap("network");
  out.surface = std::move(surface);
  return out;
}

DrainageResult drainage_from_directions(terrain::Grid surface, D8Codes dirs,
                                        const terrain::Progress& progress) {
  if (dirs.size() != surface.size()) throw terrain::Error("the direction grid and the surface differ in size");
  DrainageResult out;
  out.net = analyze_network(dirs, surface.rows, surface.cols, progress);
  out.dirs = std::move(dirs);
  out.surface = std::move(surface);
  return out;
}

}  // namespace drainage
