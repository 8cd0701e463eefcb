// Adjacency silhouettes, first pass: the nearest tessellated triangle's ID per pixel.
flat in uint g_id;
layout(location = 0) out uint o_id;
void main() { o_id = g_id; }
