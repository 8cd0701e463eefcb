/* The contract between the renderer's C++ and its GLSL, defined once: binding points of
   the uniform block and the storage buffers, texture units, explicit uniform and
   attribute locations, the members of the per-frame uniform block, and the compute
   work-group size. Only #define lines and comments, so the same file is C++ and GLSL:
   C++ includes it (renderer/gl/gl_contract.hpp) and build_program() inserts it after the
   #version line of every shader stage. tests/renderer/gl_contract_test.cpp checks every
   program's interface against it by introspection (glGetProgramResource*). */
#ifndef TERRAIN_RENDERER_GL_CONTRACT_H
#define TERRAIN_RENDERER_GL_CONTRACT_H

/* Work-group size of every compute shader (x; y and z are 1). */
#define TR_LOCAL_SIZE 256

/* Uniform block: the per-frame block, std140. Members in order (type, name); comments:
   u_eye      xyz eye, w vertical exaggeration
   u_sight    orthographic (the top view): xyz the line of sight, w the far plane's distance
              from the eye plane (> 0); perspective: 0 (orthographic(), to_eye, view_distance)
   u_light    xyz unit vector towards the light
   u_viewport width, height, pixels per triangle edge, maximum tessellation level
   u_weights  sw, iw, fw, divisor (sw + iw + fw, or 3)
   u_score    min score, falloff, far distance, crease lift (metres)
   u_lines    crease width at basin share 0 and 1 (pixels), tessellation override (> 0: every
              patch at this level; tess_override()), reversed z (1: reversed_z())
   u_misc     near plane distance, segment count, vertex count, shortest crease stroke
              (metres; 0: any)
   u_style    anti-aliased lines (1) or pixel-exact (0), crease fade band (score units;
              0: cut), score near distance, crease gap bridged (metres; 0: none)
   u_lod      levels of detail: x the squared plan length (m^2) above which a patch edge
              makes its patch coarse (a level above 0: facing by its geometry, coarse());
              0: none is
   u_strokes  hidden run drawn (pixels; 0: none), how far behind the surface (metres),
              shortest peek drawn (pixels; 0: any), the page's channel-initiation area
              (m^2: vertices draining less score -1; 0: any) */
#define TR_UBO_FRAME 0
#define TR_FRAME_BLOCK(M) \
  M(mat4, u_view_proj)    \
  M(vec4, u_eye)          \
  M(vec4, u_sight)        \
  M(vec4, u_light)        \
  M(vec4, u_viewport)     \
  M(vec4, u_weights)      \
  M(vec4, u_score)        \
  M(vec4, u_lines)        \
  M(vec4, u_misc)         \
  M(vec4, u_style)        \
  M(vec4, u_lod)          \
  M(vec4, u_strokes)

/* Shader storage buffers. */
#define TR_SSBO_CREASE_VERTICES 1
#define TR_SSBO_CREASE_SEGMENTS 2
#define TR_SSBO_CREASE_SCORES 3
#define TR_SSBO_CREASE_COMMAND 4
#define TR_SSBO_CREASE_SELECTED 5
#define TR_SSBO_MESH_POSITIONS 6
#define TR_SSBO_MESH_NORMALS 7
#define TR_SSBO_CORNER_AREAS 8
#define TR_SSBO_VERTEX_AREAS 9
#define TR_SSBO_TANGENTS 10
#define TR_SSBO_PEL_FIELDS 11
#define TR_SSBO_PEL_MAX_M 12
#define TR_SSBO_PEL_COMMAND 13
#define TR_SSBO_PEL_SEGMENTS 14
#define TR_SSBO_ID_TRIANGLES 15
#define TR_SSBO_EDGES 16
#define TR_SSBO_EDGE_KINDS 17
#define TR_SSBO_EDGE_COMMAND 18
#define TR_SSBO_EDGE_LIST 19
#define TR_SSBO_VERTEX_EDGES 20
#define TR_SSBO_CREASE_CHAINS 21
#define TR_SSBO_CREASE_OPACITY 22
#define TR_SSBO_PIECE_LABELS 23
#define TR_SSBO_PIECE_SIZES 24
#define TR_SSBO_PIECE_LIST 25
#define TR_SSBO_PEL_FACE_SEGMENTS 26
#define TR_SSBO_PEL_SMOOTHED 27
#define TR_SSBO_CREASE_SAMPLES 28
#define TR_SSBO_TILE_RECTS 29
#define TR_SSBO_SURFACE_INDICES 30
#define TR_SSBO_AWAY_PATCHES 31
#define TR_SSBO_AWAY_DRAWS 32
#define TR_SSBO_HACHURE_FIELD 33
#define TR_SSBO_FLAT_PATCHES 34

