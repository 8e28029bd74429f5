// Loads on a cluster beyond its own weight, for the stress solve: things
// resting on it (a weight on a bridge, debris on a balcony), passed by the
// caller as forces at world points. Each is moved to the leaf under it (a
// force at that leaf's centroid and its moment about it); a cluster's loads
// are averaged over a window of calls and kept with its solve, and only a
// change of more than a tenth of its weight and loads solves it again, so
// contact forces that flicker from step to step do not keep a structure
// awake.
#include <stdlib.h>
#include <string.h>

#include "stress_leaves.h"
#include "stress_loads.h"

// Calls a cluster's loads are averaged over before they count (a quarter of
// a second at 60 Hz): a body coming to rest on it bounces, and a resting
// contact's force flickers from step to step.
enum { LOAD_WINDOW_CALLS = 15 };

static int compare_loads(const void* a, const void* b) {
  const rt_leaf_load *x = a, *y = b;
  if (x->slot != y->slot) return x->slot < y->slot ? -1 : 1;
  return x->leaf < y->leaf ? -1 : x->leaf > y->leaf;
}

uint32_t rt_stress_gather_loads(bk_runtime* rt, const bk_stress_load* loads, uint32_t count) {
  if (!loads) count = 0;
  if (rt->stress_load_scratch_capacity < count) {
    rt->stress_load_scratch_capacity = bk_grow_capacity(rt->stress_load_scratch_capacity, count);
    rt->stress_load_scratch =
        bk_realloc(rt->stress_load_scratch, sizeof(rt_leaf_load) * rt->stress_load_scratch_capacity);
  }
  rt_leaf_load* out = rt->stress_load_scratch;
  uint32_t n = 0;
  for (uint32_t i = 0; i < count; ++i) {
    const bk_stress_load* load = &loads[i];
    rt_cluster* c = rt_find_cluster(rt, load->cluster);
    if (!c || c->dirty || c->leaf_count < 2 || !bk_v3_is_finite(load->point) || !bk_v3_is_finite(load->force))
      continue;
    // A moving cluster carries loads only while it rests (since the last
    // call): debris knocking against debris in flight loads nothing.
    if (!c->is_static && c->stress_rest_calls == 0) continue;
    rt_breakable* b = &rt->breakables[c->breakable];
    rt_stress_prepare_breakable(b);
    bk_body_state state = rt_body_state(rt, load->cluster.index);
    bk_transform to_world = rt_tree_to_world(c, &state);
    bk_transform to_tree = bk_transform_inverse(to_world);
    bk_vec3 point = bk_transform_point(to_tree, load->point);
    bk_vec3 force = bk_quat_rotate(bk_quat_conjugate(to_world.rotation), load->force);
    if (!bk_v3_is_finite(point) || !bk_v3_is_finite(force)) continue; // a body its caller lost
    uint32_t leaf = rt_stress_leaf_at(b, c, point);
    bk_vec3 torque = bk_v3_cross(bk_v3_sub(point, b->leaf_centroid[leaf]), force);
    out[n++] = (rt_leaf_load){
        load->cluster.index, leaf, {force.x, force.y, force.z}, {torque.x, torque.y, torque.z}};
  }
  if (n) bk_sort(out, n, sizeof *out, compare_loads);
  uint32_t unique = 0;
  for (uint32_t i = 0; i < n; ++i) {
    if (unique && out[unique - 1].slot == out[i].slot && out[unique - 1].leaf == out[i].leaf) {
      for (int d = 0; d < 3; ++d) {
        out[unique - 1].force[d] += out[i].force[d];
        out[unique - 1].torque[d] += out[i].torque[d];
      }
    } else {
      out[unique++] = out[i];
    }
  }
  return unique;
}

static double length3(const double v[3]) { return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

static bool loads_differ(const rt_leaf_load* kept, uint32_t kept_count, const rt_leaf_load* loads,
                         uint32_t count, double weight) {
  double difference = 0.0, scale = weight;
  uint32_t i = 0, j = 0;
  while (i < kept_count || j < count) {
    bool take_kept = j == count || (i < kept_count && kept[i].leaf < loads[j].leaf);
    bool take_new = i == kept_count || (j < count && loads[j].leaf < kept[i].leaf);
    double delta[3] = {0};
    for (int d = 0; d < 3; ++d)
      delta[d] = (take_new ? 0.0 : kept[i].force[d]) - (take_kept ? 0.0 : loads[j].force[d]);
    if (!take_new) scale += length3(kept[i].force);
    difference += length3(delta);
    i += !take_new;
    j += !take_kept;
  }
  return difference > 0.1 * scale;
}

// window += loads (both sorted by leaf).
static void window_add(rt_cluster* c, const rt_leaf_load* loads, uint32_t count) {
  if (!count) return;
  rt_leaf_load* merged = bk_alloc(sizeof(rt_leaf_load) * (c->stress_window_count + count));
  uint32_t i = 0, j = 0, n = 0;
  const rt_leaf_load* window = c->stress_window;
  while (i < c->stress_window_count || j < count) {
    if (j == count || (i < c->stress_window_count && window[i].leaf < loads[j].leaf)) {
      merged[n++] = window[i++];
    } else if (i == c->stress_window_count || loads[j].leaf < window[i].leaf) {
      merged[n++] = loads[j++];
    } else {
      merged[n] = window[i++];
      for (int d = 0; d < 3; ++d) {
        merged[n].force[d] += loads[j].force[d];
        merged[n].torque[d] += loads[j].torque[d];
      }
      n++, j++;
    }
  }
  bk_free(c->stress_window);
  c->stress_window = merged;
  c->stress_window_count = n;
}

bool rt_stress_window_loads(rt_cluster* c, const rt_leaf_load* loads, uint32_t count, double weight) {
  window_add(c, loads, count);
  if (++c->stress_window_calls < LOAD_WINDOW_CALLS) return false;
  for (uint32_t i = 0; i < c->stress_window_count; ++i)
    for (int d = 0; d < 3; ++d) {
      c->stress_window[i].force[d] /= c->stress_window_calls;
      c->stress_window[i].torque[d] /= c->stress_window_calls;
    }
  bool changed =
      loads_differ(c->stress_loads, c->stress_load_count, c->stress_window, c->stress_window_count, weight);
  if (changed) { // the window's average becomes the loads carried
    bk_free(c->stress_loads);
    c->stress_loads = c->stress_window;
    c->stress_load_count = c->stress_window_count;
  } else {
    bk_free(c->stress_window);
  }
  c->stress_window = NULL;
  c->stress_window_count = 0;
  c->stress_window_calls = 0;
  return changed;
}

double* rt_stress_node_loads(const rt_cluster* c) {
  if (!c->stress_load_count) return NULL;
  double* out = bk_calloc(6u * (size_t)c->leaf_count, sizeof(double));
  for (uint32_t i = 0, k = 0; i < c->leaf_count && k < c->stress_load_count; ++i) {
    while (k < c->stress_load_count && c->stress_loads[k].leaf < c->leaves[i])
      k++; // a leaf that has left the cluster since
    if (k < c->stress_load_count && c->stress_loads[k].leaf == c->leaves[i]) {
      memcpy(&out[6 * i], c->stress_loads[k].force, sizeof(double) * 3);
      memcpy(&out[6 * i + 3], c->stress_loads[k].torque, sizeof(double) * 3);
    }
  }
  return out;
}
