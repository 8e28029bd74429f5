// Breakables: an instance of a mesh tree with its BCRB graph (bonds incident
// to each leaf, hit points by bond area), anchoring, and its live material.
#include <stdlib.h>
#include <string.h>

#include "runtime_internal.h"

bk_breakable_def bk_default_breakable_def(void) {
  return (bk_breakable_def){
      .tree = NULL,
      .transform = {{0, 0, 0}, {0, 0, 0, 1}},
      .material = {.name = "default",
                   .density = 2400.0,
                   .frailty = 1.0,
                   .bond_strength = 2.0e5,
                   .accumulate = false,
                   .friction = 0.6,
                   .restitution = 0.1,
                   .compression_limit = 2.0e7,
                   .tension_limit = 1.0e6,
                   .shear_limit = 2.0e6},
      .anchored = false,
      .anchor_height = 0.0,
      .user_data = NULL,
      .refine = {.pattern = BK_PATTERN_RADIAL, .pieces = 32, .min_size = 0.02, .radial_falloff = 1.0}};
}

static void set_material(rt_breakable* b, const bk_material* m) {
  // m may be what bk_runtime_material returned, its name our own buffer.
  char name[BK_MATERIAL_NAME_MAX + 1] = {0};
  snprintf(name, sizeof name, "%s", m->name ? m->name : "");
  memcpy(b->material_name, name, sizeof name);
  b->material = *m;
  b->material.name = b->material_name;
}

static bool quat_is_finite(bk_quat q) {
  return isfinite(q.x) && isfinite(q.y) && isfinite(q.z) && isfinite(q.w);
}

