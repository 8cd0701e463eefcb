// SIL and LAY: full-screen passes over the other passes' images.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <stdexcept>

#include "passes.hpp"
#include "renderer/gl/gl_contract.hpp"
#include "renderer/gl/programs.hpp"

namespace renderer::passes {

TriangleIdPass::TriangleIdPass(const SceneGpu& scene, bool enabled, std::size_t capacity)
    : PassBase(AFT), s_(scene), enabled_(enabled), capacity_(enabled ? capacity : 0) {
  if (!enabled_) return;
  ids_ = make_texture(GL_R32UI, scene.width, scene.height);
  depth_ = make_texture(GL_DEPTH_COMPONENT32F, scene.width, scene.height);
  fbo_ = make_framebuffer(&ids_, &depth_);
  triangles_ = make_buffer(16 + capacity_ * 3 * 16, nullptr, GL_DYNAMIC_STORAGE_BIT);
  prog_ = build_program(ProgramId::SurfaceId);
  glProgramUniform1ui(prog_.id(), TR_LOC_ID_CAPACITY, GLuint(capacity_));
}

void TriangleIdPass::execute(const FrameInputs&) {
  if (!enabled_) return;
  const GLuint zero_id[4] = {0, 0, 0, 0};
  const float far_depth = s_.clear_depth();
  const std::uint32_t zero = 0;
  glNamedBufferSubData(triangles_.id(), 0, 4, &zero);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
  glClearNamedFramebufferuiv(fbo_.id(), GL_COLOR, 0, zero_id);
  glClearNamedFramebufferfv(fbo_.id(), GL_DEPTH, 0, &far_depth);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_ID_TRIANGLES, triangles_.id());
  s_.depth_state();
  s_.draw_patches(prog_, 2);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
}

std::size_t TriangleIdPass::triangles_drawn() const {
  if (!enabled_) return 0;
  std::uint32_t n = 0;
  glGetNamedBufferSubData(triangles_.id(), 0, 4, &n);
  return n;
}

SilhouettePass::SilhouettePass(const SceneGpu& scene, bool enabled, double piece_min_px,
                               const Style& style, const TriangleIdPass* ids, double tolerance,
                               const Eigen::Vector4f& extent)
    : PassBase(SIL),
      s_(scene),
      enabled_(enabled),
      piece_min_px_(enabled ? std::max(0.0, piece_min_px) : 0.0),
      ids_(ids),
      tolerance_(tolerance),
      extent_(extent),
      mask_(make_texture(GL_R8, scene.width, scene.height)),
      fbo_(make_framebuffer(&mask_, nullptr)),
      prog_(build_program(ids ? ProgramId::Adjacency : ProgramId::Silhouette)),
      tiles_(scene.make_tile_texture()) {
  if (!ids_) {
    formulated_ = enabled && style.formulated;  // Toward/Away only
    if (formulated_ && !scene.surface_normal.id())
      throw std::logic_error("formulated silhouettes need the scene's normals");
    formulated_altitude_ = style.formulated_altitude;
    formulated_strength_ = style.formulated_strength;
    if (formulated_) {
      formulated_prog_ = build_program(ProgramId::Formulated);
      facing_prog_ = build_program(ProgramId::FormulatedFacing);
      facing_ = make_texture(GL_R32F, scene.width, scene.height);
      facing_fbo_ = make_framebuffer(&facing_, nullptr);
      formulated_classes_ = scene.make_tile_texture();
      formulated_tiles_ = scene.make_tile_texture();
      formulated_classes_prog_ = build_program(ProgramId::FormulatedTiles);
      formulated_tiles_prog_ =
          build_program(ProgramId::FormulatedTiles, "#define TR_FORMULATED_MARKS 1\n");
      glProgramUniform1f(formulated_prog_.id(), TR_LOC_PIECE_MIN, float(piece_min_px_));
    }
  }
  glProgramUniform1f(prog_.id(), TR_LOC_PIECE_MIN, float(piece_min_px_));
  if (piece_min_px_ <= 0) return;
  const std::size_t n = std::size_t(scene.width) * std::size_t(scene.height);
  opacity_ = make_texture(GL_R8, scene.width, scene.height);
  labels_ = make_buffer(4 * n, nullptr, 0);
  sizes_ = make_buffer(4 * n, nullptr, 0);
  list_ = make_buffer(16 + 4 * n, nullptr, GL_DYNAMIC_STORAGE_BIT);
  pieces_prog_ = build_program(ProgramId::SilhouettePieces);
  glProgramUniform1f(pieces_prog_.id(), TR_LOC_PIECE_MIN, float(piece_min_px_));
  clear_pieces();  // the list's count bounds what warm_up_timer's draw appends
}