/* Crease strokes: "no segment" in the chains (renderer::kNoSegment), and how many
   segments a stroke's run is followed each way (renderer::kStrokeReach). */
#define TR_SEGMENT_NONE 0xFFFFFFFFu
#define TR_STROKE_REACH 64
/* Samples per crease segment for hidden-line removal along strokes, the bits of a mask
   (renderer::kStrokeSamples). */
#define TR_STROKE_SAMPLES 32

/* Patches per indirect draw of the away-facing patches (surface_cull.comp.glsl lists them,
   3 vertices each; renderer::passes::kPatchesPerDraw, which says why 64). */
#define TR_PATCHES_PER_DRAW 64u

/* Anti-aliased silhouettes are drawn as a band this many pixels wider than the
   silhouette width (composite.frag.glsl; the tiles' reach and the vector output's widths
   follow it). */
#define TR_SILHOUETTE_BAND 0.8

/* Silhouette pieces join pixels within this Chebyshev distance (renderer::kSilhouetteJoin);
   formulated silhouettes look this many pixels behind a pixel for its far side
   (renderer::kFormulatedReach). */
#define TR_SILHOUETTE_JOIN 5
#define TR_FORMULATED_REACH 4
/* A silhouette piece fades in over this share of --silhouette-min-length below it
   (renderer::kSilhouetteFade): strokes, not dashes that fade out. */
#define TR_SILHOUETTE_FADE 0.25

/* The frame block's u_lines.z and .w by name (common.glsl: tess_override(), reversed_z()). */

/* Piece rules (union_find.glsl): the label of a root. */
#define TR_PIECE_ROOT 0xFFFFFFFFu

/* Object-space edges: kinds (bit flags, as renderer::EdgeKind), the edges of a vertex
   (slots per vertex; a grid vertex has at most 6), "no vertex / no edge", cap styles, and
   the smallest cos(half the turn) a mitred join keeps (SVG's miter limit 4). */
#define TR_EDGE_CONTOUR 1u
#define TR_EDGE_BOUNDARY 2u
#define TR_EDGE_CREASE 4u
#define TR_EDGE_FACING 8u
#define TR_EDGE_SLOTS 6u
#define TR_EDGE_NONE 0xFFFFFFFFu
#define TR_CAPS_NONE 0
#define TR_CAPS_CHEAP 1
#define TR_CAPS_EXACT 2
#define TR_MITER_MIN_COS 0.25

/* Texture units. */
#define TR_TEX_TOWARD_DEPTH 0
#define TR_TEX_AWAY_DEPTH 1
#define TR_TEX_SURFACE_COLOUR 1
#define TR_TEX_CREASE_COLOUR 2
#define TR_TEX_CREASE_DEPTH 3
#define TR_TEX_SILHOUETTE 4
#define TR_TEX_PEL_COLOUR 5
#define TR_TEX_PEL_DEPTH 6
#define TR_TEX_TRIANGLE_ID 2
#define TR_TEX_ID_DEPTH 3
#define TR_TEX_EDGE_COLOUR 7
#define TR_TEX_EDGE_DEPTH 8
#define TR_TEX_SILHOUETTE_TILES 9
#define TR_TEX_AWAY_TILES 10
#define TR_TEX_TILE_MARKS 11
#define TR_TEX_SURFACE_NORMAL 12
#define TR_TEX_FORMULATED_FACING 13
#define TR_TEX_FORMULATED_TILES 14

