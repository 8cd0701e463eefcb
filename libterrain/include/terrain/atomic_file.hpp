#pragma once
// Every output of the toolkit is written through this header: to a hidden temporary file
// beside the target, checked (a failed write, ENOSPC or EFBIG, is an Error), then renamed
// onto the target. A failed or interrupted write never leaves a half-written output under
// the final name, and never replaces an existing file with a truncated one.
//
// Targets that exist but are not regular files (/dev/null, /dev/full, a FIFO) are refused:
// renaming a temporary file over a device would replace the device node (docs/formats.md).
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "terrain/temp_files.hpp"

namespace terrain {

class AtomicFile {
 public:
  // Throws Error when the target's directory does not exist or is not writable, or when
  // the target exists and is not a regular file.
  explicit AtomicFile(std::filesystem::path target);
  ~AtomicFile();  // removes the temporary file unless commit() succeeded
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  // Where to write: a hidden sibling of the target in the same directory, with the
  // target's extension (drivers such as GDAL's GPKG look at it), private to this process
  // and removed on SIGINT/SIGTERM (temp_files.hpp). When the target is itself a temporary
  // this process registered (an OutputSet's staged path), it is written in place.
  const std::filesystem::path& temp_path() const { return temp_; }
  const std::filesystem::path& target() const { return target_; }
  // Renames the temporary file onto the target (atomic on POSIX). Throws Error when the
  // temporary file is missing or the rename fails.
  void commit();

 private:
  std::filesystem::path target_;
  std::filesystem::path temp_;
  TempRegistration registration_;
  bool in_place_ = false;
  bool committed_ = false;
};

// Throws Error (one line, naming the path) unless `path`'s directory exists and is
// writable and `path` is not a directory or another non-regular file. Tools call it
// before long work so that a bad output path fails early.
void check_output_path(const std::filesystem::path& path);

// Writes what `write` puts into the stream to `path` atomically. The stream is buffered
// (1 MiB); after `write` returns it is flushed and closed, and any failure on the way
// (a bad stream state, a failed close) is an Error "cannot write 'PATH': ...".
void write_stream_atomic(const std::filesystem::path& path,
                         const std::function<void(std::ostream&)>& write);

// Writes `bytes` to `path` atomically (write_stream_atomic).
void write_file_atomic(const std::filesystem::path& path, std::string_view bytes);

// Several outputs that appear together or not at all: stage() reserves a temporary path
// for each target (the caller writes the file there, by any writer), commit() renames them
// all onto their targets; destroyed without commit(), it removes every staged file. So a
// tool that fails at its third output leaves neither the first nor the second.
class OutputSet {
 public:
  OutputSet() = default;
  OutputSet(const OutputSet&) = delete;
  OutputSet& operator=(const OutputSet&) = delete;
  // The path to write `target` to. Checks `target` as AtomicFile does.
  std::string stage(const std::filesystem::path& target);
  // Runs `write` (which writes to staged paths); an Error it throws is rethrown with every
  // staged temporary path in its message replaced by its target, so the user reads the
  // name they gave.
  void write(const std::function<void()>& write);
  void commit();

 private:
  std::vector<std::unique_ptr<AtomicFile>> files_;
};

}  // namespace terrain
