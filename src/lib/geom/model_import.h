// geom (private): what the model import files share: the import's state,
// the header checks made before assimp reads a file, the material report
// and the finishing of the mesh.
#pragma once

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <breakables/authoring.h>

#include "bk_geom.h"

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
  // Per scene material (+ 1 for meshes naming none): its source material
  // id in the mesh (bk_material_source), UINT32_MAX until a mesh uses it.
  uint32_t* source_of_material;
  uint32_t scene_material_of_source[BK_MATERIAL_SOURCES_MAX];
  uint32_t source_count;
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
/// Reads a PLY file (ply_reader.c: ours, not assimp's). *unknown_header is
/// set when it is refused for a layout this reader does not know (no
/// vertex or face element, no vertex_indices list, too many elements or
/// properties), not for damage.
bool bk_ply_parse(const void* data, size_t size, const char* name, bk_mesh* out, bool* unknown_header,
                  bk_error* err);
/// Walks a PLY file's whole body as its header declares it, whatever its
/// elements (every value present and a number, list counts small, every
/// list of vertex indices naming a vertex or -1): what assimp's PLY reader
/// trusts. False with the first problem named.
bool bk_ply_check_body(const void* data, size_t size, const char* name, bk_error* err);
/// The first PLY header line that is free text rather than a keyword (old
/// Blender exports wrote one without "comment"), as a note for
/// bk_import_info.note; false when there is none.
bool bk_ply_free_text_note(const void* data, size_t size, char* note, size_t note_size);
/// A PLY file: our reader, else (a header layout it does not know, and no
/// free text in the header, on which assimp's parser is unsafe) assimp's,
/// saying so in info->note. Finished with bk_import_finish_ply.
bool bk_import_ply(const void* data, size_t size, const char* name, const bk_import_def* def, bk_mesh* out,
                   bk_import_info* info, bk_error* err);
/// Sets info's units_given and metres_per_unit from what `scene` (of a file
/// of extension `ext`) states: FBX's UnitScaleFactor (centimetres per
/// unit); glTF is in metres and assimp applies Collada's <unit> itself.
void bk_import_read_units(const struct aiScene* scene, const char* ext, bk_import_info* info);
/// Reads a model file of format `ext` through assimp (locked, in the C
/// locale), texture paths resolved beside it. A build without assimp
/// (BK_NO_ASSIMP, the WebAssembly one) refuses both in one line.
bool bk_import_assimp_file(const char* path, const char* ext, const bk_import_def* def, bk_mesh* out,
                           bk_import_info* info, bk_error* err);
/// Reads bytes of format `ext` through assimp (locked, in the C locale) into
/// a finished mesh.
bool bk_import_assimp_memory(const void* data, size_t size, const char* ext, const char* name,
                             const bk_import_def* def, bk_mesh* out, bk_import_info* info, bk_error* err);
bool bk_import_precheck_gltf(const char* name, const char* ext, const void* data, size_t size,
                             uint64_t file_size, bk_error* err);

/// Copies text, cut to fit `size` and with control characters made blanks.
void bk_import_copy_text(char* dst, size_t size, const char* src, size_t length);
/// The source material id of scene material `index` (ids are given in the
/// order meshes use them; past BK_MATERIAL_SOURCES_MAX, 0 and counted as merged).
uint32_t bk_import_material_source(import_state* s, uint32_t index);
/// Fills info's material list (names, colours, textures, embedded images,
/// triangle counts) from the scene materials the finished mesh uses.
void bk_import_read_materials(import_state* s);
/// Keeps info's material list for the caller when the import succeeded and
/// `keep` (the caller asked for the info); else frees it. Returns ok.
bool bk_import_settle_info(bool ok, bk_import_info* info, bool keep);
/// Finishes a mesh our PLY reader made (ok: it did): the triangle limit,
/// the counts, a mesh inside out as a whole turned, the material list.
bool bk_import_finish_ply(bool ok, const char* name, const bk_import_def* def, bk_mesh* out,
                          bk_import_info* info, bk_error* err);
struct aiFileIO;
/// The file system assimp is to read through (model_import_io.c): regular
/// files only, never writing. Resets what bk_import_file_io_refused reports;
/// call with the import lock held.
struct aiFileIO* bk_import_file_io(void);
/// After a failed import: true, with "<path>: is not a regular file (read by
/// <name>)" in err, when assimp was refused a file for what it is.
bool bk_import_file_io_refused(const char* name, bk_error* err);
/// Gives info the material list of an OBJ file: its `usemtl` names, with the
/// colours and textures of its `mtllib` file when `obj_path` is given and the
/// file is beside it (texture paths resolved against the OBJ's directory).
/// A library that is missing or unreadable leaves the materials white; false
/// (with the reason) only when it is there but is not a regular file (a FIFO
/// would block the read forever).
bool bk_import_obj_materials(bk_import_info* info, const bk_mesh* mesh, const bk_obj_materials* materials,
                             const char* obj_path, bk_error* err);
/// Counts each listed material's triangles in the mesh and finds the one of the most.
void bk_import_count_triangles(bk_import_info* info, const bk_mesh* mesh);
/// Gives info a one-entry material list for a one-material mesh (our OBJ
/// and PLY readers): unnamed, white, no texture.
void bk_import_single_material(bk_import_info* info, const bk_mesh* mesh);
/// Welds, drops degenerate triangles and unused data, turns an inside-out
/// mesh, fills in normals, UVs and tangents; false (s->err set) if nothing is left.
bool bk_import_finish_mesh(import_state* s);