bk_breakable_id bk_runtime_add_breakable(bk_runtime* rt, const bk_breakable_def* def, bk_error* err) {
  bk_breakable_id null_id = {0, 0};
  const bk_result invalid = BK_ERROR_INVALID_ARGUMENT;
  if (!def) return bk_error_set_code(err, invalid, "breakable: def is NULL"), null_id;
  const bk_mesh_tree* tree = def->tree;
  if (!tree || tree->node_count == 0 || tree->leaf_count == 0)
    return bk_error_set_code(err, tree ? BK_ERROR_BAD_TREE : invalid, "breakable: tree is missing or empty"),
           null_id;
  bk_error material_err = {0};
  if (!bk_material_validate(&def->material, &material_err))
    return bk_error_set_code(err, invalid, "breakable: %s", material_err.message), null_id;
  bk_quat q = def->transform.rotation;
  if (!bk_v3_is_finite(def->transform.position) || !quat_is_finite(q))
    return bk_error_set_code(err, invalid, "breakable: transform must be finite"), null_id;
  double q_length = sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
  if (!(q_length > 0.5 && q_length < 2.0))
    return bk_error_set_code(err, invalid,
                             "breakable: transform.rotation must be a unit quaternion (length %g)", q_length),
           null_id;
  if (def->material.refine_strength > 0.0 && !rt_refine_def_validate(&def->refine, err)) return null_id;
  if (!isfinite(def->anchor_height))
    return bk_error_set_code(err, invalid, "breakable: anchor_height must be finite (got %g)",
                             def->anchor_height),
           null_id;
  // The tree is the caller's and may have been made or changed by hand: every
  // index below (bonds into leaves, leaves into nodes) and every mass must
  // hold before anything is allocated from it. Checked on every add, not
  // once per tree pointer: the caller may change its tree between adds.
  bk_error tree_err = {{0}};
  if (!bk_mesh_tree_validate(tree, &tree_err))
    return bk_error_set_code(err, BK_ERROR_BAD_TREE, "breakable: tree: %s", tree_err.message), null_id;
  bk_transform transform = {def->transform.position, bk_quat_normalize(q)};

  // A removed breakable's slot first (the lowest), with a new generation.
  uint32_t index = 0;
  while (index < rt->breakable_count && rt->breakables[index].alive)
    index++;
  uint32_t generation = 1;
  if (index == rt->breakable_count) {
    if (rt->breakable_count == rt->breakable_capacity) {
      rt->breakable_capacity = bk_grow_capacity(rt->breakable_capacity, rt->breakable_count + 1);
      rt->breakables = bk_realloc(rt->breakables, sizeof(rt_breakable) * rt->breakable_capacity);
    }
    rt->breakable_count++;
  } else {
    generation = rt->breakables[index].generation + 1;
    if (generation == 0) generation = 1; // after 2^32 reuses; 0 stays the null id
  }
  rt_breakable* b = &rt->breakables[index];
  memset(b, 0, sizeof *b);
  b->tree = tree;
  b->source = tree;
  b->generation = generation;
  b->alive = true;
  b->user_data = def->user_data;
  b->refine = def->refine;
  b->anchored = def->anchored;
  b->anchor_height = def->anchor_height;
  b->placement = transform;
  b->up = rt->up;
  rt->live_breakables++;
  set_material(b, &def->material);

  // The BCRB graph: bonds incident to each leaf (CSR), hit points by area.
  uint32_t leaves = tree->leaf_count, bonds = tree->bond_count;
  rt_breakable_build_adjacency(b);
  b->bond_hp = bk_alloc(sizeof(double) * (bonds + 1u));
  b->bond_hp_initial = bk_alloc(sizeof(double) * (bonds + 1u));
  b->bond_broken = bk_calloc(bonds + 1u, 1);
  for (uint32_t i = 0; i < bonds; ++i)
    b->bond_hp[i] = b->bond_hp_initial[i] = b->material.bond_strength * tree->bonds[i].area;
  b->leaf_cluster = bk_alloc(sizeof(uint32_t) * leaves);
  b->leaf_anchored = bk_calloc(leaves, 1);
  if (def->anchored) {
    // Fragments with a vertex on the support plane are bonded to the world;
    // "up" is the opposite of gravity (exactly +Y for gravity along -Y).
    double tolerance =
        1e-6 + 1e-6 * bk_v3_length(bk_v3_sub(tree->nodes[0].bounds.max, tree->nodes[0].bounds.min));
    bk_vec3 up = rt->up;
    for (uint32_t l = 0; l < leaves; ++l) {
      const bk_mesh* mesh = &bk_mesh_tree_leaf(tree, l)->mesh;
      for (uint32_t p = 0; p < mesh->position_count && !b->leaf_anchored[l]; ++p)
        b->leaf_anchored[l] = bk_v3_dot(bk_transform_point(transform, mesh->positions[p]), up) <=
                              def->anchor_height + tolerance;
    }
  }

  uint32_t slot = rt_cluster_alloc(rt, index);
  rt_cluster* c = &rt->clusters[slot];
  c->leaves = bk_alloc(sizeof(uint32_t) * leaves);
  for (uint32_t l = 0; l < leaves; ++l)
    c->leaves[l] = l;
  c->leaf_count = leaves;
  c->user_data = def->user_data;
  rt_cluster_finish(rt, slot);
  rt_record_created(rt, slot, (bk_cluster_id){0, 0}, transform, NULL);
  rt_journal_breakable(rt, index, true);
  return (bk_breakable_id){index, b->generation};
}

const bk_mesh_tree* bk_runtime_breakable_tree(const bk_runtime* rt, bk_breakable_id id) {
  const rt_breakable* b = rt_find_breakable(rt, id);
  return b ? b->tree : NULL;
}

void rt_breakable_build_adjacency(rt_breakable* b) {
  const bk_mesh_tree* tree = b->tree;
  uint32_t leaves = tree->leaf_count, bonds = tree->bond_count;
  bk_free(b->adjacency_start);
  bk_free(b->adjacency);
  b->adjacency_start = bk_calloc(leaves + 1u, sizeof(uint32_t));
  b->adjacency = bk_alloc(sizeof(uint32_t) * (2u * bonds + 1u));
  for (uint32_t i = 0; i < bonds; ++i) {
    b->adjacency_start[tree->bonds[i].leaf_a + 1]++;
    b->adjacency_start[tree->bonds[i].leaf_b + 1]++;
  }
  for (uint32_t i = 0; i < leaves; ++i)
    b->adjacency_start[i + 1] += b->adjacency_start[i];
  uint32_t* fill = bk_alloc(sizeof(uint32_t) * (leaves + 1u));
  memcpy(fill, b->adjacency_start, sizeof(uint32_t) * leaves);
  for (uint32_t i = 0; i < bonds; ++i) {
    b->adjacency[fill[tree->bonds[i].leaf_a]++] = i;
    b->adjacency[fill[tree->bonds[i].leaf_b]++] = i;
  }
  bk_free(fill);
}

