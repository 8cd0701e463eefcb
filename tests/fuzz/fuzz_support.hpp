#pragma once
// libFuzzer harness helpers: the readers under test take file names, so each input is
// written to a per-process scratch file first.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <string>

namespace terrain::fuzz {

// Writes the input to /tmp/terrain_fuzz_PID.EXT and returns the path.
inline std::string input_file(const std::uint8_t* data, std::size_t size, const std::string& ext) {
  const std::string path = "/tmp/terrain_fuzz_" + std::to_string(::getpid()) + ext;
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) std::abort();
  if (size) std::fwrite(data, 1, size, f);
  std::fclose(f);
  return path;
}

}  // namespace terrain::fuzz
