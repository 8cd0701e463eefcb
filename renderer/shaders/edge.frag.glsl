// EDGE: object-space edges cover their quads (pixel-exact; the colour is applied in LAY).
layout(location = 0) out vec4 o_colour;
void main() { o_colour = vec4(1.0); }
