#pragma once
// terrain-view's window (GLFW, Dear ImGui): camera moves, the option panel generated from
// the table, saved views and keyframes; the replay one command a drawn frame.
#include <string>
#include <vector>

#include "view/viewer.hpp"

namespace terrain::tools::view {

int run_window(Viewer& v, const std::vector<std::string>& replay, const std::string& save_dir);

}  // namespace terrain::tools::view
