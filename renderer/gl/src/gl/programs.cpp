#include "renderer/gl/programs.hpp"

namespace renderer {

const ProgramSpec& program_spec(ProgramId id) {
  static const std::vector<ProgramSpec> specs = [] {
    const std::string c = "common.glsl";
    const std::vector<StageSource> surface_geometry = {
        {GL_VERTEX_SHADER, {c, "surface.vert.glsl"}},
        {GL_TESS_CONTROL_SHADER, {c, "pn_control.glsl", "surface.tesc.glsl"}},
        {GL_TESS_EVALUATION_SHADER, {c, "surface.tese.glsl"}}};
    auto with = [](std::vector<StageSource> stages, StageSource more) {
      stages.push_back(std::move(more));
      return stages;
    };
    auto fullscreen = [&](std::vector<std::string> fragment) {
      fragment.insert(fragment.begin(), c);
      return std::vector<StageSource>{{GL_VERTEX_SHADER, {c, "fullscreen.vert.glsl"}},
                                      {GL_FRAGMENT_SHADER, std::move(fragment)}};
    };
    auto compute = [&](std::vector<std::string> files) {
      files.insert(files.begin(), c);
      return std::vector<StageSource>{{GL_COMPUTE_SHADER, std::move(files)}};
    };
    // In ProgramId order.
    return std::vector<ProgramSpec>{
        {"surface", with(surface_geometry, {GL_FRAGMENT_SHADER, {c, "surface.frag.glsl"}}), {}},
        {"pn_capture", surface_geometry, {"tf_face", "tf_bary", "tf_pos", "tf_nrm"}},
        {"crease_score", compute({"crease_data.glsl", "crease_score.comp.glsl"}), {}},
        {"crease_bridge", compute({"crease_data.glsl", "crease_bridge.comp.glsl"}), {}},
        {"crease_select", compute({"crease_data.glsl", "crease_select.comp.glsl"}), {}},
        {"crease_draw",
         {{GL_VERTEX_SHADER, {c, "crease_data.glsl", "crease.vert.glsl"}},
          {GL_FRAGMENT_SHADER, {c, "crease_samples.glsl", "line.frag.glsl"}}},
         {}},
        {"silhouette",
         {{GL_VERTEX_SHADER, {c, "tile_rects_list.glsl", "tile_rects.vert.glsl"}},
          {GL_FRAGMENT_SHADER,
           {c, "silhouette_list.glsl", "formulated.glsl", "silhouette.frag.glsl"}}},
         {}},
        {"composite", fullscreen({"composite.frag.glsl"}), {}},
        {"composite_silhouettes",
         {{GL_VERTEX_SHADER, {c, "tile_rects_list.glsl", "tile_rects.vert.glsl"}},
          {GL_FRAGMENT_SHADER, {c, "composite_silhouettes.glsl", "composite.frag.glsl"}}},
         {}},
        {"pel_fields", compute({"pel_common.glsl", "pel_fields.comp.glsl"}), {}},
        {"pel_extract", compute({"pel_common.glsl", "pel_extract.comp.glsl"}), {}},
        {"pel_draw",
         {{GL_VERTEX_SHADER, {c, "pel.vert.glsl"}}, {GL_FRAGMENT_SHADER, {c, "line.frag.glsl"}}},
         {}},
        {"surface_id",
         with(with(surface_geometry, {GL_GEOMETRY_SHADER, {c, "surface_id.geom.glsl"}}),
              {GL_FRAGMENT_SHADER, {c, "surface_id.frag.glsl"}}),
         {}},
        {"adjacency", fullscreen({"silhouette_list.glsl", "adjacency.frag.glsl"}), {}},
        {"edge_classify", compute({"edge_common.glsl", "edge_classify.comp.glsl"}), {}},
        {"edge_draw",
         {{GL_VERTEX_SHADER, {c, "edge_common.glsl", "edge.vert.glsl"}},
          {GL_FRAGMENT_SHADER, {c, "edge.frag.glsl"}}},
         {}},
        {"silhouette_pieces",
         compute({"silhouette_list.glsl", "union_find.glsl", "silhouette_pieces.comp.glsl"}),
         {}},
        {"pel_pieces", compute({"pel_common.glsl", "union_find.glsl", "pel_pieces.comp.glsl"}), {}},
        {"crease_visibility",
         compute({"crease_data.glsl", "crease_samples.glsl", "crease_visibility.comp.glsl"}),
         {}},
        {"away_tiles", compute({"away_tiles.comp.glsl"}), {}},
        {"tile_rects", compute({"tile_rects_list.glsl", "tile_rects.comp.glsl"}), {}},
        {"surface_cull",
         compute({"pn_control.glsl", "patch_list.glsl", "surface_cull.comp.glsl"}),
         {}},
        {"hachure_field", compute({"hachure_field.comp.glsl"}), {}},
        {"surface_split", compute({"patch_list.glsl", "surface_split.comp.glsl"}), {}},
        {"surface_flat",
         {{GL_VERTEX_SHADER, {c, "surface_flat.vert.glsl"}},
          {GL_FRAGMENT_SHADER, {c, "surface.frag.glsl"}}},
         {}},
        {"formulated",
         fullscreen({"silhouette_list.glsl", "formulated.glsl", "formulated.frag.glsl"}),
         {}},
        {"formulated_facing", fullscreen({"formulated_facing.frag.glsl"}), {}},
    };
  }();
  return specs.at(std::size_t(id));
}

GlObject build_program(ProgramId id, const std::string& defines) {
  const ProgramSpec& spec = program_spec(id);
  return build_program(spec.stages, spec.feedback, defines);
}

}  // namespace renderer
