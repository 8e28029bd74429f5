// The formats read through assimp's C API (glTF 2.0, FBX, Collada, STL, ...):
// a scene's meshes placed by their node transforms, read into one welded
// bk_mesh, with the base-colour material reported in bk_import_info (OBJ and
// PLY files never come here: model_import.c). Everything assimp hands
// back is checked again here (indices, finite and bounded coordinates,
// counts), so a corrupt file ends in a one-line error, never a bad mesh.
#include <assimp/cimport.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "bk_geom.h"
#include "model_import.h"

// Coordinates beyond this are refused, as the OBJ reader does.
#define IMPORT_MAX_COORD 1e30
// Scenes with more nodes are refused (the walks keep their own stacks).
#define IMPORT_MAX_NODES (1u << 20)
// Node names an unknown-node error lists.
#define IMPORT_LISTED_NODES 6

// assimp keeps its last error in one global string: imports take turns.
static pthread_mutex_t import_lock = PTHREAD_MUTEX_INITIALIZER;

// ---------------------------------------------------------------- scene walk

typedef struct mat4d {
  double m[4][4];
} mat4d;

static mat4d mat4d_of(const struct aiMatrix4x4* a) {
  const float* f = &a->a1; // row-major, translation in the last column
  mat4d r;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      r.m[i][j] = f[4 * i + j];
  return r;
}

static mat4d mat4d_mul(const mat4d* a, const mat4d* b) {
  mat4d r;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      r.m[i][j] = a->m[i][0] * b->m[0][j] + a->m[i][1] * b->m[1][j] + a->m[i][2] * b->m[2][j] +
                  a->m[i][3] * b->m[3][j];
  return r;
}

static bool mat4d_finite(const mat4d* a) {
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      if (!isfinite(a->m[i][j])) return false;
  return true;
}

// Cofactor matrix of the upper 3x3 (the inverse transpose times the
// determinant): transforms normals, and its sign does not matter once normalised.
static void normal_matrix(const mat4d* a, double n[3][3], double* det) {
  const double(*m)[4] = a->m;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
      n[i][j] = m[i1][j1] * m[i2][j2] - m[i1][j2] * m[i2][j1];
    }
  *det = m[0][0] * n[0][0] + m[0][1] * n[0][1] + m[0][2] * n[0][2];
}

static const char* mesh_label(const struct aiMesh* mesh, char* buffer, size_t size, uint32_t index) {
  if (mesh->mName.length > 0 && mesh->mName.length < 64)
    snprintf(buffer, size, "mesh %u ('%.63s')", index, mesh->mName.data);
  else
    snprintf(buffer, size, "mesh %u", index);
  return buffer;
}

static void ensure_corner_flags(import_state* s, uint32_t need) {
  if (need <= s->corner_flag_capacity) return;
  uint32_t capacity = bk_grow_capacity(s->corner_flag_capacity, need);
  s->corner_has_normal = bk_realloc(s->corner_has_normal, capacity);
  s->corner_has_uv = bk_realloc(s->corner_has_uv, capacity);
  s->corner_flag_capacity = capacity;
}

