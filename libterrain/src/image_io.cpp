#include "terrain/image_io.hpp"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <cpl_vsi.h>
#include <gdal_priv.h>
#include <unistd.h>

#include <atomic>
#include <memory>

#include "terrain/atomic_file.hpp"
#include "terrain/dem_io.hpp"
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

void write_rgba_geotiff(const std::string& path, int width, int height,
                        const std::vector<std::uint8_t>& rgba,
                        const std::optional<std::array<double, 6>>& geotransform,
                        const std::string& crs_wkt, const std::string& description) {
  if (width <= 0 || height <= 0 || rgba.size() != std::size_t(width) * std::size_t(height) * 4)
    throw Error("write_rgba_geotiff: pixel buffer does not match " + std::to_string(width) + " x " +
                std::to_string(height));
  ensure_gdal();
  // Made in GDAL's memory file system (a name of this call's own), then written through
  // the checked atomic writer.
  static std::atomic<unsigned> serial{0};
  const std::string mem =
      "/vsimem/terrain_" + std::to_string(::getpid()) + "_" + std::to_string(serial++) + ".tif";
  struct Unlink {  // the memory file goes whatever happens
    std::string path;
    ~Unlink() { VSIUnlink(path.c_str()); }
  } unlink{mem};
  GDALDriver* drv = GetGDALDriverManager()->GetDriverByName("GTiff");
  if (!drv) throw Error("GDAL has no GTiff driver");
  const char* options[] = {"COMPRESS=DEFLATE", "PHOTOMETRIC=RGB", "ALPHA=UNASSOCIATED",
                           "INTERLEAVE=PIXEL", nullptr};
  {
    std::unique_ptr<GDALDataset> ds(
        drv->Create(mem.c_str(), width, height, 4, GDT_Byte, const_cast<char**>(options)));
    if (!ds) throw Error("cannot write '" + path + "': " + CPLGetLastErrorMsg());
    if (geotransform) ds->SetGeoTransform(const_cast<double*>(geotransform->data()));
    if (!crs_wkt.empty()) ds->SetProjection(crs_wkt.c_str());
    if (!description.empty()) ds->SetMetadataItem("TIFFTAG_IMAGEDESCRIPTION", description.c_str());
    ds->GetRasterBand(4)->SetColorInterpretation(GCI_AlphaBand);
    int bands[] = {1, 2, 3, 4};
    if (ds->RasterIO(GF_Write, 0, 0, width, height, const_cast<std::uint8_t*>(rgba.data()), width,
                     height, GDT_Byte, 4, bands, 4, std::int64_t(width) * 4, 1, nullptr) != CE_None)
      throw Error("cannot write '" + path + "': " + CPLGetLastErrorMsg());
  }  // closed: the file complete in memory
  vsi_l_offset size = 0;
  GByte* data = VSIGetMemFileBuffer(mem.c_str(), &size, FALSE);
  if (!data) throw Error("cannot write '" + path + "': GDAL kept no image");
  write_file_atomic(path, std::string_view(reinterpret_cast<const char*>(data), size));
}

}  // namespace terrain
