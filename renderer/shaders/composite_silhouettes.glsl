// Selects the silhouette half of composite.frag.glsl (LAY): see its comment.
#define TR_COMPOSITE_SILHOUETTES 1
