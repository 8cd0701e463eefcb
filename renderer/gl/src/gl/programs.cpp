#include "renderer/gl/programs.hpp"

namespace renderer {

namespace {

// The stage lists the programs are made of: every stage begins with common.glsl.
struct Stages {
  const std::string c = "common.glsl";
  const std::vector<StageSource> surface_geometry = {
      {GL_VERTEX_SHADER, {c, "surface.vert.glsl"}},
      {GL_TESS_CONTROL_SHADER, {c, "pn_control.glsl", "surface.tesc.glsl"}},
      {GL_TESS_EVALUATION_SHADER, {c, "surface.tese.glsl"}}};
  static std::vector<StageSource> with(std::vector<StageSource> stages, StageSource more) {
    stages.push_back(std::move(more));
    return stages;
  }
  std::vector<StageSource> fullscreen(std::vector<std::string> fragment) const {
    fragment.insert(fragment.begin(), c);
    return {{GL_VERTEX_SHADER, {c, "fullscreen.vert.glsl"}},
            {GL_FRAGMENT_SHADER, std::move(fragment)}};
  }
  std::vector<StageSource> compute(std::vector<std::string> files) const {
    files.insert(files.begin(), c);
    return {{GL_COMPUTE_SHADER, std::move(files)}};
  }
};

// ProgramId's first programs, surface .. pel_draw, in its order.
std::vector<ProgramSpec> surface_and_line_programs(const Stages& s) {
  return {
      {"surface", s.with(s.surface_geometry, {GL_FRAGMENT_SHADER, {s.c, "surface.frag.glsl"}}), {}},
      {"pn_capture", s.surface_geometry, {"tf_face", "tf_bary", "tf_pos", "tf_nrm"}},
      {"crease_score", s.compute({"crease_data.glsl", "crease_score.comp.glsl"}), {}},
      {"crease_bridge", s.compute({"crease_data.glsl", "crease_bridge.comp.glsl"}), {}},
      {"crease_select", s.compute({"crease_data.glsl", "crease_select.comp.glsl"}), {}},
      {"crease_draw",
       {{GL_VERTEX_SHADER, {s.c, "crease_data.glsl", "crease.vert.glsl"}},
        {GL_FRAGMENT_SHADER, {s.c, "crease_samples.glsl", "line.frag.glsl"}}},
       {}},
      {"silhouette",
       {{GL_VERTEX_SHADER, {s.c, "tile_rects_list.glsl", "tile_rects.vert.glsl"}},
        {GL_FRAGMENT_SHADER,
         {s.c, "silhouette_list.glsl", "formulated.glsl", "silhouette.frag.glsl"}}},
       {}},
      {"composite", s.fullscreen({"composite.frag.glsl"}), {}},
      {"composite_silhouettes",
       {{GL_VERTEX_SHADER, {s.c, "tile_rects_list.glsl", "tile_rects.vert.glsl"}},
        {GL_FRAGMENT_SHADER, {s.c, "composite_silhouettes.glsl", "composite.frag.glsl"}}},
       {}},
      {"pel_fields", s.compute({"pel_common.glsl", "pel_fields.comp.glsl"}), {}},
      {"pel_extract", s.compute({"pel_common.glsl", "pel_extract.comp.glsl"}), {}},
      {"pel_draw",
       {{GL_VERTEX_SHADER, {s.c, "pel.vert.glsl"}}, {GL_FRAGMENT_SHADER, {s.c, "line.frag.glsl"}}},
       {}},
  };
}

// ProgramId's other programs, surface_id .. composite_creases, in its order.
std::vector<ProgramSpec> other_programs(const Stages& s) {
  return {
      {"surface_id",
       s.with(s.with(s.surface_geometry, {GL_GEOMETRY_SHADER, {s.c, "surface_id.geom.glsl"}}),
              {GL_FRAGMENT_SHADER, {s.c, "surface_id.frag.glsl"}}),
       {}},
      {"adjacency", s.fullscreen({"silhouette_list.glsl", "adjacency.frag.glsl"}), {}},
      {"edge_classify", s.compute({"edge_common.glsl", "edge_classify.comp.glsl"}), {}},
      {"edge_draw",
       {{GL_VERTEX_SHADER, {s.c, "edge_common.glsl", "edge.vert.glsl"}},
        {GL_FRAGMENT_SHADER, {s.c, "edge.frag.glsl"}}},
       {}},
      {"silhouette_pieces",
       s.compute({"silhouette_list.glsl", "union_find.glsl", "silhouette_pieces.comp.glsl"}),
       {}},
      {"pel_pieces", s.compute({"pel_common.glsl", "union_find.glsl", "pel_pieces.comp.glsl"}), {}},
      {"crease_visibility",
       s.compute({"crease_data.glsl", "crease_samples.glsl", "crease_visibility.comp.glsl"}),
       {}},
      {"surface_away",
       s.with(s.surface_geometry,
              {GL_FRAGMENT_SHADER, {s.c, "surface_away.glsl", "surface.frag.glsl"}}),
       {}},
      {"tile_rects", s.compute({"tile_rects_list.glsl", "tile_rects.comp.glsl"}), {}},
      {"surface_cull",
       s.compute({"pn_control.glsl", "patch_list.glsl", "surface_cull.comp.glsl"}),
       {}},
      {"hachure_field", s.compute({"hachure_field.comp.glsl"}), {}},
      {"surface_split", s.compute({"patch_list.glsl", "surface_split.comp.glsl"}), {}},
      {"surface_flat",
       {{GL_VERTEX_SHADER, {s.c, "surface_flat.vert.glsl"}},
        {GL_FRAGMENT_SHADER, {s.c, "surface.frag.glsl"}}},
       {}},
      {"formulated",
       {{GL_VERTEX_SHADER, {s.c, "tile_rects_list.glsl", "tile_rects.vert.glsl"}},
        {GL_FRAGMENT_SHADER,
         {s.c, "silhouette_list.glsl", "formulated.glsl", "formulated.frag.glsl"}}},
       {}},
      {"formulated_facing",
       {{GL_VERTEX_SHADER, {s.c, "tile_rects_list.glsl", "tile_rects.vert.glsl"}},
        {GL_FRAGMENT_SHADER, {s.c, "formulated_facing.frag.glsl"}}},
       {}},
      {"formulated_tiles", s.compute({"formulated_tiles.comp.glsl"}), {}},
      {"composite_creases",
       {{GL_VERTEX_SHADER, {s.c, "tile_rects_list.glsl", "tile_rects.vert.glsl"}},
        {GL_FRAGMENT_SHADER, {s.c, "composite.frag.glsl"}}},
       {}},
  };
}

}  // namespace

const ProgramSpec& program_spec(ProgramId id) {
  static const std::vector<ProgramSpec> specs = [] {
    const Stages s;
    std::vector<ProgramSpec> all = surface_and_line_programs(s);
    for (ProgramSpec& p : other_programs(s)) all.push_back(std::move(p));
    return all;
  }();
  return specs.at(std::size_t(id));
}

GlObject build_program(ProgramId id, const std::string& defines) {
  const ProgramSpec& spec = program_spec(id);
  return build_program(spec.stages, spec.feedback, defines);
}

}  // namespace renderer
