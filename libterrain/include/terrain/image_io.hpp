#pragma once
// Image output through OpenImageIO.
#include <cstdint>
#include <string>
#include <vector>

namespace terrain {

// Writes an 8-bit image (`channels` = 1 grey, 3 RGB, 4 RGBA; rows top to bottom) as PNG,
// atomically. `description` goes into the PNG's text metadata. Throws Error on failure.
void write_png(const std::string& path, int width, int height, int channels,
               const std::vector<std::uint8_t>& pixels, const std::string& description = {});

}  // namespace terrain
