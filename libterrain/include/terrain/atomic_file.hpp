#pragma once
// Write-to-temporary-then-rename, so that a failed or interrupted write never leaves a
// half-written output under the final name.
#include <filesystem>

namespace terrain {

class AtomicFile {
 public:
  // Throws Error when the target's directory does not exist.
  explicit AtomicFile(std::filesystem::path target);
  ~AtomicFile();  // removes the temporary file unless commit() succeeded
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  // Where to write: a hidden sibling of the target in the same directory.
  const std::filesystem::path& temp_path() const { return temp_; }
  const std::filesystem::path& target() const { return target_; }
  // Renames the temporary file onto the target (atomic on POSIX). Throws Error on failure.
  void commit();

 private:
  std::filesystem::path target_;
  std::filesystem::path temp_;
  bool committed_ = false;
};

// Throws Error (one line, naming the path) unless `path`'s directory exists and is
// writable. Tools call it before long work so that a bad output path fails early.
void check_output_path(const std::filesystem::path& path);

}  // namespace terrain
