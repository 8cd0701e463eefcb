#include "terrain/image_io.hpp"

#include <OpenImageIO/imageio.h>

#include "terrain/atomic_file.hpp"
#include "terrain/error.hpp"

namespace terrain {

void write_png(const std::string& path, int width, int height, int channels,
               const std::vector<std::uint8_t>& pixels, const std::string& description) {
  if (width <= 0 || height <= 0 || pixels.size() != std::size_t(width) * std::size_t(height) * std::size_t(channels))
    throw Error("write_png: pixel buffer does not match " + std::to_string(width) + " x " + std::to_string(height));
  AtomicFile out(path);
  {
    auto image = OIIO::ImageOutput::create("png");  // by format name: the temp file has no .png extension
    if (!image) throw Error("cannot write '" + path + "': OpenImageIO has no PNG writer");
    OIIO::ImageSpec spec(width, height, channels, OIIO::TypeDesc::UINT8);
    if (!description.empty()) spec.attribute("ImageDescription", description);
    if (!image->open(out.temp_path().string(), spec) || !image->write_image(OIIO::TypeDesc::UINT8, pixels.data()) ||
        !image->close())
      throw Error("cannot write '" + path + "': " + image->geterror());
  }
  out.commit();
}

}  // namespace terrain
