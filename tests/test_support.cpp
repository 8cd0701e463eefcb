#include "test_support.hpp"

#include "terrain/dem_io.hpp"
#include "terrain/prepare_grid.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <random>
#include <sstream>

namespace terrain::test {

namespace fs = std::filesystem;

ScratchDir::ScratchDir() {
  std::random_device rd;
  dir_ = fs::temp_directory_path() /
         ("terrain_test_" + std::to_string(::getpid()) + "_" + std::to_string(rd()));
  fs::create_directories(dir_);
}

ScratchDir::~ScratchDir() {
  std::error_code ec;
  fs::remove_all(dir_, ec);
}

std::size_t ScratchDir::n_entries() const {
  return std::size_t(std::distance(fs::directory_iterator(dir_), fs::directory_iterator{}));
}

GridMesh function_mesh(std::size_t rows, std::size_t cols, double h,
                       const std::function<double(double, double)>& f) {
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

bool mesh_and_drainage(const std::string& dem, const std::string& mesh, const std::string& dv,
                       const std::string& mesh_options, const std::string& dv_options) {
  return run(tool("dem2mesh") + " " + data(dem) + " " + mesh + " " + mesh_options + " -q")
                 .exit_code == 0 &&
         run(tool("build-drainage") + " " + mesh + " " + dv + " " + dv_options + " -q").exit_code ==
             0;
}

Background::Background(const std::string& command_line) {
  const std::string sh =
      "exec env " + command_line + " >" + logs_.path("stdout") + " 2>" + logs_.path("stderr");
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
         "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 "
         "OMPI_MCA_btl_vader_single_copy_mechanism=none "
         "OMPI_MCA_btl=self,vader " TERRAIN_MPIEXEC " --oversubscribe -np " +
         std::to_string(ranks) + " ";
}
#endif

const GridMesh& msh_50m_mesh() {
  static const GridMesh mesh = [] {
    GridRequest req;
    req.spacing = 50.0;
    return make_grid_mesh(prepare_grid(read_dem(data("msh_2007_utm10n_10m.tif")), req).grid,
                          NormalWeighting::Uniform);
  }();
  return mesh;
}

std::string pyramid_as_version1(std::string v4) {
  auto get = [&](std::size_t at, auto value) {
    std::memcpy(&value, v4.data() + at, sizeof value);
    return value;
  };
  std::size_t at =
      8 + 4 + 8 + 4 + 16 + 40 + 4;      // magic, version, header bytes, B, grid, georeference, EPSG
  at += 4 + get(at, std::uint32_t(0));  // the CRS
  std::string v1 = v4.substr(0, at);
  // The digest and the flags, left out (no flag: the tiles hold positions and normals only).
  if (get(at + 8, std::uint32_t(0)) != 0) return {};
  at += 12;
  std::uint64_t removed = 12;
  const std::uint32_t n_levels = get(at, std::uint32_t(0));
  const std::uint32_t block = get(20, std::uint32_t(0));
  const std::uint64_t rows = get(24, std::uint64_t(0)), cols = get(32, std::uint64_t(0));
  const std::size_t n_blocks = ((rows - 1 + block - 1) / block) * ((cols - 1 + block - 1) / block);
  v1 += v4.substr(at, 4);
  at += 4;
  for (std::size_t k = 0; k < n_blocks; ++k) {
    const std::uint32_t n = get(at + 24, std::uint32_t(0));
    v1 += v4.substr(at, 28 + 4 * std::size_t(n));  // box, n, errors; the slopes left out
    at += 28 + 8 * std::size_t(n);
    removed += 4 * std::uint64_t(n);
  }
  const std::uint64_t header = get(12, std::uint64_t(0));
  removed += 4;  // the header's CRC
  std::string index = v4.substr(at, header - 4 - at);
  std::size_t entry = 0;
  for (std::uint32_t l = 0; l < n_levels; ++l) {
    const std::uint64_t tiles =
        get(at + entry, std::uint64_t(0)) * get(at + entry + 8, std::uint64_t(0));
    entry += 16;
    for (std::uint64_t t = 0; t < tiles; ++t, entry += 16) {
      const std::uint64_t offset = get(at + entry, std::uint64_t(0)) - removed;
      std::memcpy(index.data() + entry, &offset, 8);
    }
  }
  v1 += index;
  v1 += v4.substr(header);  // the tiles
  const std::uint32_t one = 1;
  std::memcpy(v1.data() + 8, &one, 4);
  const std::uint64_t v1_header = header - removed;
  std::memcpy(v1.data() + 12, &v1_header, 8);
  return v1;
}

}  // namespace terrain::test
