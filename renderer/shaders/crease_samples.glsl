// Crease samples for hidden-line removal along strokes (renderer/core/stroke_visibility.hpp):
// each segment sampled at n points (k + 0.5) / n along it on screen, bit k of each mask
// sample k. Written by crease_visibility.comp.glsl, read by line.frag.glsl for creases.
#define TR_CREASE_SAMPLES 1
struct SegmentSamples {
  uint visible;     // line.frag's 3 x 3 test
  uint bridgeable;  // hidden, on screen, at most u_strokes.y metres behind the farthest surface
  uint closed;      // visible, or in a hidden run that is drawn
  uint shown;       // closed, less the peeks: what is drawn
  uint n;           // samples; 0: not drawn, or an end behind the near plane
  float step;       // screen length of a sample (pixels)
};
layout(std430, binding = TR_SSBO_CREASE_SAMPLES) buffer CreaseSamples { SegmentSamples samples[]; };
