#pragma once
// Move-only RAII owners of GL object names. Include after a context exists.
#include <epoxy/gl.h>

#include <utility>

namespace renderer {

enum class GlKind { Buffer, VertexArray, Texture, Framebuffer, Query, Program };

class GlObject {
 public:
  GlObject() = default;
  explicit GlObject(GlKind kind, GLenum target = 0);  // glCreate* (DSA)
  ~GlObject() { reset(); }
  GlObject(GlObject&& o) noexcept : kind_(o.kind_), id_(std::exchange(o.id_, 0)) {}
  GlObject& operator=(GlObject&& o) noexcept {
    if (this != &o) {
      reset();
      kind_ = o.kind_;
      id_ = std::exchange(o.id_, 0);
    }
    return *this;
  }
  GlObject(const GlObject&) = delete;
  GlObject& operator=(const GlObject&) = delete;

  GLuint id() const { return id_; }
  void reset();

 private:
  GlKind kind_ = GlKind::Buffer;
  GLuint id_ = 0;
};

// A buffer with immutable storage of `bytes` (glNamedBufferStorage), optionally filled.
GlObject make_buffer(std::size_t bytes, const void* data,
                     GLbitfield flags = GL_DYNAMIC_STORAGE_BIT);
// A 2-D texture with one level of `format` (nearest filtering, clamped).
GlObject make_texture(GLenum format, int width, int height);

}  // namespace renderer