void SilhouettePass::clear_pieces() const {
  // The labels and sizes are set as pixels are listed (silhouette_list.glsl).
  const GLuint header[4] = {0, 0, 1, 1};
  glNamedBufferSubData(list_.id(), 0, sizeof header, header);
  glClearTexImage(opacity_.id(), 0, GL_RED, GL_UNSIGNED_BYTE, nullptr);
}

void SilhouettePass::pieces() const {
  const GLuint p = pieces_prog_.id();
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
  glUseProgram(p);
  glBindTextureUnit(TR_TEX_SILHOUETTE, mask_.id());
  glBindImageTexture(TR_IMG_SILHOUETTE_OPACITY, opacity_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY,
                     GL_R8);
  glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, list_.id());
  for (int stage = 1; stage <= 3; ++stage) {
    glProgramUniform1i(p, TR_LOC_PIECE_STAGE, stage);
    glDispatchComputeIndirect(4);
    glMemoryBarrier(stage < 3 ? GL_SHADER_STORAGE_BARRIER_BIT
                              : GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  }
  glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
}

namespace {
// The formulated silhouettes' uniforms of `program` (the step: where it reads it).
void set_formulated(const GlObject& program, const FormulatedView& f, bool step) {
  glProgramUniform4f(program.id(), TR_LOC_FORMULATED, f.direction.x(), f.direction.y(),
                     f.direction.z(), f.strength);
  if (step) glProgramUniform2i(program.id(), TR_LOC_FORMULATED_STEP, f.step_x, f.step_up);
}
}  // namespace

void SilhouettePass::draw_formulated(const FormulatedView& f) const {
  // The tiles near which a formulated pixel may lie (formulated_tiles.comp.glsl: each
  // tile's classes, then the marks); the smoothed facing within what the test reads about
  // them, once; then the test within the reach of a formulated pixel. The same pixels as
  // both over the whole image.
  set_formulated(formulated_classes_prog_, f, false);
  set_formulated(facing_prog_, f, false);
  set_formulated(formulated_prog_, f, true);
  glBindTextureUnit(TR_TEX_SURFACE_NORMAL, s_.surface_normal.id());
  for (const auto& [prog, out] : {std::pair{&formulated_classes_prog_, &formulated_classes_},
                                  std::pair{&formulated_tiles_prog_, &formulated_tiles_}}) {
    glUseProgram(prog->id());
    glBindImageTexture(TR_IMG_FORMULATED_TILES, out->id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R8);
    glDispatchCompute(dispatch_groups_x(s_.tile_count()), dispatch_groups_y(s_.tile_count()), 1);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
    glBindTextureUnit(TR_TEX_FORMULATED_TILES, out->id());
  }
  // The test at p, within TR_FORMULATED_REACH + 1 of a marked tile, reads the facing at
  // p + k step, |k| <= TR_FORMULATED_REACH: the facing is drawn that far more along the step.
  glBindFramebuffer(GL_FRAMEBUFFER, facing_fbo_.id());
  s_.draw_near_tiles(formulated_tiles_, TR_FORMULATED_REACH * (1 + std::abs(f.step_x)) + 1,
                     TR_FORMULATED_REACH * (1 + std::abs(f.step_up)) + 1, facing_prog_);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
  glBindTextureUnit(TR_TEX_FORMULATED_FACING, facing_.id());
  s_.draw_near_tiles(formulated_tiles_, TR_FORMULATED_REACH + 1, formulated_prog_);
}

