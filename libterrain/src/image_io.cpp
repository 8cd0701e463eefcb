#include "terrain/image_io.hpp"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include "terrain/atomic_file.hpp"
#include "terrain/error.hpp"

namespace terrain {

void write_png(const std::string& path, int width, int height, int channels,
               const std::vector<std::uint8_t>& pixels, const std::string& description) {
  if (width <= 0 || height <= 0 ||
      pixels.size() != std::size_t(width) * std::size_t(height) * std::size_t(channels))
    throw Error("write_png: pixel buffer does not match " + std::to_string(width) + " x " +
                std::to_string(height));
  // Encoded in memory (OpenImageIO's PNG writer does not report failed file writes), then
  // written through the checked atomic writer.
  std::vector<unsigned char> bytes;
  {
    OIIO::Filesystem::IOVecOutput proxy(bytes);
    auto image = OIIO::ImageOutput::create("png");
    if (!image) throw Error("cannot write '" + path + "': OpenImageIO has no PNG writer");
    OIIO::ImageSpec spec(width, height, channels, OIIO::TypeDesc::UINT8);
    if (!description.empty()) spec.attribute("ImageDescription", description);
    if (!image->set_ioproxy(&proxy) || !image->open(path, spec) ||
        !image->write_image(OIIO::TypeDesc::UINT8, pixels.data()) || !image->close())
      throw Error("cannot write '" + path + "': " + image->geterror());
  }
  write_file_atomic(path,
                    std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

}  // namespace terrain
