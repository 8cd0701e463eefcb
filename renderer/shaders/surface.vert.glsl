// Mesh vertices into the tessellation stages (exaggerated).
layout(location = TR_ATTR_POSITION) in vec3 a_position;
layout(location = TR_ATTR_NORMAL) in vec3 a_normal;
out vec3 v_pos;
out vec3 v_nrm;
void main() {
  v_pos = exaggerate_position(a_position);
  v_nrm = exaggerate_normal(a_normal);
}
