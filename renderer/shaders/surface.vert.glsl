// Mesh vertices into the tessellation stages (exaggerated).
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
out vec3 v_pos;
out vec3 v_nrm;
void main() {
  v_pos = exaggerate_position(a_position);
  v_nrm = exaggerate_normal(a_normal);
}
