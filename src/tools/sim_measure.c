// breakables sim's measures of a run (see sim_measure.h).
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sim_measure.h"
#include "tree_export.h"

// The patterns the objects' trees were made with (a tree loaded from a file
// keeps its own): JSON members "pattern" (the one they share, else "mixed")
// and "patterns" (one per object), or a line of text.
void sim_print_patterns(const loaded_scene* s, bool json) {
  const char* shared = s->tree_count ? bk_fracture_pattern_name(s->trees[0].desc.pattern) : "none";
  for (uint32_t i = 1; i < s->tree_count; ++i)
    if (s->trees[i].desc.pattern != s->trees[0].desc.pattern) shared = "mixed";
  if (json) {
    printf("\"pattern\": \"%s\", \"patterns\": [", shared);
    for (uint32_t i = 0; i < s->tree_count; ++i)
      printf("%s\"%s\"", i ? ", " : "", bk_fracture_pattern_name(s->trees[i].desc.pattern));
    printf("]");
  } else if (strcmp(shared, "mixed") != 0) {
    printf("  pattern %s\n", shared);
  } else {
    printf("  patterns:");
    for (uint32_t i = 0; i < s->tree_count; ++i)
      printf("%s %s %s", i ? "," : "", s->scene->objects[i].mesh,
             bk_fracture_pattern_name(s->trees[i].desc.pattern));
    printf("\n");
  }
}

// Fragments of one copy of the scene (the copies have the same trees).
uint32_t sim_fragments_of(const loaded_scene* s) {
  uint32_t total = 0;
  for (uint32_t i = 0; i < s->tree_count; ++i)
    total += s->trees[i].leaf_count;
  return total;
}

// Every fragment's height now, object after object, copy after copy.
double* sim_heights_of(const loaded_scene* s) {
  uint32_t total = sim_fragments_of(s), copies = s->copies ? s->copies : 1;
  double* heights = bk_alloc(sizeof(double) * (total ? total * copies : 1u));
  bk_vec3* centroids = bk_alloc(sizeof(bk_vec3) * (total ? total : 1u));
  uint32_t at = 0;
  for (uint32_t c = 0; c < copies; ++c) {
    for (uint32_t i = 0; i < s->tree_count; ++i) {
      uint32_t n = bk_world_fragment_centroids(s->world, loaded_scene_id(s, c, i), centroids, total);
      // A loaded state's tree may have grown already (--load-state): its
      // first leaves stand for the scene's (the heights of refined ones are
      // then their first piece's).
      if (n > s->trees[i].leaf_count) n = s->trees[i].leaf_count;
      for (uint32_t l = 0; l < n; ++l)
        heights[at + l] = centroids[l].y;
      at += s->trees[i].leaf_count;
    }
  }
  free(centroids);
  return heights;
}

// How each breakable's tree frame was turned at the start, object after
// object, copy after copy (every body of it stood where it was placed).
bk_quat* sim_start_rotations(const loaded_scene* s) {
  uint32_t copies = s->copies ? s->copies : 1, count = s->tree_count * copies;
  bk_quat* rotations = bk_alloc(sizeof(bk_quat) * (count + 1u));
  for (uint32_t k = 0; k < count; ++k) {
    bk_breakable_id id = loaded_scene_id(s, k / s->tree_count, k % s->tree_count);
    rotations[k] = bk_quat_identity();
    bk_body_view view = {0};
    for (uint32_t b = 0; bk_world_body_view(s->world, b, &view); ++b)
      if (view.breakable.index == id.index) {
        rotations[k] = view.tree_to_world.rotation;
        break;
      }
  }
  return rotations;
}

// Fragments whose centroid ended more than 0.5 m below where it started.
// A refined fragment's pieces (its tree grew) started where they were in
// it: its start height, plus how far each piece's centroid lies above its
// own in the tree frame as it was turned then.
uint32_t sim_fragments_fallen(const loaded_scene* s, const double* rest_heights, const bk_quat* rotations) {
  const bk_runtime* runtime = bk_world_runtime(s->world);
  uint32_t fallen = 0, at = 0, copies = s->copies ? s->copies : 1;
  for (uint32_t k = 0; k < s->tree_count * copies; ++k) {
    const bk_mesh_tree* first = &s->trees[k % s->tree_count];
    const bk_mesh_tree* tree =
        bk_runtime_breakable_tree(runtime, loaded_scene_id(s, k / s->tree_count, k % s->tree_count));
    if (!tree) tree = first;
    bk_vec3* centroids = bk_alloc(sizeof(bk_vec3) * (tree->leaf_count + 1u));
    uint32_t n = bk_world_fragment_centroids(
        s->world, loaded_scene_id(s, k / s->tree_count, k % s->tree_count), centroids, tree->leaf_count);
    for (uint32_t l = 0; l < n && l < tree->leaf_count; ++l) {
      double rest = 0.0;
      if (tree->leaf_count == first->leaf_count) {
        rest = rest_heights[at + l];
      } else {
        // New nodes are appended: the first ancestor among the first tree's
        // nodes is the fragment the piece was refined from.
        uint32_t node = tree->leaf_nodes[l];
        while (node >= first->node_count)
          node = tree->nodes[node].parent;
        uint32_t from = first->nodes[node].leaf_begin;
        bk_vec3 offset =
            bk_v3_sub(bk_mesh_tree_mass(tree, bk_mesh_tree_leaf(tree, l)->moments).centroid,
                      bk_mesh_tree_mass(first, bk_mesh_tree_leaf(first, from)->moments).centroid);
        rest = rest_heights[at + from] + bk_quat_rotate(rotations[k], offset).y;
      }
      fallen += centroids[l].y < rest - 0.5; // NaN (gone) counts as not fallen
    }
    bk_free(centroids);
    at += first->leaf_count;
  }
  return fallen;
}

// Fragments of every object's tree as it is now (refinement grows them).
uint32_t sim_leaves_now(const loaded_scene* s) {
  uint32_t total = 0, copies = s->copies ? s->copies : 1;
  for (uint32_t c = 0; c < copies; ++c)
    for (uint32_t i = 0; i < s->tree_count; ++i) {
      const bk_mesh_tree* tree =
          bk_runtime_breakable_tree(bk_world_runtime(s->world), loaded_scene_id(s, c, i));
      total += tree ? tree->leaf_count : 0;
    }
  return total;
}

// The first object's tree as it stands now, to the files asked for; false
// (one line printed) at the first that cannot be written.
bool sim_export_first_tree(const loaded_scene* s, const char* obj_path, const char* gltf_path) {
  const bk_mesh_tree* tree = bk_runtime_breakable_tree(bk_world_runtime(s->world), loaded_scene_id(s, 0, 0));
  bk_error err = {0};
  bool ok = tree != NULL;
  if (ok && obj_path) ok = tree_export_obj(tree, obj_path, &err);
  if (ok && gltf_path) {
    // As fracture writes a tree with its default options, its one material
    // a plain surface (a built-in mesh's).
    app_export_materials materials = {0};
    app_export_materials_from_import(NULL, s->scene->objects[0].mesh, &materials);
    bk_gltf_def gltf = bk_default_gltf_def();
    gltf.materials = materials.list;
    gltf.material_count = materials.count;
    ok = bk_mesh_tree_save_gltf(tree, gltf_path, &gltf, &err);
    app_export_materials_free(&materials);
  }
  if (!ok) fprintf(stderr, "breakables sim: %s\n", err.message[0] ? err.message : "no object to export");
  return ok;
}
