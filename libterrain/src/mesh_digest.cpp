#include "terrain/mesh_digest.hpp"

#define XXH_INLINE_ALL
#include <xxhash.h>

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>

namespace terrain {

struct MeshDigest::State {
  XXH3_state_t xxh;
};

MeshDigest::MeshDigest() : state_(std::make_unique<State>()) { XXH3_64bits_reset(&state_->xxh); }
MeshDigest::~MeshDigest() = default;

void MeshDigest::add(const Eigen::Vector3f* positions, const Eigen::Vector3f* normals,
                     std::size_t n) {
  static_assert(std::endian::native == std::endian::little,
                "the digest is of little-endian floats");
  constexpr std::size_t kChunk = 2048;  // vertices interleaved at a time
  std::array<char, 24 * kChunk> buf;
  for (std::size_t i = 0; i < n; i += kChunk) {
    const std::size_t k = std::min(kChunk, n - i);
    for (std::size_t j = 0; j < k; ++j) {
      std::memcpy(&buf[24 * j], positions[i + j].data(), 12);
      std::memcpy(&buf[24 * j + 12], normals[i + j].data(), 12);
    }
    XXH3_64bits_update(&state_->xxh, buf.data(), 24 * k);
  }
}

std::uint64_t MeshDigest::value() const { return XXH3_64bits_digest(&state_->xxh); }

std::uint64_t mesh_digest(const GridMesh& mesh) {
  MeshDigest d;
  d.add(mesh.positions.data(), mesh.normals.data(),
        std::min(mesh.positions.size(), mesh.normals.size()));
  return d.value();
}

std::string digest_text(std::uint64_t digest) { return fmt::format("{:016x}", digest); }

}  // namespace terrain
