#pragma once
// Image output through OpenImageIO (PNG) and GDAL (GeoTIFF).
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace terrain {

// Writes an 8-bit image (`channels` = 1 grey, 3 RGB, 4 RGBA; rows top to bottom) as PNG,
// atomically. `description` goes into the PNG's text metadata. Throws Error on failure.
void write_png(const std::string& path, int width, int height, int channels,
               const std::vector<std::uint8_t>& pixels, const std::string& description = {});

// Writes an 8-bit RGBA image (rows top to bottom) as a GeoTIFF, atomically: 4 bands, the
// 4th its alpha (unassociated), DEFLATE; with `geotransform` (GDAL's six numbers) and
// `crs_wkt` the map's georeference, else none. `description` goes into its
// TIFFTAG_IMAGEDESCRIPTION. Throws Error on failure.
void write_rgba_geotiff(const std::string& path, int width, int height,
                        const std::vector<std::uint8_t>& rgba,
                        const std::optional<std::array<double, 6>>& geotransform,
                        const std::string& crs_wkt, const std::string& description = {});

}  // namespace terrain
