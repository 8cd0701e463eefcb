#pragma once
// What fuzz_pyramid runs on one input, shared with the regression test: the image's
// checksums made to match first (pyramid_fix_checksums, so that the fuzzer reaches past
// them), then the pyramid opened (header, blocks, index: every count against the file's
// size), every tile checked (check_tiles: decoded, its vertices in its blocks' boxes) and
// each level read whole where it is small. Throws terrain::Error for a bad file.
#include <fstream>
#include <string>

#include "terrain/mesh_pyramid.hpp"

namespace terrain::fuzz {

inline void pyramid_target(std::string bytes, const std::string& path) {
  pyramid_fix_checksums(bytes);
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
  MeshPyramid p(path);
  (void)p.check_tiles();
  for (int l = 0; l < p.level_count(); ++l)
    if (p.rows(l) * p.cols(l) <= 100000) (void)p.read_window(l, 0, 0, p.rows(l), p.cols(l));
}

}  // namespace terrain::fuzz
