// libFuzzer harness: the mesh pyramid reader (pyramid_target.hpp).
#include <cstdio>
#include <string>

#include "fuzz_support.hpp"
#include "pyramid_target.hpp"
#include "terrain/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = "/tmp/terrain_fuzz_" + std::to_string(::getpid()) + ".tpyr";
  try {
    terrain::fuzz::pyramid_target(std::string(reinterpret_cast<const char*>(data), size), path);
  } catch (const terrain::Error&) {
  }
  std::remove(path.c_str());
  return 0;
}
