// libFuzzer harness: the terrain mesh reader (strict PLY header, then OpenMesh's body
// parser, then the grid, lattice and value checks) and the mesh mode's PN sampling of what
// it read (mesh_target.hpp).
#include <string>

#include "fuzz_support.hpp"
#include "mesh_target.hpp"
#include "terrain/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const terrain::fuzz::InputFile input(data, size, ".ply");
  const std::string& path = input.path;
  try {
    terrain::fuzz::mesh_target(path);
  } catch (const terrain::Error&) {
  }
  return 0;
}
