#include "terrain/atomic_file.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
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
  const fs::file_status st = fs::status(path, ec);
  if (fs::is_directory(st)) throw Error("cannot write '" + path.string() + "': it is a directory");
  if (fs::exists(st) && !fs::is_regular_file(st))
    throw Error("cannot write '" + path.string() +
                "': it exists and is not a regular file (a device or pipe); give a file name");
}

AtomicFile::AtomicFile(fs::path target) : target_(std::move(target)) {
  check_output_path(target_);
  if (is_registered_temporary(target_)) {
    // A staged path of an OutputSet (or another AtomicFile) of this process: it is already
    // a private temporary that its owner renames, so it is written in place rather than
    // through a second, nested temporary.
    temp_ = target_;
    in_place_ = true;
    return;
  }
  temp_ = temporary_sibling(target_);
  registration_ = TempRegistration(temp_);
}

AtomicFile::~AtomicFile() {
  if (!committed_) {
    std::error_code ec;
    fs::remove(temp_, ec);
    for (const char* suffix : {"-journal", "-wal", "-shm"})
      fs::remove(temp_.string() + suffix, ec);  // SQLite's
  }
}

void AtomicFile::commit() {
  std::error_code ec;
  if (!fs::is_regular_file(temp_, ec))
    throw Error("cannot write '" + target_.string() + "': nothing was written");
  if (in_place_) {
    committed_ = true;
    return;
  }
  // A file replaced keeps its mode (a read-only output stays read-only), as cp and GDAL do.
  if (const fs::file_status old = fs::status(target_, ec); !ec && fs::is_regular_file(old))
    fs::permissions(temp_, old.permissions(), fs::perm_options::replace, ec);
  fs::rename(temp_, target_, ec);
  if (ec) throw Error("cannot write '" + target_.string() + "': " + ec.message());
  committed_ = true;
  registration_ = TempRegistration();
}

void write_stream_atomic(const fs::path& path, const std::function<void(std::ostream&)>& write) {
  AtomicFile out(path);
  {
    std::vector<char> buffer(std::size_t(1) << 20);
    std::ofstream file;
    file.rdbuf()->pubsetbuf(buffer.data(), std::streamsize(buffer.size()));
    errno = 0;
    file.open(out.temp_path(), std::ios::binary | std::ios::trunc);
    if (!file)
      throw Error("cannot write '" + path.string() + "': cannot create the file (" +
                  std::strerror(errno) + ")");
    errno = 0;
    write(file);
    file.flush();
    const bool written = bool(file);
    file.close();
    if (!written || !file)
      throw Error("cannot write '" + path.string() + "': " +
                  (errno != 0 ? std::string(std::strerror(errno))
                              : std::string("write failed (disk full?)")));
  }
  out.commit();
}

void write_file_atomic(const fs::path& path, std::string_view bytes) {
  write_stream_atomic(
      path, [&](std::ostream& os) { os.write(bytes.data(), std::streamsize(bytes.size())); });
}

std::string OutputSet::stage(const fs::path& target) {
  files_.push_back(std::make_unique<AtomicFile>(target));
  return files_.back()->temp_path().string();
}

void OutputSet::write(const std::function<void()>& write) {
  try {
    write();
  } catch (const Error& e) {
    std::string msg = e.what();
    for (const auto& f : files_) {
      const std::string temp = f->temp_path().string(), target = f->target().string();
      for (std::size_t at; (at = msg.find(temp)) != std::string::npos;)
        msg.replace(at, temp.size(), target);
    }
    throw Error(msg);
  }
}

void OutputSet::commit() {
  // The renames are one step for SIGINT/SIGTERM/SIGHUP: an interrupt waits until the last
  // is done, so it leaves every output new or every output old.
  const DeferInterrupts one_step;
  for (auto& f : files_) f->commit();
}

}  // namespace terrain
