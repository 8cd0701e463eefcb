#pragma once
// Ink of a rendered picture (tests): which pixels carry lines, and how near two pictures'
// lines lie to each other (vector output vs PNG, one network vs another).
#include <gtest/gtest.h>

#include <OpenImageIO/imagebuf.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

namespace terrain::test {

struct Ink {
  int w = 0, h = 0;
  std::vector<std::uint8_t> on;
};

// The pixels a picture draws: any not the background (#dde4ec) by more than 48 of 255.
inline Ink drawn_of(const std::string& png);

// Ink: a pixel neither the background (#dde4ec) nor the mask (white), by more than 48 of
// 255 in some channel (the mask's anti-aliased rim, at most 0x22 from both, is not ink).
inline Ink ink_of(const std::string& png, bool mask_is_ink = false) {
  OIIO::ImageBuf buf(png);
  EXPECT_TRUE(buf.read(0, 0, true, OIIO::TypeDesc::UINT8)) << png;
  const auto& spec = buf.spec();
  Ink ink{spec.width, spec.height,
          std::vector<std::uint8_t>(std::size_t(spec.width) * std::size_t(spec.height))};
  std::vector<std::uint8_t> px(std::size_t(spec.width) * std::size_t(spec.height) * 3);
  buf.get_pixels(OIIO::ROI(0, spec.width, 0, spec.height, 0, 1, 0, 3), OIIO::TypeDesc::UINT8,
                 px.data());
  const int bg[3] = {0xdd, 0xe4, 0xec};
  for (std::size_t i = 0; i < ink.on.size(); ++i) {
    int d_bg = 0, d_mask = 0;
    for (int c = 0; c < 3; ++c) {
      d_bg = std::max(d_bg, std::abs(px[3 * i + std::size_t(c)] - bg[c]));
      d_mask = std::max(d_mask, 255 - px[3 * i + std::size_t(c)]);
    }
    ink.on[i] = (mask_is_ink ? d_bg : std::min(d_bg, d_mask)) > 48;
  }
  return ink;
}

inline Ink drawn_of(const std::string& png) { return ink_of(png, true); }

// The share of a's ink pixels with ink of b within `radius` px (their (2 radius + 1)^2
// window); 1 without ink.
inline double near_share(const Ink& a, const Ink& b, int radius = 1) {
  std::size_t n = 0, near = 0;
  for (int y = 0; y < a.h; ++y)
    for (int x = 0; x < a.w; ++x) {
      if (!a.on[std::size_t(y * a.w + x)]) continue;
      ++n;
      bool hit = false;
      for (int dy = -radius; dy <= radius && !hit; ++dy)
        for (int dx = -radius; dx <= radius && !hit; ++dx) {
          const int u = x + dx, v = y + dy;
          hit = u >= 0 && v >= 0 && u < b.w && v < b.h && b.on[std::size_t(v * b.w + u)];
        }
      near += hit;
    }
  return n ? double(near) / double(n) : 1.0;
}

inline std::size_t count(const Ink& a) {
  return std::size_t(std::count(a.on.begin(), a.on.end(), 1));
}

}  // namespace terrain::test
