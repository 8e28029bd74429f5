// Wavefront OBJ writer: one `o fragment_<i>` object per mesh, positions with
// exact round-trip precision, per-corner vt/vn.
#include <inttypes.h>
#include <stdio.h>

#include "bk_geom.h"

static void write_mesh(FILE* f, const bk_mesh* m, uint32_t index, uint64_t position_base,
                       uint64_t corner_base) {
  fprintf(f, "o fragment_%u\n", index);
  // %.17g round-trips doubles exactly, so a reload welds and measures identically.
  for (uint32_t i = 0; i < m->position_count; ++i)
    fprintf(f, "v %.17g %.17g %.17g\n", m->positions[i].x, m->positions[i].y, m->positions[i].z);
  // %.9g round-trips floats exactly.
  for (uint32_t i = 0; i < m->corner_count; ++i)
    fprintf(f, "vt %.9g %.9g\n", (double)m->corners[i].uv[0], (double)m->corners[i].uv[1]);
  for (uint32_t i = 0; i < m->corner_count; ++i) {
    const float* n = m->corners[i].normal;
    fprintf(f, "vn %.9g %.9g %.9g\n", (double)n[0], (double)n[1], (double)n[2]);
  }
  for (uint32_t t = 0; t < m->triangle_count; ++t) {
    fputc('f', f);
    for (int k = 0; k < 3; ++k) {
      uint32_t c = m->indices[3 * t + k];
      uint64_t corner = corner_base + c + 1;
      fprintf(f, " %" PRIu64 "/%" PRIu64 "/%" PRIu64, position_base + m->corners[c].position + 1, corner,
              corner);
    }
    fputc('\n', f);
  }
}

bool bk_obj_save(const char* path, const bk_mesh* meshes, uint32_t mesh_count, bk_error* err) {
  if (mesh_count > 0 && !meshes) return bk_error_set(err, "%s: no meshes given", path);
  // Refuse to write what the reader would reject (bad indices, non-finite values).
  for (uint32_t i = 0; i < mesh_count; ++i) {
    bk_error why = {{0}};
    if (meshes[i].triangle_count > 0 && !bk_mesh_validate(&meshes[i], &why))
      return bk_error_set(err, "%s: mesh %u: %s", path, i, why.message);
  }

  // Write beside the target and rename over it, so an existing file is never half-overwritten.
  static const bk_atomic_messages messages = {"cannot open for writing", "write failed",
                                              "cannot replace file"};
  bk_atomic_file file = {0};
  if (!bk_file_begin_atomic(path, &messages, &file, err)) return false;
  FILE* f = file.stream;

  uint64_t positions = 0, corners = 0, triangles = 0;
  for (uint32_t i = 0; i < mesh_count; ++i) {
    positions += meshes[i].position_count;
    triangles += meshes[i].triangle_count;
  }
  fprintf(f, "# breakables export: objects %u, vertices %" PRIu64 ", triangles %" PRIu64 "\n", mesh_count,
          positions, triangles);
  positions = 0;
  bk_c_locale c_locale = bk_c_locale_begin(); // "0.5", never "0,5"
  for (uint32_t i = 0; i < mesh_count; ++i) {
    write_mesh(f, &meshes[i], i, positions, corners);
    positions += meshes[i].position_count;
    corners += meshes[i].corner_count;
  }
  bk_c_locale_end(&c_locale);
  // fprintf failures are sticky in the stream; commit checks them.
  return bk_file_commit_atomic(&file, path, &messages, err);
}
