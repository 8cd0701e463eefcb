#pragma once
// libFuzzer harness helpers: the readers under test take file names, so each input is
// written to a per-process scratch file first.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <string>

namespace terrain::fuzz {

// The input written to /tmp/terrain_fuzz_PID.EXT, removed again when this goes out of scope
// (the regression test runs the targets in ctest: no file left behind in /tmp).
struct InputFile {
  std::string path;
  InputFile(const std::uint8_t* data, std::size_t size, const std::string& ext)
      : path("/tmp/terrain_fuzz_" + std::to_string(::getpid()) + ext) {
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) std::abort();
    if (size) std::fwrite(data, 1, size, f);
    std::fclose(f);
  }
  InputFile(const InputFile&) = delete;
  InputFile& operator=(const InputFile&) = delete;
  ~InputFile() { std::remove(path.c_str()); }
};

}  // namespace terrain::fuzz
