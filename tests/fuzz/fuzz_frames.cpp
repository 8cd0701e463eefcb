// libFuzzer harness: the frame-list CSV parser of terrain-render batch.
#include <string>

#include "renderer/core/frames.hpp"
#include "terrain/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    (void)renderer::parse_frames_csv(text, renderer::FrameParams{}, "fuzz.csv");
  } catch (const terrain::Error&) {
  }
  return 0;
}
