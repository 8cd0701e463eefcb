// libFuzzer harness: the .dv reader and what reads a database (summary, elevations,
// preview, a window). Every checksum is recomputed for every input (dv_fix_checksums), so
// the fuzzer reaches the checks behind them (a hostile file can match its CRCs too).
// Versions 1 and 2 (the corpus holds both).
#include <cstring>
#include <string>
#include <vector>

#include "drainage/dv_file.hpp"
#include "drainage/dv_views.hpp"
#include "fuzz_support.hpp"
#include "terrain/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<std::uint8_t> bytes(data, data + size);
  drainage::dv_fix_checksums(reinterpret_cast<char*>(bytes.data()), bytes.size());
  const terrain::fuzz::InputFile input(bytes.data(), bytes.size(), ".dv");
  const std::string& path = input.path;
  try {
    const drainage::DrainageDb db = drainage::read_dv(path);
    (void)drainage::summarize(db);
    if (db.vertices.size() <= (1u << 20)) (void)drainage::dv_preview(db);
    (void)drainage::read_dv_window(path, db.header.rows / 3, db.header.cols / 4, 7, 5);
  } catch (const terrain::Error&) {
  }
  return 0;
}