void SilhouettePass::draw(double pixel_angle, const FormulatedView& formulated) const {
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
  glClearTexImage(tiles_.id(), 0, GL_RED, GL_UNSIGNED_BYTE, nullptr);
  glBindImageTexture(TR_IMG_SILHOUETTE_TILES, tiles_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R8);
  if (piece_min_px_ > 0) {
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_PIECE_LABELS, labels_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_PIECE_SIZES, sizes_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_PIECE_LIST, list_.id());
  }
  if (!ids_) {
    // The formulated silhouettes first; the Toward/Away test then leaves theirs (it reads
    // the same uniforms: none when the step is 0).
    const FormulatedView f = formulated_ ? formulated : FormulatedView{};
    set_formulated(prog_, f, true);
    if (f.active()) draw_formulated(f);
  }
  glUseProgram(prog_.id());
  if (ids_) {
    glProgramUniform2f(prog_.id(), TR_LOC_ADJ_TOLERANCE, float(tolerance_), float(pixel_angle));
    glProgramUniform4fv(prog_.id(), TR_LOC_ADJ_EXTENT, 1, extent_.data());
    glBindTextureUnit(TR_TEX_TRIANGLE_ID, ids_->ids().id());
    glBindTextureUnit(TR_TEX_ID_DEPTH, ids_->depth().id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_ID_TRIANGLES, ids_->triangles().id());
    glBindVertexArray(s_.empty_vao.id());
    glDrawArrays(GL_TRIANGLES, 0, 3);
  } else {
    // Toward/Away: the test on the pixels within one pixel of a tile that holds an away
    // depth (AFT marked them; no silhouette pixel lies elsewhere).
    glBindTextureUnit(TR_TEX_TOWARD_DEPTH, s_.toward_depth.id());
    glBindTextureUnit(TR_TEX_AWAY_DEPTH, s_.away_depth.id());
    s_.draw_near_tiles(s_.away_tiles, 1, prog_);
  }
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
}

void SilhouettePass::execute(const FrameInputs& in) {
  const float zero4[4] = {0, 0, 0, 0};
  glClearNamedFramebufferfv(fbo_.id(), GL_COLOR, 0, zero4);
  if (!enabled_) return;
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
  glDisable(GL_DEPTH_TEST);
  if (piece_min_px_ > 0) clear_pieces();
  // The angle one pixel spans at the image centre (vertical field of view over the height);
  // orthographic: the metres it spans.
  draw(in.view.pixel_size(1.0),
       formulated_view(in.view, formulated_altitude_, formulated_strength_));
  if (piece_min_px_ > 0) pieces();
}

void SilhouettePass::warm_up_timer() const {
  GlObject q(GlKind::Query, GL_TIME_ELAPSED);
  const float zero4[4] = {0, 0, 0, 0};
  glBeginQuery(GL_TIME_ELAPSED, q.id());
  glClearNamedFramebufferfv(fbo_.id(), GL_COLOR, 0, zero4);
  glBindBufferBase(GL_UNIFORM_BUFFER, TR_UBO_FRAME, s_.ubo.id());
  if (piece_min_px_ > 0) clear_pieces();
  draw(0.0, FormulatedView{});
  glEndQuery(GL_TIME_ELAPSED);
  GLuint64 ns = 0;
  glGetQueryObjectui64v(q.id(), GL_QUERY_RESULT, &ns);
}

CompositePass::CompositePass(const SceneGpu& scene, const Layers& layers, const Style& style,
                             const CreasePass& creases, const PelPass& pels, const EdgePass& edges,
                             const SilhouettePass& silhouettes)
    : PassBase(LAY),
      s_(scene),
      layers_(layers),
      style_(style),
      creases_(creases),
      pels_(pels),
      edges_(edges),
      silhouettes_(silhouettes),
      copy_base_(surface_is_base(layers, style)),
      colour_(make_texture(GL_RGBA8, scene.width, scene.height)),
      fbo_(make_framebuffer(&colour_, nullptr)),
      prog_(copy_base_ ? GlObject() : build_program(ProgramId::Composite, defines())),
      silhouettes_prog_(build_program(ProgramId::CompositeSilhouettes, defines())) {
  if (copy_base_ && layers.creases)
    creases_prog_ = build_program(ProgramId::CompositeCreases, defines());
}

bool CompositePass::surface_is_base(const Layers& layers, const Style& style) {
  return layers.shaded && !style.transparent && !layers.pels && !layers.edges;
}

std::string CompositePass::defines() const {
  std::string d;
  if (!pels_.active()) d += "#define TR_COMPOSITE_NO_PELS 1\n";
  if (!layers_.creases) d += "#define TR_COMPOSITE_NO_CREASES 1\n";
  if (!edges_.active()) d += "#define TR_COMPOSITE_NO_EDGES 1\n";
  if (style_.antialias) d += "#define TR_COMPOSITE_ANTIALIASED 1\n";
  if (style_.transparent) d += "#define TR_COMPOSITE_TRANSPARENT 1\n";
  if (copy_base_) d += "#define TR_COMPOSITE_SURFACE_COPIED 1\n";
  return d;
}