// Places one mesh under a world transform: positions and normals
// transformed, one corner per vertex, triangles checked and appended.
static bool place_mesh(import_state* s, uint32_t index, const mat4d* world) {
  const struct aiMesh* am = s->scene->mMeshes[index];
  char label[96];
  if (!am) return bk_error_set(s->err, "%s: mesh %u is missing", s->name, index);
  if (!(am->mPrimitiveTypes & aiPrimitiveType_TRIANGLE) || am->mNumFaces == 0)
    return true; // points/lines only
  bk_mesh* m = &s->mesh;
  if (am->mNumVertices > s->def->max_vertices - m->position_count)
    return bk_error_set(s->err, "%s: too many vertices (more than %u)", s->name, s->def->max_vertices);
  if (am->mNumFaces > s->def->max_triangles - m->triangle_count)
    return bk_error_set(s->err, "%s: too many triangles (more than %u)", s->name, s->def->max_triangles);
  if (!am->mVertices)
    return bk_error_set(s->err, "%s: %s has no positions", s->name,
                        mesh_label(am, label, sizeof label, index));
  double nm[3][3], det = 0.0;
  normal_matrix(world, nm, &det);
  bool mirrored = det < 0.0;
  uint32_t base = m->position_count;
  uint32_t corner_base = m->corner_count;
  bk_mesh_reserve(m, base + am->mNumVertices, corner_base + am->mNumVertices,
                  m->triangle_count + am->mNumFaces);
  ensure_corner_flags(s, corner_base + am->mNumVertices);
  uint8_t material = bk_material_id(bk_import_material_source(s, am->mMaterialIndex), false);
  const struct aiVector3D* uvs = am->mTextureCoords[0];
  for (uint32_t v = 0; v < am->mNumVertices; ++v) {
    const struct aiVector3D* p = &am->mVertices[v];
    double local[3] = {p->x, p->y, p->z}, world_p[3];
    for (int i = 0; i < 3; ++i)
      world_p[i] =
          world->m[i][0] * local[0] + world->m[i][1] * local[1] + world->m[i][2] * local[2] + world->m[i][3];
    for (int i = 0; i < 3; ++i) {
      if (!isfinite(local[i]) || !isfinite(world_p[i]))
        return bk_error_set(s->err, "%s: %s, vertex %u: non-finite coordinate", s->name,
                            mesh_label(am, label, sizeof label, index), v);
      if (fabs(world_p[i]) > IMPORT_MAX_COORD)
        return bk_error_set(s->err, "%s: %s, vertex %u: coordinate %g out of range (limit 1e30)", s->name,
                            mesh_label(am, label, sizeof label, index), v, world_p[i]);
    }
    bk_mesh_add_position(m, bk_v3(world_p[0], world_p[1], world_p[2]));
    bk_corner c = {.position = base + v};
    bool has_normal = false, has_uv = false;
    if (am->mNormals) {
      const struct aiVector3D* n = &am->mNormals[v];
      bk_vec3 w = bk_v3(nm[0][0] * n->x + nm[0][1] * n->y + nm[0][2] * n->z,
                        nm[1][0] * n->x + nm[1][1] * n->y + nm[1][2] * n->z,
                        nm[2][0] * n->x + nm[2][1] * n->y + nm[2][2] * n->z);
      if (det < 0.0) w = bk_v3_scale(w, -1.0);
      double scale = fmax(fabs(w.x), fmax(fabs(w.y), fabs(w.z)));
      if (isfinite(scale) && scale > 0.0) {
        w = bk_v3_normalize(bk_v3_scale(w, 1.0 / scale));
        c.normal[0] = (float)w.x, c.normal[1] = (float)w.y, c.normal[2] = (float)w.z;
        has_normal = true;
      }
    }
    if (uvs && isfinite(uvs[v].x) && isfinite(uvs[v].y) && fabsf(uvs[v].x) < 1e30f &&
        fabsf(uvs[v].y) < 1e30f) {
      c.uv[0] = uvs[v].x, c.uv[1] = uvs[v].y;
      has_uv = true;
    }
    s->corner_has_normal[m->corner_count] = has_normal;
    s->corner_has_uv[m->corner_count] = has_uv;
    s->info->normals_computed |= !has_normal;
    s->info->uvs_projected |= !has_uv;
    bk_mesh_add_corner(m, &c);
  }
  uint32_t placed = 0;
  for (uint32_t f = 0; f < am->mNumFaces; ++f) {
    const struct aiFace* face = &am->mFaces[f];
    if (face->mNumIndices != 3 || !face->mIndices) {
      s->info->dropped_primitives++;
      continue;
    }
    uint32_t c[3];
    for (int k = 0; k < 3; ++k) {
      if (face->mIndices[k] >= am->mNumVertices)
        return bk_error_set(s->err, "%s: %s, face %u: vertex index %u out of range (%u vertices)", s->name,
                            mesh_label(am, label, sizeof label, index), f, face->mIndices[k],
                            am->mNumVertices);
      c[k] = corner_base + face->mIndices[k];
    }
    if (mirrored)
      bk_mesh_add_triangle(m, c[0], c[2], c[1], material, 0);
    else
      bk_mesh_add_triangle(m, c[0], c[1], c[2], material, 0);
    placed++;
  }
  s->info->triangles_in += placed;
  s->info->meshes++;
  s->info->mirrored_meshes += mirrored;
  return true;
}

