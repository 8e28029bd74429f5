// The runtime for the page: create it, add breakables, feed contacts, split,
// and read the events, as flat arrays of doubles JavaScript views in place
// (web_runtime_events' layout, one record per event, in web/js/breakables.js).
// The page's physics engine answers where a cluster's body is through
// Module.bodyState, called from here while the runtime works.
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "web_bridge.h"

typedef struct web_runtime {
  bk_runtime* runtime;
  int handle;  // the page's key of this runtime, given back in body-state calls
  double* out; // the last event or cluster records
  uint32_t out_count, out_capacity;
} web_runtime;

// Asks the page for a body's state: 13 doubles (position, rotation x y z w,
// linear and angular velocity) written at `out`.
EM_JS(void, web_ask_body_state, (int handle, uint32_t index, uint32_t generation, double* out),
      { Module["bodyState"](handle, index, generation, out); });

static bk_body_state body_state(bk_cluster_id cluster, void* context) {
  const web_runtime* w = context;
  double v[13] = {0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0};
  web_ask_body_state(w->handle, cluster.index, cluster.generation, v);
  bk_body_state s = {0};
  s.transform.position = bk_v3(v[0], v[1], v[2]);
  s.transform.rotation = (bk_quat){v[3], v[4], v[5], v[6]};
  s.linear_velocity = bk_v3(v[7], v[8], v[9]);
  s.angular_velocity = bk_v3(v[10], v[11], v[12]);
  return s;
}

EMSCRIPTEN_KEEPALIVE web_runtime* web_runtime_create(int handle, double gx, double gy, double gz) {
  web_runtime* w = bk_calloc(1, sizeof *w);
  w->handle = handle;
  bk_runtime_def def = bk_default_runtime_def();
  def.gravity = bk_v3(gx, gy, gz);
  def.refine_threads = 0; // no threads in this build: refinement lands on the calling thread
  def.body_state = body_state;
  def.context = w;
  bk_error err = {0};
  w->runtime = bk_runtime_create(&def, &err);
  if (!w->runtime) {
    web_set_error(&err);
    bk_free(w);
    return NULL;
  }
  return w;
}

EMSCRIPTEN_KEEPALIVE void web_runtime_destroy(web_runtime* w) {
  if (!w) return;
  bk_runtime_destroy(w->runtime);
  bk_free(w->out);
  bk_free(w);
}

/// Adds a breakable of `tree` (a web_tree: its tree must outlive the
/// runtime) at position p and rotation q (x y z w), of the named material.
/// Writes its id (index, generation) to id[2]; false with the error kept.
EMSCRIPTEN_KEEPALIVE bool web_runtime_add(web_runtime* w, const web_tree* tree, const double* p,
                                          const double* q, const char* material, int anchored,
                                          double anchor_height, uint32_t* id) {
  bk_breakable_def def = bk_default_breakable_def();
  def.tree = &tree->tree;
  def.transform.position = bk_v3(p[0], p[1], p[2]);
  def.transform.rotation = (bk_quat){q[0], q[1], q[2], q[3]};
  if (material && material[0]) {
    const bk_material* m = bk_material_find(material);
    if (!m) {
      bk_error err = {0};
      bk_error_set(&err, "breakable: unknown material '%s'", material);
      web_set_error(&err);
      return false;
    }
    def.material = *m;
  }
  def.anchored = anchored != 0;
  def.anchor_height = anchor_height;
  bk_error err = {0};
  bk_breakable_id b = bk_runtime_add_breakable(w->runtime, &def, &err);
  if (bk_breakable_is_null(b)) {
    web_set_error(&err);
    return false;
  }
  id[0] = b.index, id[1] = b.generation;
  return true;
}

/// Contacts as 7 doubles each: cluster index, generation, point xyz,
/// impulse, closing speed.
EMSCRIPTEN_KEEPALIVE void web_runtime_contacts(web_runtime* w, const double* data, uint32_t count) {
  if (!count) return;
  bk_damage_contact* contacts = bk_alloc(count * sizeof *contacts);
  for (uint32_t i = 0; i < count; ++i) {
    const double* c = &data[7 * i];
    contacts[i] = (bk_damage_contact){.cluster = {(uint32_t)c[0], (uint32_t)c[1]},
                                      .point = bk_v3(c[2], c[3], c[4]),
                                      .impulse = c[5],
                                      .closing_speed = c[6]};
  }
  bk_runtime_apply_contacts(w->runtime, contacts, count);
  bk_free(contacts);
}

