// Fixed shapes: the ground quad and the projectile sphere in its levels of detail.
#include <math.h>
#include <string.h>

#include "render_internal.h"

void render_make_ground(app_renderer* r) {
  // A large quad; uvs in metres so the paving keeps its size.
  const float s = ground_half_size;
  vertex quad[4] = {{{-s, 0, -s}, {0, 1, 0}, {-s, -s}, {1, 0, 0, 1}, 0},
                    {{-s, 0, s}, {0, 1, 0}, {-s, s}, {1, 0, 0, 1}, 0},
                    {{s, 0, s}, {0, 1, 0}, {s, s}, {1, 0, 0, 1}, 0},
                    {{s, 0, -s}, {0, 1, 0}, {s, -s}, {1, 0, 0, 1}, 0}};
  vertex tris[6] = {quad[0], quad[1], quad[2], quad[0], quad[2], quad[3]};
  glGenVertexArrays(1, &r->ground_vao);
  glGenBuffers(1, &r->ground_vbo);
  glBindVertexArray(r->ground_vao);
  glBindBuffer(GL_ARRAY_BUFFER, r->ground_vbo);
  glBufferData(GL_ARRAY_BUFFER, sizeof tris, tris, GL_STATIC_DRAW);
}

// Projectiles in three levels of detail, chosen by their size on screen: a
// volley leaves dozens on the ground, and at full detail they were ~40k
// triangles a frame counting the shadow pass.
enum { SPHERE_RINGS = 12, SPHERE_SEGMENTS = 20 }; // the finest level
static const int sphere_rings[SPHERE_LEVELS] = {SPHERE_RINGS, 8, 5};
static const int sphere_segments[SPHERE_LEVELS] = {SPHERE_SEGMENTS, 12, 8};

void render_make_sphere(app_renderer* r) {
  // Room for every level at the finest one's size.
  enum {
    MAX_VERTICES = SPHERE_LEVELS * (SPHERE_RINGS + 1) * (SPHERE_SEGMENTS + 1),
    MAX_INDICES = SPHERE_LEVELS * 6 * SPHERE_RINGS * SPHERE_SEGMENTS
  };
  vertex vertices[MAX_VERTICES];
  uint32_t indices[MAX_INDICES];
  uint32_t v = 0, i = 0;
  for (int level = 0; level < SPHERE_LEVELS; ++level) {
    int rings = sphere_rings[level], segments = sphere_segments[level];
    uint32_t base = v;
    r->sphere_first[level] = i;
    for (int ring = 0; ring <= rings; ++ring)
      for (int seg = 0; seg <= segments; ++seg) {
        float theta = (float)ring / (float)rings * 3.14159265f,
              phi = (float)seg / (float)segments * 6.2831853f;
        float n[3] = {sinf(theta) * cosf(phi), cosf(theta), sinf(theta) * sinf(phi)};
        vertices[v++] = (vertex){{n[0], n[1], n[2]},
                                 {n[0], n[1], n[2]},
                                 {(float)seg / (float)segments * 2, (float)ring / (float)rings},
                                 {-sinf(phi), 0, cosf(phi), 1},
                                 0};
      }
    for (int ring = 0; ring < rings; ++ring)
      for (int seg = 0; seg < segments; ++seg) {
        uint32_t a = base + (uint32_t)(ring * (segments + 1) + seg), b = a + (uint32_t)segments + 1;
        uint32_t quad[6] = {a, a + 1, b, a + 1, b + 1, b};
        memcpy(&indices[i], quad, sizeof quad);
        i += 6;
      }
    r->sphere_index_count[level] = i - r->sphere_first[level];
  }
  glGenVertexArrays(1, &r->sphere_vao);
  glGenBuffers(1, &r->sphere_vbo);
  glGenBuffers(1, &r->sphere_ibo);
  glBindVertexArray(r->sphere_vao);
  glBindBuffer(GL_ARRAY_BUFFER, r->sphere_vbo);
  glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(sizeof(vertex) * v), vertices, GL_STATIC_DRAW);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->sphere_ibo);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(sizeof(uint32_t) * i), indices, GL_STATIC_DRAW);
  render_vertex_layout();
}
