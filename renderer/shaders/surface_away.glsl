// Selects AFT's variant of surface.frag.glsl: each away-facing fragment marks its
// TR_SILHOUETTE_TILE tile in the away tiles (SceneGpu::away_tiles), where SIL's Toward/Away
// test then runs.
#define TR_SURFACE_AWAY_TILES 1
