#version 330 core
// Depth only; vertices are placed through the node table as in mesh.vert.
layout(location = 0) in vec3 in_position;
layout(location = 5) in uint in_node;
uniform samplerBuffer u_nodes;
uniform mat4 u_light_view_projection;
#if DITHERED
flat out float v_skip; // share of the node's shadow left out: as it fades, and as glass
#endif
void main() {
  int row = int(in_node) * 5;
  mat4 model = transpose(mat4(texelFetch(u_nodes, row), texelFetch(u_nodes, row + 1),
                              texelFetch(u_nodes, row + 2), vec4(0.0, 0.0, 0.0, 1.0)));
  gl_Position = u_light_view_projection * model * vec4(in_position, 1.0);
#if DITHERED
  v_skip = texelFetch(u_nodes, row + 4).y;
#endif
}
