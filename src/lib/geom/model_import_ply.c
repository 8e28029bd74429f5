// PLY files: read by our own strict reader (ply_reader.c); a header whose
// layout it does not know (no face element, another name for the index
// list) goes to assimp instead, with a note saying so, once its body has
// been walked whole. Damaged data (a file that ends early, a bad list
// count, an index past the vertices) keeps our reader's one-line error.
#include <stdio.h>
#include <string.h>

#include "bk_geom.h"
#include "model_import.h"

bool bk_import_ply(const void* data, size_t size, const char* name, const bk_import_def* def, bk_mesh* out,
                   bk_import_info* info, bk_error* err) {
  char free_text[sizeof info->note] = "";
  bool has_free_text = bk_ply_free_text_note(data, size, free_text, sizeof free_text);
  bool unknown_header = false;
  bk_error ours = {0};
  if (bk_ply_parse(data, size, name, out, &unknown_header, &ours)) {
    snprintf(info->note, sizeof info->note, "%s", free_text);
    return bk_import_finish_ply(true, name, def, out, info, err);
  }
  // assimp's PLY parser is unsafe on header lines it does not know, and
  // trusts the body's counts and indices: it gets only a header of PLY's
  // own keywords and a body walked whole first.
  if (!unknown_header || has_free_text) return bk_error_set(err, "%s", ours.message);
  if (!bk_ply_check_body(data, size, name, err)) return false;
  bk_import_info_free(info);
  memset(info, 0, sizeof *info);
  snprintf(info->format, sizeof info->format, "assimp:ply");
  info->metres_per_unit = 1.0;
  if (!bk_import_assimp_memory(data, size, "ply", name, def, out, info, err)) {
    // Both refused it: ours says what it did not know.
    return bk_error_set(err, "%s", ours.message);
  }
  // The reason without the file's name, which the note's reader prints.
  const char* reason = ours.message;
  size_t prefix = strlen(name);
  if (strncmp(reason, name, prefix) == 0 && strncmp(reason + prefix, ": ", 2) == 0) reason += prefix + 2;
  snprintf(info->note, sizeof info->note, "our PLY reader does not know this header (%.120s); read by assimp",
           reason);
  return true;
}
