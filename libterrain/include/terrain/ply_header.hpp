#pragma once
// A strict reader of PLY headers (Turk 1994; http://paulbourke.net/dataformats/ply/),
// run before any PLY body parser sees a file: every line is checked, so that a damaged
// header is one clear Error instead of a crash, a hang or an allocation of gigabytes in
// the body parser (tests/terrain/ply_header_test.cpp, tests/fuzz/).
#include <cstdint>
#include <istream>
#include <string>
#include <vector>

namespace terrain {

struct PlyProperty {
  std::string name;
  int size = 0;        // bytes of the scalar (of each list item for a list)
  int count_size = 0;  // bytes of a list's count, 0 for a scalar property
  bool is_float = false;
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
  // Bytes of one record in a binary file; for list properties, assuming `list_items`
  // items in every list.
  std::uint64_t record_bytes(int list_items) const;
  const PlyProperty* find(const std::string& property) const;
};

struct PlyHeader {
  std::string format;                 // "ascii", "binary_little_endian" or "binary_big_endian"
  std::vector<std::string> comments;  // the text after "comment "
  std::vector<PlyElement> elements;   // in file order
  std::uint64_t header_bytes = 0;     // up to and including the end_header line
  const PlyElement* find(const std::string& element) const;
};

// Reads the header at the start of `in`. Throws Error("cannot read 'NAME': ...") for: no
// "ply" magic, a missing or unknown format, an element without a count or with a count
// that is not a number below 2^40, a duplicate element, an unknown property type, a
// property outside any element or named twice in one, a line over 64 KiB, a header over
// 16 MiB, and no end_header.
PlyHeader read_ply_header(std::istream& in, const std::string& name);

}  // namespace terrain
