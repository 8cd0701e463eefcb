#pragma once
// The digest of a mesh's vertices: XXH3-64 of each vertex's position and normal (six
// little-endian floats, the PLY's vertex record without optional data) in row order.
// dem2mesh writes it into the PLY's header (comment mesh_digest) and into the pyramid
// beside it, which a reader uses only when the two agree (docs/formats.md).
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

#include <Eigen/Core>

#include "terrain/grid_mesh.hpp"

namespace terrain {

class MeshDigest {
 public:
  MeshDigest();
  ~MeshDigest();
  MeshDigest(const MeshDigest&) = delete;
  MeshDigest& operator=(const MeshDigest&) = delete;
  // The next n vertices.
  void add(const Eigen::Vector3f* positions, const Eigen::Vector3f* normals, std::size_t n);
  std::uint64_t value() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

std::uint64_t mesh_digest(const GridMesh& mesh);

// The digest as the files write it: 16 lower-case hexadecimal digits.
std::string digest_text(std::uint64_t digest);

}  // namespace terrain