/* Image units: the silhouette opacity the piece rule writes (r8); the tiles of
   TR_SILHOUETTE_TILE x TR_SILHOUETTE_TILE pixels that hold a silhouette pixel (r8, 1),
   where LAY looks for silhouettes near a pixel before its window; the tiles that hold an
   away-facing surface pixel (r8, 1), where SIL looks for silhouettes; the tiles' classes
   for the formulated silhouettes, then the tiles near which they may lie (r8, 1), where SIL
   looks for them (formulated_tiles.comp.glsl); the tiles a crease covers (r8, 1), where LAY
   composites the creases over the copied surface. */
#define TR_IMG_SILHOUETTE_OPACITY 0
#define TR_IMG_SILHOUETTE_TILES 1
#define TR_IMG_AWAY_TILES 2
#define TR_IMG_FORMULATED_TILES 3
#define TR_IMG_CREASE_TILES 4
#define TR_SILHOUETTE_TILE 8

/* Vertex attributes of the surface. */
#define TR_ATTR_POSITION 0
#define TR_ATTR_NORMAL 1

/* Uniform locations. Surface: */
#define TR_LOC_SURFACE_MODE 0
/* Composite: */
#define TR_LOC_LAYERS 0
#define TR_LOC_BACKGROUND 1
#define TR_LOC_MASK_COLOUR 2
#define TR_LOC_CREASE_COLOUR 3
#define TR_LOC_SILHOUETTE_COLOUR 4
#define TR_LOC_SILHOUETTE_WIDTH 5
#define TR_LOC_PEL_COLOUR 6
#define TR_LOC_PELS 7
/* PEL passes: */
#define TR_LOC_PEL_GRID 10
#define TR_LOC_PEL_STAGE 11
#define TR_LOC_PEL_LIGHT 12
#define TR_LOC_PEL_TAU 13
#define TR_LOC_PEL_WIDTH 14
/* Adjacency silhouettes: */
#define TR_LOC_ADJ_TOLERANCE 15
#define TR_LOC_ID_CAPACITY 16
#define TR_LOC_ADJ_EXTENT 17
/* Object-space edges: */
#define TR_LOC_EDGE_STAGE 18
#define TR_LOC_EDGE_MASK 19
#define TR_LOC_EDGE_COUNT 20
#define TR_LOC_EDGE_COS 21
#define TR_LOC_EDGE_CAPS 22
#define TR_LOC_EDGE_WIDTH 23
/* Composite, edges: */
#define TR_LOC_EDGE_COLOUR 24
#define TR_LOC_EDGES 25
/* Pieces (silhouettes: pixels; PELs: metres): */
#define TR_LOC_PIECE_STAGE 26
#define TR_LOC_PIECE_MIN 27
/* Crease visibility along strokes: */
#define TR_LOC_CREASE_STAGE 28
/* Tile rectangles (SIL and LAY draw only near marked tiles): */
#define TR_LOC_TILE_REACH 29
/* AFT's patch cull: */
#define TR_LOC_PATCH_COUNT 30
/* Hachures' field (hachure_field.comp.glsl): the inverse view-projection (a mat4: locations
   31 to 34), the tone (1 light, 0 slope). */
#define TR_LOC_HACHURE_INVERSE 31
#define TR_LOC_HACHURE_TONE 35
/* TFT's flat patches (surface_flat.vert.glsl): 1 for the coarse ones. */
#define TR_LOC_FLAT_COARSE 36
/* Formulated silhouettes (formulated.glsl): the lowered line of sight (xyz) and the
   strength (w); the step behind a pixel (window pixels, y up; (0, 0): none drawn). */
#define TR_LOC_FORMULATED 37
#define TR_LOC_FORMULATED_STEP 38

#endif
