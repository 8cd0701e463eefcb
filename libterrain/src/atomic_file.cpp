#include "terrain/atomic_file.hpp"

#include <unistd.h>

#include <string>
#include <system_error>

#include "terrain/error.hpp"

namespace terrain {

namespace fs = std::filesystem;

void check_output_path(const fs::path& path) {
  fs::path dir = path.parent_path();
  if (dir.empty()) dir = ".";
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw Error("cannot write '" + path.string() + "': directory '" + dir.string() +
                "' does not exist");
  if (::access(dir.c_str(), W_OK) != 0)
    throw Error("cannot write '" + path.string() + "': directory '" + dir.string() +
                "' is not writable");
  if (fs::is_directory(path, ec))
    throw Error("cannot write '" + path.string() + "': it is a directory");
}

AtomicFile::AtomicFile(fs::path target) : target_(std::move(target)) {
  check_output_path(target_);
  // Hidden, unique per process, and with the target's extension (drivers such as GDAL's
  // GPKG look at it).
  temp_ = target_.parent_path() / ("." + target_.stem().string() + ".tmp" + std::to_string(::getpid()) +
                                   target_.extension().string());
}

AtomicFile::~AtomicFile() {
  if (!committed_) {
    std::error_code ec;
    fs::remove(temp_, ec);
  }
}

void AtomicFile::commit() {
  std::error_code ec;
  fs::rename(temp_, target_, ec);
  if (ec) throw Error("cannot write '" + target_.string() + "': " + ec.message());
  committed_ = true;
}

}  // namespace terrain
