// libFuzzer harness: the scattered-point reader and the Delaunay surface (points_target.hpp).
#include "points_target.hpp"
#include "terrain/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    terrain::fuzz::points_target(data, size);
  } catch (const terrain::Error&) {
  }
  return 0;
}
