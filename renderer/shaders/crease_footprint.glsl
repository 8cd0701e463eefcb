// Selects the footprint variant of crease.vert.glsl: DM's quads widened by a pixel each
// side, so that they hold every pixel DM's own quads covered, and none for a segment that
// shows no sample (LAY's composite_creases; crease_samples.glsl follows).
#define TR_CREASE_FOOTPRINT 1
