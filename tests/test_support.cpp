#include "test_support.hpp"

#include "terrain/dem_io.hpp"
#include "terrain/prepare_grid.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
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

GridMesh function_mesh(std::size_t rows, std::size_t cols, double h, const std::function<double(double, double)>& f) {
  Georef geo;
  geo.dx = geo.dy = h;
  geo.x0 = -0.5 * h;  // sample (0, 0) at the world origin
  geo.y0 = 0.5 * h;
  geo.crs_kind = CrsKind::Projected;
  Grid g(rows, cols, geo);
  for (std::size_t r = 0; r < rows; ++r)
    for (std::size_t c = 0; c < cols; ++c) g.at(r, c) = float(f(double(c) * h, -double(r) * h));
  return make_grid_mesh(g, NormalWeighting::Area);
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

Background::Background(const std::string& command_line) {
  const std::string sh = "exec env " + command_line + " >" + logs_.path("stdout") + " 2>" + logs_.path("stderr");
  pid_ = ::fork();
  if (pid_ == 0) {
    ::execl("/bin/sh", "sh", "-c", sh.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
}

Background::~Background() {
  if (pid_ > 0 && status_ < 0) {
    ::kill(pid_, SIGKILL);
    wait();
  }
}

void Background::signal(int sig) const { ::kill(pid_, sig); }

int Background::wait() {
  if (status_ < 0) {
    int st = 0;
    while (::waitpid(pid_, &st, 0) < 0 && errno == EINTR) {
    }
    status_ = WIFEXITED(st) ? WEXITSTATUS(st) : WIFSIGNALED(st) ? 128 + WTERMSIG(st) : 255;
  }
  return status_;
}

std::string Background::err() const { return file_bytes(logs_.path("stderr")); }

#ifdef TERRAIN_MPIEXEC
std::string mpirun(int ranks) {
  return "ASAN_OPTIONS=\"$ASAN_OPTIONS:detect_leaks=0\" "
         "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_btl_vader_single_copy_mechanism=none "
         "OMPI_MCA_btl=self,vader " TERRAIN_MPIEXEC " --oversubscribe -np " + std::to_string(ranks) + " ";
}
#endif

const GridMesh& msh_50m_mesh() {
  static const GridMesh mesh = [] {
    GridRequest req;
    req.spacing = 50.0;
    return make_grid_mesh(prepare_grid(read_dem(data("msh_2007_utm10n_10m.tif")), req).grid, NormalWeighting::Uniform);
  }();
  return mesh;
}

}  // namespace terrain::test