// Depth-first walk with an explicit stack, accumulating node transforms.
static bool place_nodes(import_state* s, const struct aiNode* root, const mat4d* parent_world) {
  typedef struct frame {
    const struct aiNode* node;
    mat4d world;
  } frame;
  uint32_t capacity = 64, count = 0;
  frame* stack = bk_alloc(sizeof(frame) * capacity);
  mat4d first = mat4d_of(&root->mTransformation);
  stack[count++] = (frame){root, mat4d_mul(parent_world, &first)};
  bool ok = true;
  uint32_t visited = 0;
  while (count && ok) {
    frame f = stack[--count];
    if (++visited > IMPORT_MAX_NODES) {
      ok = bk_error_set(s->err, "%s: too many nodes (more than %u)", s->name, IMPORT_MAX_NODES);
      break;
    }
    if (!mat4d_finite(&f.world)) {
      ok = bk_error_set(s->err, "%s: node '%.64s' has a non-finite transform", s->name, f.node->mName.data);
      break;
    }
    if (f.node->mNumMeshes && !f.node->mMeshes) {
      ok =
          bk_error_set(s->err, "%s: node '%.64s' lists meshes it does not have", s->name, f.node->mName.data);
      break;
    }
    bool used = false;
    for (uint32_t i = 0; i < f.node->mNumMeshes && ok; ++i) {
      uint32_t mesh = f.node->mMeshes[i];
      if (mesh >= s->scene->mNumMeshes)
        ok = bk_error_set(s->err, "%s: node '%.64s' uses mesh %u of %u", s->name, f.node->mName.data, mesh,
                          s->scene->mNumMeshes);
      else
        ok = place_mesh(s, mesh, &f.world), used = true;
    }
    s->info->nodes_used += used;
    if (f.node->mNumChildren && !f.node->mChildren) {
      ok = bk_error_set(s->err, "%s: node '%.64s' lists children it does not have", s->name,
                        f.node->mName.data);
      break;
    }
    for (uint32_t i = f.node->mNumChildren; i-- > 0 && ok;) {
      const struct aiNode* child = f.node->mChildren[i];
      if (!child) continue;
      if (count == capacity) {
        if (capacity >= IMPORT_MAX_NODES) {
          ok = bk_error_set(s->err, "%s: too many nodes (more than %u)", s->name, IMPORT_MAX_NODES);
          break;
        }
        capacity *= 2;
        stack = bk_realloc(stack, sizeof(frame) * capacity);
      }
      mat4d local = mat4d_of(&child->mTransformation);
      stack[count++] = (frame){child, mat4d_mul(&f.world, &local)};
    }
  }
  bk_free(stack);
  return ok;
}

// Finds a node by name; also counts the nodes and lists a few names for errors.
static const struct aiNode* find_node(const struct aiNode* root, const char* name, mat4d* world,
                                      uint32_t* node_count, char* names, size_t names_size) {
  typedef struct frame {
    const struct aiNode* node;
    mat4d world; // of the node's parent
  } frame;
  uint32_t capacity = 64, count = 0, listed = 0;
  frame* stack = bk_alloc(sizeof(frame) * capacity);
  mat4d identity = {{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}};
  stack[count++] = (frame){root, identity};
  const struct aiNode* found = NULL;
  *node_count = 0;
  if (names_size) names[0] = '\0';
  while (count && *node_count < IMPORT_MAX_NODES) {
    frame f = stack[--count];
    ++*node_count;
    if (name && !found && strcmp(f.node->mName.data, name) == 0) {
      found = f.node;
      *world = f.world;
    }
    if (names_size && f.node->mName.length > 0 && listed <= IMPORT_LISTED_NODES) {
      size_t used = strlen(names);
      if (listed == IMPORT_LISTED_NODES)
        snprintf(names + used, names_size - used, ", ...");
      else
        snprintf(names + used, names_size - used, "%s'%.40s'", listed ? ", " : "", f.node->mName.data);
      listed++;
    }
    mat4d here = mat4d_of(&f.node->mTransformation);
    mat4d world_here = mat4d_mul(&f.world, &here);
    for (uint32_t i = f.node->mNumChildren; f.node->mChildren && i-- > 0;) {
      if (!f.node->mChildren[i]) continue;
      if (count == capacity) {
        if (capacity >= IMPORT_MAX_NODES) break;
        capacity *= 2;
        stack = bk_realloc(stack, sizeof(frame) * capacity);
      }
      stack[count++] = (frame){f.node->mChildren[i], world_here};
    }
  }
  bk_free(stack);
  return found;
}

