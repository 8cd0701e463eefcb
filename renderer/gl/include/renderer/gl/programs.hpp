#pragma once
// Every GLSL program of the renderer, named: which embedded files make each stage. The
// renderer builds its programs from this table, and tests/renderer/gl_contract_test.cpp
// checks the interface of every program in it against renderer/gl/gl_contract.h.
#include <array>
#include <string>
#include <vector>

#include "renderer/gl/shader.hpp"

namespace renderer {

enum class ProgramId {
  Surface,               // TFT/AFT: PN patches, tessellated (surface.*)
  PnCapture,             // the same without rasterization, captured by transform feedback (tests)
  CreaseScore,           // DM: score of every crease vertex
  CreaseBridge,          // DM: opacity of every segment (fade, gaps bridged)
  CreaseSelect,          // DM: segments drawn (strokes long enough), indirect draw command
  CreaseDraw,            // DM: the selected segments as screen-space quads
  Silhouette,            // SIL: Toward/Away
  Composite,             // LAY: every pixel, without the silhouettes
  CompositeSilhouettes,  // LAY: again, the pixels near silhouettes, with them
  PelFields,             // PEL: per-vertex fields
  PelExtract,            // PEL: zero-crossing segments, indirect draw command
  PelDraw,               // PEL: the segments as quads
  SurfaceId,             // Adjacency silhouettes: triangle IDs and the triangle list
  Adjacency,             // Adjacency silhouettes: the full-screen pass
  EdgeClassify,          // EDGE: classify the edges, find the joins, append (indirect draw command)
  EdgeDraw,              // EDGE: the drawn edges as quads with caps
  SilhouettePieces,      // SIL: silhouette pieces and their opacity (anti-aliased)
  PelPieces,             // PEL: PEL pieces and their segments' opacity (anti-aliased)
  CreaseVisibility,      // DM: crease samples' visibility along strokes (anti-aliased)
  SurfaceAway,           // AFT: the surface program that also marks the away tiles
  TileRects,             // SIL and LAY: the rectangles of pixels near marked tiles they draw
  SurfaceCull,           // AFT: the patches that may face away in view, listed for the draw
  HachureField,          // hachures: the fall-line field of the frame (after TFT; not a timed pass)
  SurfaceSplit,          // TFT: the patches in view, split into flat ones (one triangle each) and
                         // tessellated ones
  SurfaceFlat,           // TFT: the flat patches as triangles, without the tessellation stages
  Formulated,            // SIL: formulated silhouettes, near marked tiles, before Toward/Away
  FormulatedFacing,      // SIL: the smoothed facing towards the lowered eye, near marked tiles,
                         // before Formulated
  FormulatedTiles,       // SIL: the tiles' classes for the formulated silhouettes (with
                         // TR_FORMULATED_MARKS: the tiles near which they may lie)
  CompositeCreases,      // LAY over the copied surface: the tiles DM's creases cover, with them
};
inline constexpr std::array kAllPrograms = {
    ProgramId::Surface,          ProgramId::PnCapture,        ProgramId::CreaseScore,
    ProgramId::CreaseBridge,     ProgramId::CreaseSelect,     ProgramId::CreaseDraw,
    ProgramId::Silhouette,       ProgramId::Composite,        ProgramId::CompositeSilhouettes,
    ProgramId::PelFields,        ProgramId::PelExtract,       ProgramId::PelDraw,
    ProgramId::SurfaceId,        ProgramId::Adjacency,        ProgramId::EdgeClassify,
    ProgramId::EdgeDraw,         ProgramId::SilhouettePieces, ProgramId::PelPieces,
    ProgramId::CreaseVisibility, ProgramId::SurfaceAway,      ProgramId::TileRects,
    ProgramId::SurfaceCull,      ProgramId::HachureField,     ProgramId::SurfaceSplit,
    ProgramId::SurfaceFlat,      ProgramId::Formulated,       ProgramId::FormulatedFacing,
    ProgramId::FormulatedTiles,  ProgramId::CompositeCreases};

struct ProgramSpec {
  const char* name;
  std::vector<StageSource> stages;
  std::vector<std::string> feedback;  // transform-feedback varyings
};
const ProgramSpec& program_spec(ProgramId id);

// build_program() of the program's spec, with `defines` ("#define NAME 1\n" lines).
GlObject build_program(ProgramId id, const std::string& defines = "");

}  // namespace renderer