EMSCRIPTEN_KEEPALIVE void web_runtime_damage_at(web_runtime* w, double x, double y, double z,
                                                double impulse) {
  bk_runtime_damage_at(w->runtime, bk_v3(x, y, z), impulse);
}
EMSCRIPTEN_KEEPALIVE uint32_t web_runtime_split(web_runtime* w) { return bk_runtime_split(w->runtime); }
EMSCRIPTEN_KEEPALIVE void web_runtime_clear_events(web_runtime* w) { bk_runtime_clear_events(w->runtime); }
EMSCRIPTEN_KEEPALIVE bool web_runtime_remove_cluster(web_runtime* w, uint32_t index, uint32_t generation) {
  return bk_runtime_remove_cluster(w->runtime, (bk_cluster_id){index, generation}) == BK_OK;
}

// ---------------------------------------------------------------- records

static double* room(web_runtime* w, uint32_t more) {
  if (w->out_count + more > w->out_capacity) {
    uint32_t capacity = (w->out_count + more) * 2 + 64;
    w->out = bk_realloc(w->out, capacity * sizeof(double));
    w->out_capacity = capacity;
  }
  double* at = w->out + w->out_count;
  w->out_count += more;
  return at;
}

static void put_transform(double* d, bk_transform t) {
  d[0] = t.position.x, d[1] = t.position.y, d[2] = t.position.z;
  d[3] = t.rotation.x, d[4] = t.rotation.y, d[5] = t.rotation.z, d[6] = t.rotation.w;
}

// A cluster: index, generation, breakable index, generation, static, leaf
// count L, node count N, mass, volume, inertia xyz, principal (7), then L
// leaves and N nodes: 19 + L + N doubles.
static void put_cluster(web_runtime* w, const bk_cluster_info* c) {
  double* d = room(w, 19 + c->leaf_count + c->node_count);
  d[0] = c->id.index, d[1] = c->id.generation, d[2] = c->breakable.index, d[3] = c->breakable.generation;
  d[4] = c->is_static ? 1 : 0, d[5] = c->leaf_count, d[6] = c->node_count, d[7] = c->mass, d[8] = c->volume;
  d[9] = c->inertia.x, d[10] = c->inertia.y, d[11] = c->inertia.z;
  put_transform(&d[12], c->principal);
  for (uint32_t i = 0; i < c->leaf_count; ++i)
    d[19 + i] = c->leaves[i];
  for (uint32_t i = 0; i < c->node_count; ++i)
    d[19 + c->leaf_count + i] = c->nodes[i];
}

/// The events since the last clear, as records (kinds in order: created
/// clusters, then removed, then broken bonds); counts into counts[3].
/// Created: parent index, generation, body (13: transform 7, v, w), then
/// the cluster record. Removed: cluster index, generation, breakable index,
/// generation. Broken: breakable index, generation, cluster index,
/// generation, bond, position xyz, velocity xyz, area, cause (0 damage,
/// 1 stress). The array stays valid until the next call here.
EMSCRIPTEN_KEEPALIVE const double* web_runtime_events(web_runtime* w, uint32_t* counts) {
  w->out_count = 0;
  uint32_t created = bk_runtime_created_clusters(w->runtime, NULL, 0);
  uint32_t removed = bk_runtime_removed_clusters(w->runtime, NULL, 0);
  uint32_t broken = bk_runtime_broken_bonds(w->runtime, NULL, 0);
  uint32_t most = created > removed ? created : removed;
  most = most > broken ? most : broken;
  void* scratch =
      bk_alloc((size_t)(most ? most : 1) * sizeof(bk_cluster_created) + sizeof(bk_bond_break) * most);
  bk_cluster_created* c = scratch;
  bk_runtime_created_clusters(w->runtime, c, created);
  for (uint32_t i = 0; i < created; ++i) {
    double* d = room(w, 15);
    d[0] = c[i].parent.index, d[1] = c[i].parent.generation;
    put_transform(&d[2], c[i].body.transform);
    d[9] = c[i].body.linear_velocity.x, d[10] = c[i].body.linear_velocity.y,
    d[11] = c[i].body.linear_velocity.z;
    d[12] = c[i].body.angular_velocity.x, d[13] = c[i].body.angular_velocity.y;
    d[14] = c[i].body.angular_velocity.z;
    put_cluster(w, &c[i].cluster);
  }
  bk_cluster_removed* r = scratch;
  bk_runtime_removed_clusters(w->runtime, r, removed);
  for (uint32_t i = 0; i < removed; ++i) {
    double* d = room(w, 4);
    d[0] = r[i].cluster.index, d[1] = r[i].cluster.generation, d[2] = r[i].breakable.index;
    d[3] = r[i].breakable.generation;
  }
  bk_bond_break* b = scratch;
  bk_runtime_broken_bonds(w->runtime, b, broken);
  for (uint32_t i = 0; i < broken; ++i) {
    double* d = room(w, 13);
    d[0] = b[i].breakable.index, d[1] = b[i].breakable.generation, d[2] = b[i].cluster.index;
    d[3] = b[i].cluster.generation, d[4] = b[i].bond, d[5] = b[i].position.x, d[6] = b[i].position.y;
    d[7] = b[i].position.z, d[8] = b[i].velocity.x, d[9] = b[i].velocity.y, d[10] = b[i].velocity.z;
    d[11] = b[i].area, d[12] = b[i].cause == BK_BREAK_STRESS ? 1 : 0;
  }
  bk_free(scratch);
  counts[0] = created, counts[1] = removed, counts[2] = broken;
  return w->out;
}

