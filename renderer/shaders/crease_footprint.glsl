// Selects the footprint variant of crease.vert.glsl: DM's quads widened by a pixel each
// side, so that they hold every pixel DM's own quads covered (LAY's composite_creases).
#define TR_CREASE_FOOTPRINT 1
