// The unit of length a model file states (FBX, glTF, Collada), read from
// the scene assimp made of it: the import scales the mesh to metres.
#include <assimp/scene.h>
#include <math.h>
#include <string.h>

#include "model_import.h"

// A number in the scene's metadata (0 when absent or not a number).
static double metadata_number(const struct aiScene* scene, const char* key) {
  const struct aiMetadata* m = scene->mMetaData;
  for (uint32_t i = 0; m && m->mKeys && m->mValues && i < m->mNumProperties; ++i) {
    const struct aiMetadataEntry* v = &m->mValues[i];
    if (strcmp(m->mKeys[i].data, key) != 0 || !v->mData) continue;
    if (v->mType == AI_FLOAT) return *(const float*)v->mData;
    if (v->mType == AI_DOUBLE) return *(const double*)v->mData;
    if (v->mType == AI_INT32) return *(const int32_t*)v->mData;
  }
  return 0.0;
}

// The file's unit of length, where its format states one: an FBX file's
// UnitScaleFactor is centimetres per unit (assimp keeps the file's numbers);
// glTF is in metres and assimp applies a Collada file's <unit> itself.
void bk_import_read_units(const struct aiScene* scene, const char* ext, bk_import_info* info) {
  info->metres_per_unit = 1.0;
  if (strcmp(ext, "fbx") == 0) {
    double centimetres = metadata_number(scene, "UnitScaleFactor");
    info->units_given = true;
    if (isfinite(centimetres) && centimetres > 1e-6 && centimetres < 1e9)
      info->metres_per_unit = 0.01 * centimetres;
  } else {
    info->units_given = strcmp(ext, "gltf") == 0 || strcmp(ext, "glb") == 0 || strcmp(ext, "dae") == 0;
  }
}