/// A live cluster's record (as in web_runtime_events), NULL for a stale id.
EMSCRIPTEN_KEEPALIVE const double* web_runtime_cluster(web_runtime* w, uint32_t index, uint32_t generation) {
  bk_cluster_info info = {0};
  if (!bk_runtime_cluster(w->runtime, (bk_cluster_id){index, generation}, &info)) return NULL;
  w->out_count = 0;
  put_cluster(w, &info);
  return w->out;
}

// ---------------------------------------------------------------- materials and state

static bk_breakable_id breakable(uint32_t index, uint32_t generation) {
  return (bk_breakable_id){index, generation};
}
EMSCRIPTEN_KEEPALIVE bool web_runtime_set_frailty(web_runtime* w, uint32_t i, uint32_t g, double v) {
  return bk_runtime_set_frailty(w->runtime, breakable(i, g), v) == BK_OK;
}
EMSCRIPTEN_KEEPALIVE bool web_runtime_set_density(web_runtime* w, uint32_t i, uint32_t g, double v) {
  return bk_runtime_set_density(w->runtime, breakable(i, g), v) == BK_OK;
}
EMSCRIPTEN_KEEPALIVE double web_runtime_frailty(web_runtime* w, uint32_t i, uint32_t g) {
  return bk_runtime_frailty(w->runtime, breakable(i, g));
}
EMSCRIPTEN_KEEPALIVE double web_runtime_density(web_runtime* w, uint32_t i, uint32_t g) {
  return bk_runtime_density(w->runtime, breakable(i, g));
}
EMSCRIPTEN_KEEPALIVE void web_runtime_state_hash(web_runtime* w, char* out) {
  snprintf(out, 17, "%016llx", (unsigned long long)bk_runtime_state_hash(w->runtime));
}
/// clusters, bonds broken, splits, pending splits, breakables.
EMSCRIPTEN_KEEPALIVE void web_runtime_stats(web_runtime* w, double* out) {
  bk_runtime_stats s = bk_runtime_get_stats(w->runtime);
  out[0] = s.clusters, out[1] = s.bonds_broken, out[2] = s.splits, out[3] = s.pending_splits,
  out[4] = s.breakables;
}

// ---------------------------------------------------------------- materials table

EMSCRIPTEN_KEEPALIVE uint32_t web_material_count(void) { return bk_material_count(); }
/// Material i: its name, and density, frailty, bond strength, friction,
/// restitution into out[5].
EMSCRIPTEN_KEEPALIVE const char* web_material(uint32_t i, double* out) {
  const bk_material* m = bk_material_at(i);
  if (!m) return NULL;
  out[0] = m->density, out[1] = m->frailty, out[2] = m->bond_strength, out[3] = m->friction;
  out[4] = m->restitution;
  return m->name;
}
