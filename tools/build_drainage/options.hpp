#pragma once
// build-drainage's options (CLI11) and the job they ask for.
#include <CLI/CLI.hpp>

#include <cstddef>
#include <string>
#include <vector>

#include "drainage/job.hpp"

namespace terrain::tools::build_drainage {

// The options as CLI11 fills them.
struct Options {
  std::vector<std::string> positional;
  std::string raster, d8_input, rasters_dir, surface_out, encoding = "taudem", outlets, watersheds;
  double snap_distance = 0, spacing = 10.0, memory_mib = 0;
  bool keep_flats = false, fill = false, keep_pits = false;
  int threads = 0;
  std::uint32_t dv_version = drainage::kDvVersion;
  std::size_t tile_size = 0;
  std::optional<double> breach;
};

void add_options(CLI::App& app, Options& o);
// The job the options ask for: the inputs, the outputs (the watersheds' names defaulted), the
// drainage rules. Throws for options that do not go together.
drainage::DrainageJob job_of(const CLI::App& app, Options& o);

}  // namespace terrain::tools::build_drainage