bool rt_refine_def_validate(const bk_refine_def* d, bk_error* err) {
  const bk_result invalid = BK_ERROR_INVALID_ARGUMENT;
  if (d->pattern != BK_PATTERN_RADIAL && d->pattern != BK_PATTERN_VORONOI && d->pattern != BK_PATTERN_PLANES)
    return bk_error_set_code(err, invalid,
                             "breakable: refine.pattern must be radial, voronoi or planes (got %s)",
                             bk_fracture_pattern_name(d->pattern));
  if (d->pieces < 2 || d->pieces > 1024)
    return bk_error_set_code(err, invalid, "breakable: refine.pieces must be in [2, 1024] (got %u)",
                             d->pieces);
  if (!(d->min_size > 0.0) || !isfinite(d->min_size))
    return bk_error_set_code(err, invalid, "breakable: refine.min_size must be positive (got %g)",
                             d->min_size);
  if (!(d->radial_falloff >= 0.0 && d->radial_falloff <= 1.4))
    return bk_error_set_code(err, invalid, "breakable: refine.radial_falloff must be in [0, 1.4] (got %g)",
                             d->radial_falloff);
  return true;
}

// The runtime's own copy of a refined breakable's tree (refine.c): its
// arrays, and the meshes of the nodes refinement made (the first
// shared_nodes nodes' meshes are the caller's).
void rt_breakable_free_tree(rt_breakable* b) {
  bk_mesh_tree* t = b->own_tree;
  if (!t) return;
  for (uint32_t i = b->shared_nodes; i < t->node_count; ++i)
    bk_mesh_free(&t->nodes[i].mesh);
  bk_free(t->nodes);
  bk_free(t->leaf_nodes);
  bk_free(t->bonds);
  bk_free(t);
  b->own_tree = NULL;
}

void rt_breakable_free(rt_breakable* b) {
  rt_breakable_free_tree(b);
  bk_free(b->leaf_refining);
  bk_free(b->adjacency_start);
  bk_free(b->adjacency);
  bk_free(b->bond_hp);
  bk_free(b->bond_hp_initial);
  bk_free(b->bond_broken);
  bk_free(b->leaf_cluster);
  bk_free(b->leaf_anchored);
  bk_free(b->leaf_centroid);
  bk_free(b->leaf_volume);
  bk_free(b->leaf_motion);
  bk_free(b->bond_stress);
  uint32_t generation = b->generation;
  memset(b, 0, sizeof *b);
  b->generation = generation;
}

bk_result bk_runtime_remove_breakable(bk_runtime* rt, bk_breakable_id id) {
  rt_breakable* b = rt_find_breakable(rt, id);
  if (!b) return BK_ERROR_STALE_ID;
  rt_journal_breakable(rt, id.index, false);
  rt_refine_cancel(rt, id.index);
  for (uint32_t slot = 0; slot < rt->cluster_count; ++slot)
    if (rt->clusters[slot].alive && rt->clusters[slot].breakable == id.index) rt_remove_cluster(rt, slot);
  rt_breakable_free(b);
  rt->live_breakables--;
  return BK_OK;
}

void* bk_runtime_breakable_user_data(const bk_runtime* rt, bk_breakable_id id) {
  const rt_breakable* b = rt_find_breakable(rt, id);
  return b ? b->user_data : NULL;
}

bk_result bk_runtime_set_breakable_user_data(bk_runtime* rt, bk_breakable_id id, void* user_data) {
  rt_breakable* b = rt_find_breakable(rt, id);
  if (!b) return BK_ERROR_STALE_ID;
  b->user_data = user_data;
  return BK_OK;
}

