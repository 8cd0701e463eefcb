#include "renderer/gl/gl_objects.hpp"

namespace renderer {

GlObject::GlObject(GlKind kind, GLenum target) : kind_(kind) {
  switch (kind) {
    case GlKind::Buffer:
      glCreateBuffers(1, &id_);
      break;
    case GlKind::VertexArray:
      glCreateVertexArrays(1, &id_);
      break;
    case GlKind::Texture:
      glCreateTextures(target ? target : GL_TEXTURE_2D, 1, &id_);
      break;
    case GlKind::Framebuffer:
      glCreateFramebuffers(1, &id_);
      break;
    case GlKind::Query:
      glCreateQueries(target ? target : GL_TIME_ELAPSED, 1, &id_);
      break;
    case GlKind::Program:
      id_ = glCreateProgram();
      break;
  }
}

void GlObject::reset() {
  if (id_ == 0) return;
  switch (kind_) {
    case GlKind::Buffer:
      glDeleteBuffers(1, &id_);
      break;
    case GlKind::VertexArray:
      glDeleteVertexArrays(1, &id_);
      break;
    case GlKind::Texture:
      glDeleteTextures(1, &id_);
      break;
    case GlKind::Framebuffer:
      glDeleteFramebuffers(1, &id_);
      break;
    case GlKind::Query:
      glDeleteQueries(1, &id_);
      break;
    case GlKind::Program:
      glDeleteProgram(id_);
      break;
  }
  id_ = 0;
}

GlObject make_buffer(std::size_t bytes, const void* data, GLbitfield flags) {
  GlObject b(GlKind::Buffer);
  glNamedBufferStorage(b.id(), GLsizeiptr(bytes > 0 ? bytes : 4), bytes > 0 ? data : nullptr,
                       flags);
  return b;
}

GlObject make_texture(GLenum format, int width, int height) {
  GlObject t(GlKind::Texture, GL_TEXTURE_2D);
  glTextureStorage2D(t.id(), 1, format, width, height);
  glTextureParameteri(t.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(t.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTextureParameteri(t.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(t.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  return t;
}

}  // namespace renderer