// ---------------------------------------------------------------- entry points

static bool assimp_failed(const char* name, bk_error* err);

static unsigned import_flags(void) {
  // No aiProcess_FlipWindingOrder or MakeLeftHanded: the files' own
  // right-handed, counter-clockwise convention is ours.
  // (aiProcess_ValidateDataStructure runs at import: failing in
  // aiApplyPostProcessing, assimp 5.2 frees the scene twice.)
  return aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_SortByPType;
}

static struct aiPropertyStore* import_properties(void) {
  struct aiPropertyStore* store = aiCreatePropertyStore();
  aiSetImportPropertyInteger(store, AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  aiSetImportPropertyInteger(store, AI_CONFIG_IMPORT_FBX_READ_ANIMATIONS, 0);
  aiSetImportPropertyInteger(store, AI_CONFIG_IMPORT_FBX_READ_CAMERAS, 0);
  aiSetImportPropertyInteger(store, AI_CONFIG_IMPORT_FBX_READ_LIGHTS, 0);
  return store;
}

// Checks the scene as the reader left it, before assimp's own post-processing
// runs on it (which trusts every index: a face pointing past its mesh's
// vertices aborts it).
static bool check_raw_scene(const struct aiScene* scene, const char* name, bk_error* err) {
  if (scene->mNumMeshes && !scene->mMeshes)
    return bk_error_set(err, "%s: the scene lists meshes it does not have", name);
  // SortByPType fails when it removes every mesh, and assimp 5.2's
  // aiApplyPostProcessing then frees the scene twice: refuse here first.
  uint32_t polygons = 0;
  for (uint32_t i = 0; i < scene->mNumMeshes; ++i) {
    const struct aiMesh* m = scene->mMeshes[i];
    for (uint32_t f = 0; m && m->mFaces && f < m->mNumFaces; ++f)
      polygons += m->mFaces[f].mNumIndices >= 3;
  }
  if (polygons == 0)
    return bk_error_set(err, "%s: no triangles (%s)", name,
                        scene->mNumMeshes ? "only points and lines" : "the scene has no meshes");
  for (uint32_t i = 0; i < scene->mNumMeshes; ++i) {
    const struct aiMesh* m = scene->mMeshes[i];
    char label[96];
    if (!m) return bk_error_set(err, "%s: mesh %u is missing", name, i);
    if ((m->mNumVertices && !m->mVertices) || (m->mNumFaces && !m->mFaces))
      return bk_error_set(err, "%s: %s lists data it does not have", name,
                          mesh_label(m, label, sizeof label, i));
    for (uint32_t f = 0; f < m->mNumFaces; ++f) {
      const struct aiFace* face = &m->mFaces[f];
      if (face->mNumIndices == 0 || !face->mIndices)
        return bk_error_set(err, "%s: %s, face %u has no vertices", name,
                            mesh_label(m, label, sizeof label, i), f);
      for (uint32_t k = 0; k < face->mNumIndices; ++k)
        if (face->mIndices[k] >= m->mNumVertices)
          return bk_error_set(err, "%s: %s, face %u: vertex index %u out of range (%u vertices)", name,
                              mesh_label(m, label, sizeof label, i), f, face->mIndices[k], m->mNumVertices);
    }
  }
  return true;
}

// Reads and validates with no other post-processing, checks, then
// post-processes; NULL (err set) on failure.
static const struct aiScene* read_scene(const char* path, const void* data, size_t size, const char* hint,
                                        const char* name, bk_error* err) {
  struct aiPropertyStore* props = import_properties();
  const unsigned validate = aiProcess_ValidateDataStructure;
  // Every file assimp opens (the model, a .gltf's buffers, textures) is
  // checked to be a regular file first: a FIFO would block it forever.
  struct aiFileIO* io = bk_import_file_io();
  const struct aiScene* scene =
      data ? aiImportFileFromMemoryWithProperties(data, (unsigned)size, validate, hint, props)
           : aiImportFileExWithProperties(path, validate, io, props);
  aiReleasePropertyStore(props);
  if (!scene && bk_import_file_io_refused(name, err)) return NULL;
  if (!scene) return assimp_failed(name, err), NULL;
  if (!check_raw_scene(scene, name, err)) {
    aiReleaseImport(scene);
    return NULL;
  }
  scene = aiApplyPostProcessing(scene, import_flags()); // none of these steps fails on a checked scene
  if (!scene) return assimp_failed(name, err), NULL;
  return scene;
}

// Turns an imported scene into the mesh (node selection, placement, material, finishing).
static bool convert_scene(const struct aiScene* scene, const char* name, const char* ext,
                          const char* base_dir, const bk_import_def* def, bk_mesh* out, bk_import_info* info,
                          bk_error* err) {
  if (!scene->mRootNode) return bk_error_set(err, "%s: the scene has no nodes", name);
  if (scene->mNumMeshes && !scene->mMeshes)
    return bk_error_set(err, "%s: the scene lists meshes it does not have", name);
  import_state s = {.name = name, .base_dir = base_dir, .def = def, .scene = scene, .info = info, .err = err};
  // One more slot than the scene has: meshes naming no valid material.
  s.source_of_material = bk_alloc(sizeof(uint32_t) * (scene->mNumMaterials + 1u));
  memset(s.source_of_material, 0xff, sizeof(uint32_t) * (scene->mNumMaterials + 1u));
  mat4d parent = {{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}};
  char names[320];
  const struct aiNode* start =
      find_node(scene->mRootNode, def->node, &parent, &info->nodes, names, sizeof names);
  bk_import_read_units(scene, ext, info);
  for (int i = 0; i < 3; ++i) // metres: the unit scales everything below the root
    for (int j = 0; j < 4; ++j)
      parent.m[i][j] *= info->metres_per_unit;
  bool ok = true;
  if (def->node && !start)
    ok = bk_error_set(err, "%s: no node named '%.80s' (nodes: %s)", name, def->node,
                      names[0] ? names : "none named");
  else
    ok = place_nodes(&s, start ? start : scene->mRootNode, &parent) && bk_import_finish_mesh(&s);
  if (ok) bk_import_read_materials(&s);
  bk_free(s.corner_has_normal);
  bk_free(s.corner_has_uv);
  bk_free(s.source_of_material);
  if (ok) {
    *out = s.mesh;
  } else {
    bk_mesh_free(&s.mesh);
  }
  return ok;
}

// One-line reason from assimp's last error.
static bool assimp_failed(const char* name, bk_error* err) {
  char reason[300];
  const char* text = aiGetErrorString();
  if (!text || !text[0]) text = "unknown error";
  bk_import_copy_text(reason, sizeof reason, text, strlen(text));
  return bk_error_set(err, "%s: cannot import: %s", name, reason);
}

bool bk_import_assimp_memory(const void* data, size_t size, const char* ext, const char* name,
                             const bk_import_def* def, bk_mesh* out, bk_import_info* info, bk_error* err) {
  pthread_mutex_lock(&import_lock);
  bk_c_locale locale = bk_c_locale_begin();
  const struct aiScene* scene = read_scene(NULL, data, size, ext, name, err);
  bool ok = scene && convert_scene(scene, name, ext, "", def, out, info, err);
  aiReleaseImport(scene);
  bk_c_locale_end(&locale);
  pthread_mutex_unlock(&import_lock);
  return ok;
}

bool bk_import_assimp_file(const char* path, const char* ext, const bk_import_def* def, bk_mesh* out,
                           bk_import_info* info, bk_error* err) {
  char base_dir[BK_IMPORT_TEXT_MAX];
  const char* slash = strrchr(path, '/');
  if (!slash)
    snprintf(base_dir, sizeof base_dir, ".");
  else if (slash == path)
    snprintf(base_dir, sizeof base_dir, "/");
  else
    snprintf(base_dir, sizeof base_dir, "%.*s", (int)(slash - path), path);
  pthread_mutex_lock(&import_lock);
  bk_c_locale locale = bk_c_locale_begin();
  const struct aiScene* scene = read_scene(path, NULL, 0, ext, path, err);
  bool ok = scene && convert_scene(scene, path, ext, base_dir, def, out, info, err);
  aiReleaseImport(scene);
  bk_c_locale_end(&locale);
  pthread_mutex_unlock(&import_lock);
  return ok;
}
