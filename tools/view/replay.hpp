#pragma once
// terrain-view's replay (--replay FILE; docs/terrain-view.md, "Replay"): one command a line,
// each checked as the option table checks options, an error naming its line.
#include <cstddef>
#include <exception>
#include <string>
#include <vector>

#include "terrain/error.hpp"
#include "view/viewer.hpp"

namespace terrain::tools::view {

// One replay command; returns false at quit. `wait_frames` receives `wait N`.
bool run_command(Viewer& v, const std::string& line, int& wait_frames);

// A replay command's error, with its line number, fit for one line of stderr.
terrain::Error replay_error(std::size_t index, const std::exception& e);

// The lines of a replay file.
std::vector<std::string> read_replay(const std::string& path);

// The replay without a window.
int run_offscreen(Viewer& v, const std::vector<std::string>& replay);

}  // namespace terrain::tools::view
