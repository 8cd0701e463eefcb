// libFuzzer harness: the D8-raster reader of build-drainage --d8-input (GDAL opens the
// bytes as whatever raster they are; TauDEM and ESRI encodings alternate).
#include <string>

#include "drainage/rasters.hpp"
#include "fuzz_support.hpp"
#include "terrain/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const terrain::fuzz::InputFile input(data, size, ".tif");
  const std::string& path = input.path;
  try {
    terrain::Grid grid;
    (void)drainage::read_d8_raster(
        path, size % 2 ? drainage::D8Encoding::Esri : drainage::D8Encoding::Taudem, grid);
  } catch (const terrain::Error&) {
  }
  return 0;
}
