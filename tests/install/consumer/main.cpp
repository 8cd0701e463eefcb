// Reads a DEM with libterrain, runs the drainage pipeline of libdrainage on it and prints
// the number of points and basins: what a library user of the installed toolkit writes.
#include <iostream>

#include "drainage/pipeline.hpp"
#include "terrain/dem_io.hpp"

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  try {
    const drainage::DrainageResult r =
        drainage::compute_drainage(terrain::read_dem(argv[1]), {true, true, {}});
    std::cout << "points: " << r.net.points << "\nbasins: " << r.net.pits.size() << "\n";
  } catch (const terrain::Error& e) {
    std::cerr << e.what() << "\n";
    return 1;
  }
  return 0;
}