// Mass properties follow the density of every cluster of the breakable.
static void refresh_masses(bk_runtime* rt, uint32_t breakable_index) {
  for (uint32_t i = 0; i < rt->cluster_count; ++i) {
    rt_cluster* c = &rt->clusters[i];
    if (c->alive && c->breakable == breakable_index) rt_cluster_mass(rt, c);
  }
}

// Intact bonds keep the fraction of hit points they had left (never more
// than all of them: an untouched bond's product can round up by an ulp).
static void rescale_bonds(rt_breakable* b, double bond_strength) {
  for (uint32_t i = 0; i < b->tree->bond_count; ++i) {
    double initial = bond_strength * b->tree->bonds[i].area;
    if (!b->bond_broken[i] && b->bond_hp_initial[i] > 0.0)
      b->bond_hp[i] = fmin(b->bond_hp[i] * (initial / b->bond_hp_initial[i]), initial);
    b->bond_hp_initial[i] = initial;
  }
}

bk_result bk_runtime_set_material(bk_runtime* rt, bk_breakable_id id, const bk_material* material) {
  rt_breakable* b = rt_find_breakable(rt, id);
  if (!b) return BK_ERROR_STALE_ID;
  if (!bk_material_validate(material, NULL)) return BK_ERROR_INVALID_ARGUMENT;
  if (material->refine_strength > 0.0 && !rt_refine_def_validate(&b->refine, NULL))
    return BK_ERROR_INVALID_ARGUMENT;
  bool density_changed = material->density != b->material.density;
  if (material->bond_strength != b->material.bond_strength) rescale_bonds(b, material->bond_strength);
  set_material(b, material);
  if (density_changed) refresh_masses(rt, id.index);
  rt_stress_material_changed(rt, id.index); // new loads or limits: check the bonds again
  rt_journal_material(rt, id.index);
  return BK_OK;
}

bk_result bk_runtime_set_frailty(bk_runtime* rt, bk_breakable_id id, double frailty) {
  rt_breakable* b = rt_find_breakable(rt, id);
  if (!b) return BK_ERROR_STALE_ID;
  if (!(frailty >= 0.0) || !isfinite(frailty)) return BK_ERROR_INVALID_ARGUMENT;
  b->material.frailty = frailty;
  rt_journal_material(rt, id.index);
  return BK_OK;
}

bk_result bk_runtime_set_density(bk_runtime* rt, bk_breakable_id id, double density) {
  rt_breakable* b = rt_find_breakable(rt, id);
  if (!b) return BK_ERROR_STALE_ID;
  if (!(density >= BK_MATERIAL_DENSITY_MIN && density <= BK_MATERIAL_DENSITY_MAX))
    return BK_ERROR_INVALID_ARGUMENT;
  b->material.density = density;
  refresh_masses(rt, id.index);
  rt_stress_material_changed(rt, id.index);
  rt_journal_material(rt, id.index);
  return BK_OK;
}

bk_result bk_runtime_set_bond_strength(bk_runtime* rt, bk_breakable_id id, double bond_strength) {
  rt_breakable* b = rt_find_breakable(rt, id);
  if (!b) return BK_ERROR_STALE_ID;
  if (!(bond_strength >= BK_MATERIAL_BOND_STRENGTH_MIN && bond_strength <= BK_MATERIAL_BOND_STRENGTH_MAX))
    return BK_ERROR_INVALID_ARGUMENT;
  rescale_bonds(b, bond_strength);
  b->material.bond_strength = bond_strength;
  rt_journal_material(rt, id.index);
  return BK_OK;
}

bk_material bk_runtime_material(const bk_runtime* rt, bk_breakable_id id) {
  const rt_breakable* b = rt_find_breakable(rt, id);
  return b ? b->material : (bk_material){0};
}

double bk_runtime_frailty(const bk_runtime* rt, bk_breakable_id id) {
  return bk_runtime_material(rt, id).frailty;
}
double bk_runtime_density(const bk_runtime* rt, bk_breakable_id id) {
  return bk_runtime_material(rt, id).density;
}
double bk_runtime_bond_strength(const bk_runtime* rt, bk_breakable_id id) {
  return bk_runtime_material(rt, id).bond_strength;
}
