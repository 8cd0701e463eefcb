#include "test_support.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <random>
#include <sstream>

namespace terrain::test {

namespace fs = std::filesystem;

ScratchDir::ScratchDir() {
  std::random_device rd;
  dir_ = fs::temp_directory_path() / ("terrain_test_" + std::to_string(::getpid()) + "_" + std::to_string(rd()));
  fs::create_directories(dir_);
}

ScratchDir::~ScratchDir() {
  std::error_code ec;
  fs::remove_all(dir_, ec);
}

std::size_t ScratchDir::n_entries() const {
  return std::size_t(std::distance(fs::directory_iterator(dir_), fs::directory_iterator{}));
}

RunResult run(const std::string& command_line) {
  ScratchDir tmp;
  const std::string out = tmp.path("stdout"), err = tmp.path("stderr");
  const int status = std::system((command_line + " >" + out + " 2>" + err).c_str());
  RunResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  auto slurp = [](const std::string& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  };
  r.out = slurp(out);
  r.err = slurp(err);
  return r;
}

}  // namespace terrain::test
