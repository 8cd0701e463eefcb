#pragma once
// Shared helpers of the test suite: data paths (from CMake, never the working
// directory), a scratch directory, and running a tool.
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>

#include "terrain/grid_mesh.hpp"

namespace terrain::test {

// Appended, not `"..." + name`: GCC 12 warns (-Warray-bounds, -Wrestrict) about the
// inlined copies of a literal-plus-string concatenation, wrongly.
inline std::string in_dir(std::string dir, const std::string& name) {
  return dir.append(1, '/').append(name);
}
inline std::string data(const std::string& name) { return in_dir(TERRAIN_DATA_DIR, name); }
inline std::string tool(const std::string& name) { return in_dir(TERRAIN_BIN_DIR, name); }
// A file's whole contents, bytes as they are ("" when it cannot be read).
inline std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A mesh pyramid's bytes (docs/formats.md, version 4, no flags) as version 1 wrote them:
// the mesh's digest, the flags, the blocks' slopes and the header's CRC taken out of the
// header, the header's size and the index's tile offsets moved by the bytes they took, the
// version set to 1; "" when its flags are set.
std::string pyramid_as_version1(std::string v4);

// A fresh directory under the system temp dir, removed at destruction.
class ScratchDir {
 public:
  ScratchDir();
  ~ScratchDir();
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::size_t n_entries() const;

 private:
  std::filesystem::path dir_;
};

struct RunResult {
  int exit_code = -1;
  std::string out;  // stdout
  std::string err;  // stderr
};

// Runs a command line through /bin/sh and captures its exit code, stdout and stderr.
RunResult run(const std::string& command_line);

// Runs dem2mesh on data(dem) into `mesh` with `mesh_options`, then build-drainage on it into
// `dv` with `dv_options`; true when both exit 0 (the end-to-end tests' small scene).
bool mesh_and_drainage(const std::string& dem, const std::string& mesh, const std::string& dv,
                       const std::string& mesh_options, const std::string& dv_options);

// A command started in the background (`/bin/sh -c "exec COMMAND"`, so the process is the
// command itself and a signal sent to it reaches the tool), stdout and stderr to files.
class Background {
 public:
  explicit Background(const std::string& command_line);
  ~Background();  // kills and reaps the process if wait() was not called
  Background(const Background&) = delete;
  Background& operator=(const Background&) = delete;
  void signal(int sig) const;
  // Waits for the process: the exit code, or 128 + the signal that ended it.
  int wait();
  std::string err() const;

 private:
  int pid_ = -1;
  int status_ = -1;
  ScratchDir logs_;
};

#ifdef TERRAIN_MPIEXEC
// mpirun with the settings a root user in a container needs (Open MPI refuses root
// otherwise; no cross-memory attach there), as many ranks as asked on 2 cores. Under
// AddressSanitizer the ranks skip the leak check: Open MPI keeps allocations until exit in
// components it unloads, whose stacks no suppression can name (the same code paths run
// leak-checked in one process in the other tests).
std::string mpirun(int ranks);
#endif

// The mesh (area-weighted normals) of z = f(x, y) on rows x cols samples h metres apart,
// in its local frame: sample (r, c) at x = c h, y = -r h, the origin at sample (0, 0).
// f is called row by row, west to east, so a seeded random term is reproducible.
GridMesh function_mesh(std::size_t rows, std::size_t cols, double h,
                       const std::function<double(double, double)>& f);

// The demo's Mount St. Helens mesh: the bundled 2007 DEM resampled to 50 m (dem2mesh
// --spacing 50), uniform vertex normals. Built once.
const GridMesh& msh_50m_mesh();

}  // namespace terrain::test
