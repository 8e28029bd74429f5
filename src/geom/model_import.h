// geom (private): what the model import files share: the import's state,
// the header checks made before assimp reads a file, the material report
// and the finishing of the mesh.
#pragma once

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <breakables/authoring.h>

struct aiScene;

/// One import in progress.
typedef struct import_state {
  const char* name;     // prefixes errors
  const char* base_dir; // resolves texture paths ("" for memory)
  const bk_import_def* def;
  const struct aiScene* scene;
  bk_import_info* info;
  bk_error* err;
  bk_mesh mesh;
  bool* corner_has_normal; // per corner: the file gave a normal
  bool* corner_has_uv;
  uint32_t corner_flag_capacity;
  uint32_t* material_triangles; // per scene material: triangles placed
} import_state;

/// How many leading bytes of a file bk_import_precheck looks at.
#define BK_IMPORT_PRECHECK_BYTES 65536

/// Refuses a file whose header declares more elements than its `file_size`
/// bytes can hold (PLY, OFF: their readers allocate by those counts). `head`
/// is the file's first bytes (up to BK_IMPORT_PRECHECK_BYTES), `ext` its
/// lower-case extension, `name` prefixes the message.
bool bk_import_precheck(const char* name, const char* ext, const void* head, size_t size, uint64_t file_size,
                        bk_error* err);

/// How many leading bytes of a file bk_import_precheck_content needs, after
/// bk_import_precheck accepted its `head`: the whole text of a .gltf and of a
/// .3ds, a .glb up to its BIN chunk's header; 0 for the other formats.
uint64_t bk_import_precheck_content_bytes(const char* ext, const void* head, size_t size, uint64_t file_size);
/// Checks what assimp's readers trust beyond the header: a glTF document's
/// JSON (bk_import_precheck_gltf), a 3DS file's chunk tree and the counts in
/// it. `data` is the file's first `size` bytes (at least
/// bk_import_precheck_content_bytes of them).
bool bk_import_precheck_content(const char* name, const char* ext, const void* data, size_t size,
                                uint64_t file_size, bk_error* err);
/// Refuses a glTF 2.0 document (`ext` "gltf": the text; "glb": the file up to
/// its BIN chunk's header) that leaves out what the specification requires
/// or points outside its arrays or buffers; the message names the field.
/// Reads a PLY file (ply_reader.c: ours, not assimp's).
bool bk_ply_parse(const void* data, size_t size, const char* name, bk_mesh* out, bk_error* err);
bool bk_import_precheck_gltf(const char* name, const char* ext, const void* data, size_t size,
                             uint64_t file_size, bk_error* err);

/// Copies text, cut to fit `size` and with control characters made blanks.
void bk_import_copy_text(char* dst, size_t size, const char* src, size_t length);
/// Fills info's material fields from the material of the most triangles placed.
void bk_import_read_material(import_state* s);
/// Welds, drops degenerate triangles and unused data, turns an inside-out
/// mesh, fills in normals, UVs and tangents; false (s->err set) if nothing is left.
bool bk_import_finish_mesh(import_state* s);