void CompositePass::execute(const FrameInputs&) {
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
  glDisable(GL_DEPTH_TEST);
  glBindTextureUnit(TR_TEX_TOWARD_DEPTH, s_.toward_depth.id());
  glBindTextureUnit(TR_TEX_SURFACE_COLOUR, s_.surface_colour.id());
  glBindTextureUnit(TR_TEX_CREASE_COLOUR, creases_.colour().id());
  glBindTextureUnit(TR_TEX_CREASE_DEPTH, creases_.depth().id());
  glBindTextureUnit(TR_TEX_SILHOUETTE, silhouettes_.opacity().id());
  glBindTextureUnit(TR_TEX_SILHOUETTE_TILES, silhouettes_.tiles().id());
  glBindTextureUnit(TR_TEX_PEL_COLOUR, pels_.colour().id());
  glBindTextureUnit(TR_TEX_PEL_DEPTH, pels_.depth().id());
  glBindTextureUnit(TR_TEX_EDGE_COLOUR, edges_.colour().id());
  glBindTextureUnit(TR_TEX_EDGE_DEPTH, edges_.depth().id());
  glBindVertexArray(s_.empty_vao.id());
  auto use = [&](GLuint p) {
    glUseProgram(p);
    glProgramUniform4i(p, TR_LOC_LAYERS, layers_.shaded, layers_.mask, layers_.creases,
                       layers_.silhouettes);
    glProgramUniform3fv(p, TR_LOC_BACKGROUND, 1, style_.background.data());
    glProgramUniform3fv(p, TR_LOC_MASK_COLOUR, 1, style_.mask.data());
    glProgramUniform3fv(p, TR_LOC_CREASE_COLOUR, 1, style_.crease_colour.data());
    glProgramUniform3fv(p, TR_LOC_PEL_COLOUR, 1, style_.pel_colour.data());
    glProgramUniform1i(p, TR_LOC_PELS, pels_.active() ? 1 : 0);
    glProgramUniform3fv(p, TR_LOC_EDGE_COLOUR, 1, style_.edge_colour.data());
    glProgramUniform1i(p, TR_LOC_EDGES, edges_.active() ? 1 : 0);
  };
  // Every pixel without the silhouettes, then the pixels near them again with them
  // (composite.frag.glsl). Where the surface is the base, it is copied (llvmpipe: a copy of
  // memory, not a pass over every pixel), and the creases composited only on the tiles
  // their fragments covered (CreasePass::tiles): the composite of a pixel no crease
  // covers is its surface's colour.
  if (copy_base_) {
    glCopyImageSubData(s_.surface_colour.id(), GL_TEXTURE_2D, 0, 0, 0, 0, colour_.id(),
                       GL_TEXTURE_2D, 0, 0, 0, 0, s_.width, s_.height, 1);
    if (creases_prog_.id()) {
      use(creases_prog_.id());
      s_.draw_near_tiles(creases_.tiles(), 0, creases_prog_);
    }
  } else {
    use(prog_.id());
    glDrawArrays(GL_TRIANGLES, 0, 3);
  }
  if (!layers_.silhouettes) return;
  const GLuint p = silhouettes_prog_.id();
  use(p);
  const int w = std::max(1, style_.silhouette_width);
  // No silhouette coverage beyond: anti-aliased, the band's half-width + 1.5 px (the
  // composite's silhouette_band); pixel-exact, the dilation window's larger side.
  const int reach = style_.antialias ? int(0.5 * (double(w) + TR_SILHOUETTE_BAND) + 1.5)
                                     : std::max((w - 1) / 2, w / 2);
  glProgramUniform3fv(p, TR_LOC_SILHOUETTE_COLOUR, 1, style_.silhouette_colour.data());
  glProgramUniform1i(p, TR_LOC_SILHOUETTE_WIDTH, w);
  glProgramUniform1i(p, TR_LOC_TILE_REACH, reach);
  s_.draw_near_tiles(silhouettes_.tiles(), reach, silhouettes_prog_);
}

}  // namespace renderer::passes
