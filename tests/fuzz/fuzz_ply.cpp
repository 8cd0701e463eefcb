// libFuzzer harness: the terrain mesh reader (strict PLY header, then OpenMesh's body
// parser, then the grid and value checks).
#include <string>

#include "fuzz_support.hpp"
#include "terrain/error.hpp"
#include "terrain/mesh_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = terrain::fuzz::input_file(data, size, ".ply");
  try {
    (void)terrain::read_mesh_ply(path);
  } catch (const terrain::Error&) {
  }
  return 0;
}
