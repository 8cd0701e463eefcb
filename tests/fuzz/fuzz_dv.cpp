// libFuzzer harness: the .dv reader and what reads a database (summary, elevations,
// preview). The CRC field is recomputed for every input, so the fuzzer reaches the checks
// behind the checksum (a hostile file can match its CRC too). Format version 1 only: it
// is the only version there is.
#include <cstring>
#include <string>
#include <vector>

#include "drainage/dv_file.hpp"
#include "drainage/dv_views.hpp"
#include "fuzz_support.hpp"
#include "terrain/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<std::uint8_t> bytes(data, data + size);
  if (bytes.size() >= 20) {
    const std::uint32_t crc = drainage::dv_checksum(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    std::memcpy(bytes.data() + 16, &crc, 4);
  }
  const std::string path = terrain::fuzz::input_file(bytes.data(), bytes.size(), ".dv");
  try {
    const drainage::DrainageDb db = drainage::read_dv(path);
    (void)drainage::summarize(db);
    if (db.vertices.size() <= (1u << 20)) (void)drainage::dv_preview(db);
  } catch (const terrain::Error&) {
  }
  return 0;
}
