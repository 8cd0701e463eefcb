// The rectangles of pixels that SIL and LAY draw (tile_rects.comp.glsl writes them, the
// draws' vertex shader reads them; tile_rects.vert.glsl): the header is the indirect draw
// command, 6 vertices per rectangle; each rectangle is (x0, y0, x1, y1), pixel edges.
layout(std430, binding = TR_SSBO_TILE_RECTS) buffer TileRects {
  uint rect_vertices, rect_instances, rect_first, rect_base;
  ivec4 rect[];
};
