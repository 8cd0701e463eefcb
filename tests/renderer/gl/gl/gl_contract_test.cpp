// Every program of the renderer (renderer/gl/programs.hpp) against the C++/GLSL contract
// (renderer/gl/gl_contract.h), by introspection of the linked programs: the uniform block's
// binding, size and member offsets equal the C++ FrameBlock's; every storage block,
// sampler, image, uniform and vertex input is named in the contract with the binding, unit or
// location the driver reports; compute work groups are TR_LOCAL_SIZE wide.
#include <gtest/gtest.h>

#include <cstddef>
#include <map>
#include <string>

#include "renderer/gl/gl_context.hpp"
#include "renderer/gl/gl_contract.hpp"
#include "renderer/gl/programs.hpp"

namespace renderer {
namespace {

// Names of the GLSL interface and what the contract says of each.
const std::map<std::string, int> kStorageBlocks = {{"CreaseVertices", TR_SSBO_CREASE_VERTICES},
                                                   {"CreaseSegments", TR_SSBO_CREASE_SEGMENTS},
                                                   {"Scores", TR_SSBO_CREASE_SCORES},
                                                   {"DrawCommand", TR_SSBO_CREASE_COMMAND},
                                                   {"Selected", TR_SSBO_CREASE_SELECTED},
                                                   {"MeshPositions", TR_SSBO_MESH_POSITIONS},
                                                   {"MeshNormals", TR_SSBO_MESH_NORMALS},
                                                   {"CornerAreas", TR_SSBO_CORNER_AREAS},
                                                   {"VertexAreas", TR_SSBO_VERTEX_AREAS},
                                                   {"Tangents", TR_SSBO_TANGENTS},
                                                   {"Fields", TR_SSBO_PEL_FIELDS},
                                                   {"MaxM", TR_SSBO_PEL_MAX_M},
                                                   {"PelCommand", TR_SSBO_PEL_COMMAND},
                                                   {"PelSegments", TR_SSBO_PEL_SEGMENTS},
                                                   {"IdTriangles", TR_SSBO_ID_TRIANGLES},
                                                   {"Edges", TR_SSBO_EDGES},
                                                   {"EdgeKinds", TR_SSBO_EDGE_KINDS},
                                                   {"EdgeCommand", TR_SSBO_EDGE_COMMAND},
                                                   {"EdgeList", TR_SSBO_EDGE_LIST},
                                                   {"VertexEdges", TR_SSBO_VERTEX_EDGES},
                                                   {"CreaseChains", TR_SSBO_CREASE_CHAINS},
                                                   {"Opacity", TR_SSBO_CREASE_OPACITY},
                                                   {"PieceLabels", TR_SSBO_PIECE_LABELS},
                                                   {"PieceSizes", TR_SSBO_PIECE_SIZES},
                                                   {"PieceList", TR_SSBO_PIECE_LIST},
                                                   {"FaceSegments", TR_SSBO_PEL_FACE_SEGMENTS},
                                                   {"PelSmoothed", TR_SSBO_PEL_SMOOTHED},
                                                   {"CreaseSamples", TR_SSBO_CREASE_SAMPLES},
                                                   {"TileRects", TR_SSBO_TILE_RECTS},
                                                   {"SurfaceIndices", TR_SSBO_SURFACE_INDICES},
                                                   {"AwayPatches", TR_SSBO_AWAY_PATCHES},
                                                   {"AwayDraws", TR_SSBO_AWAY_DRAWS},
                                                   {"HachureField", TR_SSBO_HACHURE_FIELD},
                                                   {"FlatPatches", TR_SSBO_FLAT_PATCHES}};
const std::map<std::string, int> kSamplers = {{"u_toward", TR_TEX_TOWARD_DEPTH},
                                              {"u_away", TR_TEX_AWAY_DEPTH},
                                              {"u_surface_colour", TR_TEX_SURFACE_COLOUR},
                                              {"u_crease", TR_TEX_CREASE_COLOUR},
                                              {"u_crease_depth", TR_TEX_CREASE_DEPTH},
                                              {"u_silhouette", TR_TEX_SILHOUETTE},
                                              {"u_pel", TR_TEX_PEL_COLOUR},
                                              {"u_pel_depth", TR_TEX_PEL_DEPTH},
                                              {"u_ids", TR_TEX_TRIANGLE_ID},
                                              {"u_id_depth", TR_TEX_ID_DEPTH},
                                              {"u_edge", TR_TEX_EDGE_COLOUR},
                                              {"u_edge_depth", TR_TEX_EDGE_DEPTH},
                                              {"u_silhouette_tiles", TR_TEX_SILHOUETTE_TILES},
                                              {"u_away_tiles", TR_TEX_AWAY_TILES},
                                              {"u_marks", TR_TEX_TILE_MARKS},
                                              {"u_normal", TR_TEX_SURFACE_NORMAL},
                                              {"u_facing", TR_TEX_FORMULATED_FACING},
                                              {"u_formulated_tiles", TR_TEX_FORMULATED_TILES}};
const std::map<std::string, int> kImages = {{"u_opacity", TR_IMG_SILHOUETTE_OPACITY},
                                            {"u_tiles", TR_IMG_SILHOUETTE_TILES},
                                            {"u_away_tiles", TR_IMG_AWAY_TILES},
                                            {"u_formulated_marks", TR_IMG_FORMULATED_TILES},
                                            {"u_crease_tiles", TR_IMG_CREASE_TILES}};
const std::map<std::string, int> kUniformLocations = {
    {"u_mode", TR_LOC_SURFACE_MODE},
    {"u_flat_coarse", TR_LOC_FLAT_COARSE},
    {"u_formulated", TR_LOC_FORMULATED},
    {"u_formulated_step", TR_LOC_FORMULATED_STEP},
    {"u_layers", TR_LOC_LAYERS},
    {"u_background", TR_LOC_BACKGROUND},
    {"u_mask_colour", TR_LOC_MASK_COLOUR},
    {"u_crease_colour", TR_LOC_CREASE_COLOUR},
    {"u_silhouette_colour", TR_LOC_SILHOUETTE_COLOUR},
    {"u_silhouette_width", TR_LOC_SILHOUETTE_WIDTH},
    {"u_pel_colour", TR_LOC_PEL_COLOUR},
    {"u_pels", TR_LOC_PELS},
    {"u_grid", TR_LOC_PEL_GRID},
    {"u_stage", TR_LOC_PEL_STAGE},
    {"u_pel_light", TR_LOC_PEL_LIGHT},
    {"u_tau", TR_LOC_PEL_TAU},
    {"u_pel_width", TR_LOC_PEL_WIDTH},
    {"u_capacity", TR_LOC_ID_CAPACITY},
    {"u_tolerance", TR_LOC_ADJ_TOLERANCE},
    {"u_extent", TR_LOC_ADJ_EXTENT},
    {"u_edge_stage", TR_LOC_EDGE_STAGE},
    {"u_edge_mask", TR_LOC_EDGE_MASK},
    {"u_edge_count", TR_LOC_EDGE_COUNT},
    {"u_edge_cos", TR_LOC_EDGE_COS},
    {"u_edge_caps", TR_LOC_EDGE_CAPS},
    {"u_edge_width", TR_LOC_EDGE_WIDTH},
    {"u_edge_colour", TR_LOC_EDGE_COLOUR},
    {"u_edges", TR_LOC_EDGES},
    {"u_piece_stage", TR_LOC_PIECE_STAGE},
    {"u_piece_min", TR_LOC_PIECE_MIN},
    {"u_crease_stage", TR_LOC_CREASE_STAGE},
    {"u_reach", TR_LOC_TILE_REACH},
    {"u_patches", TR_LOC_PATCH_COUNT},
    {"u_inverse", TR_LOC_HACHURE_INVERSE},
    {"u_tone", TR_LOC_HACHURE_TONE}};
const std::map<std::string, int> kAttributes = {{"a_position", TR_ATTR_POSITION},
                                                {"a_normal", TR_ATTR_NORMAL}};

#define TR_OFFSET(type, name) {#name, offsetof(FrameBlock, name)},
const std::map<std::string, std::size_t> kFrameOffsets = {TR_FRAME_BLOCK(TR_OFFSET)};
#undef TR_OFFSET

std::string resource_name(GLuint program, GLenum interface, GLuint index) {
  char name[256] = {};
  GLsizei length = 0;
  glGetProgramResourceName(program, interface, index, sizeof name, &length, name);
  return std::string(name, std::size_t(length));
}

GLint resource_property(GLuint program, GLenum interface, GLuint index, GLenum property) {
  GLint value = -1;
  glGetProgramResourceiv(program, interface, index, 1, &property, 1, nullptr, &value);
  return value;
}

GLint active(GLuint program, GLenum interface) {
  GLint n = 0;
  glGetProgramInterfaceiv(program, interface, GL_ACTIVE_RESOURCES, &n);
  return n;
}

bool is_sampler(GLint type) { return type == GL_SAMPLER_2D || type == GL_UNSIGNED_INT_SAMPLER_2D; }
bool is_image(GLint type) { return type == GL_IMAGE_2D; }

TEST(GlContract, EveryProgramMatchesTheContract) {
  GlContext ctx;
  std::size_t blocks = 0, samplers = 0, images = 0, locations = 0, computes = 0, frames = 0;
  for (const ProgramId id : kAllPrograms) {
    const char* name = program_spec(id).name;
    const GlObject program = build_program(id);
    const GLuint p = program.id();
    SCOPED_TRACE(name);

    for (GLint i = 0; i < active(p, GL_UNIFORM_BLOCK); ++i) {
      ASSERT_EQ(resource_name(p, GL_UNIFORM_BLOCK, GLuint(i)), "FrameBlock");
      EXPECT_EQ(resource_property(p, GL_UNIFORM_BLOCK, GLuint(i), GL_BUFFER_BINDING), TR_UBO_FRAME);
      EXPECT_EQ(resource_property(p, GL_UNIFORM_BLOCK, GLuint(i), GL_BUFFER_DATA_SIZE),
                GLint(sizeof(FrameBlock)));
      ++frames;
    }
    for (GLint i = 0; i < active(p, GL_SHADER_STORAGE_BLOCK); ++i) {
      const std::string block = resource_name(p, GL_SHADER_STORAGE_BLOCK, GLuint(i));
      ASSERT_TRUE(kStorageBlocks.count(block))
          << "storage block '" << block << "' is not in the contract";
      EXPECT_EQ(resource_property(p, GL_SHADER_STORAGE_BLOCK, GLuint(i), GL_BUFFER_BINDING),
                kStorageBlocks.at(block))
          << block;
      ++blocks;
    }
    for (GLint i = 0; i < active(p, GL_UNIFORM); ++i) {
      const std::string u = resource_name(p, GL_UNIFORM, GLuint(i));
      if (resource_property(p, GL_UNIFORM, GLuint(i), GL_BLOCK_INDEX) >=
          0) {  // a FrameBlock member
        ASSERT_TRUE(kFrameOffsets.count(u))
            << "block member '" << u << "' is not in TR_FRAME_BLOCK";
        EXPECT_EQ(std::size_t(resource_property(p, GL_UNIFORM, GLuint(i), GL_OFFSET)),
                  kFrameOffsets.at(u))
            << u;
        continue;
      }
      const GLint location = resource_property(p, GL_UNIFORM, GLuint(i), GL_LOCATION);
      const GLint type = resource_property(p, GL_UNIFORM, GLuint(i), GL_TYPE);
      if (is_image(type)) {
        ASSERT_TRUE(kImages.count(u)) << "image '" << u << "' is not in the contract";
        GLint unit = -1;
        glGetUniformiv(p, location, &unit);
        EXPECT_EQ(unit, kImages.at(u)) << u;
        ++images;
      } else if (is_sampler(type)) {
        ASSERT_TRUE(kSamplers.count(u)) << "sampler '" << u << "' is not in the contract";
        GLint unit = -1;
        glGetUniformiv(p, location, &unit);
        EXPECT_EQ(unit, kSamplers.at(u)) << u;
        ++samplers;
      } else {
        ASSERT_TRUE(kUniformLocations.count(u)) << "uniform '" << u << "' is not in the contract";
        EXPECT_EQ(location, kUniformLocations.at(u)) << u;
        ++locations;
      }
    }
    for (GLint i = 0; i < active(p, GL_PROGRAM_INPUT); ++i) {
      const std::string in = resource_name(p, GL_PROGRAM_INPUT, GLuint(i));
      if (in.rfind("gl_", 0) == 0) continue;  // built-ins (gl_VertexID, gl_GlobalInvocationID)
      ASSERT_TRUE(kAttributes.count(in)) << "vertex input '" << in << "' is not in the contract";
      EXPECT_EQ(resource_property(p, GL_PROGRAM_INPUT, GLuint(i), GL_LOCATION), kAttributes.at(in))
          << in;
    }
    if (program_spec(id).stages.front().stage == GL_COMPUTE_SHADER) {
      GLint size[3] = {};
      glGetProgramiv(p, GL_COMPUTE_WORK_GROUP_SIZE, size);
      EXPECT_EQ(size[0], TR_LOCAL_SIZE);
      EXPECT_EQ(size[1], 1);
      EXPECT_EQ(size[2], 1);
      ++computes;
    }
  }
  // The checks ran on the interfaces there are (a program could lose them silently).
  EXPECT_EQ(computes, 14u);
  EXPECT_GE(frames, 9u);
  EXPECT_GE(blocks, 14u);
  EXPECT_EQ(samplers, 45u);  // silhouette 4, formulated 3, formulated facing 2, formulated tiles 1,
                             // tile rects 2, composite 8 + 10 (with silhouettes)
                             // + 8 (on the crease tiles), adjacency 2, crease visibility and
                             // PEL draw 1 each, pieces 1, hachure field 2
  EXPECT_EQ(images, 7u);  // pieces (opacity), silhouette, formulated and adjacency (tiles), AFT's
                          // surface (away tiles), formulated tiles, crease draw (tiles)
  EXPECT_GE(locations, 14u);
}

// Dispatch sizes cover every item once with groups of TR_LOCAL_SIZE.
TEST(GlContract, DispatchCoversEveryItem) {
  for (std::size_t n : {std::size_t(1), std::size_t(255), std::size_t(256), std::size_t(257),
                        std::size_t(65535) * TR_LOCAL_SIZE + 1, std::size_t(40'000'000)}) {
    const std::size_t x = dispatch_groups_x(n), y = dispatch_groups_y(n);
    EXPECT_LE(x, 65535u);
    EXPECT_GE(x * y * TR_LOCAL_SIZE, n) << n;
    EXPECT_LT((x * (y - 1)) * TR_LOCAL_SIZE, n) << n;  // no whole row of groups is idle
  }
}

}  // namespace
}  // namespace renderer
