// Noisy planes: the planes pattern with --noise. Each cut's cap is meshed at
// the noise's resolution and pushed along its normal; the tree must stay as
// exact as a flat one (the pieces asked for, every node closed, volumes
// adding up), its bonds must measure the rough faces the leaves share (not
// their flat shadows), and it must be the same for any thread count.
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bk_fracture.h"
#include "ensure.h"
#include "load_shape.h"
#include "tree_bytes.h"

static bk_fracture_def noisy_def(uint32_t pieces, double amplitude, double frequency) {
  bk_fracture_def d = bk_default_fracture_def();
  d.pattern = BK_PATTERN_PLANES;
  d.pieces = pieces;
  d.noise_amplitude = amplitude;
  d.noise_frequency = frequency;
  return d;
}

static bk_mesh_tree build(const bk_mesh* m, const bk_fracture_def* d) {
  bk_mesh_tree tree = {0};
  bk_error err = {0};
  ENSURE_MSG(bk_mesh_tree_build(m, d, &tree, &err), "%u pieces: %s", d->pieces, err.message);
  return tree;
}

static double triangle_area(const bk_mesh* m, uint32_t t, bk_vec3* normal) {
  bk_vec3 p0 = m->positions[bk_mesh_tri_position(m, t, 0)];
  bk_vec3 e = bk_v3_cross(bk_v3_sub(m->positions[bk_mesh_tri_position(m, t, 1)], p0),
                          bk_v3_sub(m->positions[bk_mesh_tri_position(m, t, 2)], p0));
  double length = bk_v3_length(e);
  if (normal) *normal = length > 0.0 ? bk_v3_scale(e, 1.0 / length) : e;
  return 0.5 * length;
}

// Cut faces of the leaves: their total area, how far the most tilted one
// leans from its cut's plane (1 - |cos|), and their mean area.
typedef struct cut_faces {
  double area, most_tilt, mean_area;
  uint32_t count;
} cut_faces;

static cut_faces measure_cut_faces(const bk_mesh_tree* t) {
  cut_faces f = {0};
  for (uint32_t l = 0; l < t->leaf_count; ++l) {
    const bk_mesh* m = &bk_mesh_tree_leaf(t, l)->mesh;
    for (uint32_t i = 0; i < m->triangle_count; ++i) {
      uint32_t tag = m->tags[i];
      if (!bk_material_is_interior(m->materials[i]) || tag == 0 || tag > t->node_count) continue;
      bk_vec3 normal = {0};
      double area = triangle_area(m, i, &normal);
      f.area += area;
      f.count++;
      if (area > 1e-12)
        f.most_tilt = fmax(f.most_tilt, 1.0 - fabs(bk_v3_dot(normal, t->nodes[tag - 1].plane.normal)));
    }
  }
  f.mean_area = f.count ? f.area / f.count : 0.0;
  return f;
}

static void ensure_exact(const bk_mesh_tree* t, const char* name, uint32_t pieces) {
  ENSURE_MSG(t->leaf_count == pieces, "%s: %u leaves for %u", name, t->leaf_count, pieces);
  bk_mesh_tree_stats st = bk_mesh_tree_measure(t);
  ENSURE_MSG(st.open_nodes == 0, "%s: %u nodes are not closed", name, st.open_nodes);
  ENSURE_MSG(fabs(st.leaf_volume_sum - st.source_volume) <= 1e-9 * st.source_volume, "%s: volume error %g",
             name, fabs(st.leaf_volume_sum - st.source_volume) / st.source_volume);
  ENSURE_MSG(st.max_child_rel_error <= 1e-9, "%s: child volume error %g", name, st.max_child_rel_error);
  ENSURE(st.min_leaf_volume > 0.0);
  ENSURE(t->bond_count >= t->leaf_count - 1);
}

// Every source shape: exact, closed, adding up; the cut faces bend, except
// the eggshell's: its cut faces are strips as narrow as the shell is thick,
// and the push tapers to nothing within a quarter of the distance to a
// face's border.
static void test_shapes(void) {
  static const char* const shapes[] = {"cube", "torus", "eggshell", "wall", "bunny"};
  for (uint32_t s = 0; s < sizeof shapes / sizeof shapes[0]; ++s) {
    bool thin = strcmp(shapes[s], "eggshell") == 0;
    bk_mesh m = load_shape(shapes[s]);
    bk_aabb box = bk_mesh_bounds(&m);
    double size = bk_v3_length(bk_v3_sub(box.max, box.min));
    bk_fracture_def d = noisy_def(150, 0.02 * size, 4.0 / size);
    bk_mesh_tree t = build(&m, &d);
    ensure_exact(&t, shapes[s], 150);
    cut_faces f = measure_cut_faces(&t);
    ENSURE_MSG(thin || f.most_tilt > 0.003, "%s: cut faces lean by at most %g", shapes[s], f.most_tilt);
    fprintf(stderr, "    %s: %u nodes, %u bonds, cut faces lean up to %.3f\n", shapes[s], t.node_count,
            t.bond_count, f.most_tilt);
    bk_mesh_tree_free(&t);
    bk_mesh_free(&m);
  }
}

// A bond is the area two leaves share: over all bonds that is every cut
// face once, so twice the bonds' area is the leaves' cut-face area. Flat
// shadows of rough faces would come out smaller. Bonds recomputed from the
// leaves' tags (as after loading a cache) are the same.
static void test_bonds_measure_rough_faces(void) {
  bk_mesh cube = load_shape("cube");
  for (int noisy = 0; noisy < 2; ++noisy) {
    bk_fracture_def d = noisy_def(96, noisy ? 0.04 : 0.0, 5.0);
    bk_mesh_tree t = build(&cube, &d);
    ensure_exact(&t, noisy ? "noisy cube" : "flat cube", 96);
    double bonded = 0.0;
    for (uint32_t b = 0; b < t.bond_count; ++b) {
      const bk_bond* bond = &t.bonds[b];
      bonded += bond->area;
      ENSURE_REL(bk_v3_length(bond->normal), 1.0, 1e-12);
      // The contact lies where both leaves are.
      for (int k = 0; k < 2; ++k) {
        bk_aabb box = bk_mesh_tree_leaf(&t, k ? bond->leaf_b : bond->leaf_a)->bounds;
        const double c[3] = {bond->centroid.x, bond->centroid.y, bond->centroid.z};
        const double lo[3] = {box.min.x, box.min.y, box.min.z}, hi[3] = {box.max.x, box.max.y, box.max.z};
        for (int a = 0; a < 3; ++a)
          ENSURE(c[a] >= lo[a] - 1e-9 && c[a] <= hi[a] + 1e-9);
      }
    }
    cut_faces f = measure_cut_faces(&t);
    ENSURE_MSG(fabs(2.0 * bonded - f.area) <= 1e-9 * f.area, "%s: bonds %.12g, cut faces %.12g / 2",
               noisy ? "noisy" : "flat", bonded, f.area);
    if (noisy)
      ENSURE_MSG(f.most_tilt > 0.02, "noisy cut faces lean by at most %g", f.most_tilt);
    else
      ENSURE_MSG(f.most_tilt < 1e-9, "flat cut faces lean by %g", f.most_tilt);
    uint32_t count = t.bond_count;
    bk_bond* built = malloc(sizeof(bk_bond) * count);
    memcpy(built, t.bonds, sizeof(bk_bond) * count);
    bk_mesh_tree_compute_bonds(&t);
    ENSURE(t.bond_count == count && memcmp(built, t.bonds, sizeof(bk_bond) * count) == 0);
    free(built);
    bk_mesh_tree_free(&t);
  }
  bk_mesh_free(&cube);
}

// The caps are meshed at the noise's resolution (about three points per
// wave), not finer: a cut face triangle covers a fair share of a grid cell,
// and a higher frequency means more, smaller triangles.
static void test_noise_resolution(void) {
  bk_mesh cube = load_shape("cube");
  uint32_t counts[2] = {0, 0};
  for (int k = 0; k < 2; ++k) {
    double frequency = k ? 8.0 : 4.0, cell = 1.0 / (3.0 * frequency);
    bk_fracture_def d = noisy_def(64, 0.03, frequency);
    bk_mesh_tree t = build(&cube, &d);
    cut_faces f = measure_cut_faces(&t);
    counts[k] = f.count;
    fprintf(stderr, "    frequency %g: %u cut-face triangles, mean area %.3f of a grid cell\n", frequency,
            f.count, f.mean_area / (cell * cell));
    ENSURE_MSG(f.mean_area > 0.15 * cell * cell, "cut faces %g of a cell", f.mean_area / (cell * cell));
    bk_mesh_tree_free(&t);
  }
  ENSURE_MSG(counts[1] > 2 * counts[0], "frequency 8: %u cut-face triangles, 4: %u", counts[1], counts[0]);
  bk_mesh_free(&cube);
}

// The same bytes on 1, 2 and 3 threads; another seed, another tree; the
// amplitude changes the pieces.
static void test_threads_and_seeds(void) {
  bk_mesh torus = load_shape("torus");
  bk_fracture_def d = noisy_def(300, 0.02, 6.0);
  d.threads = 1;
  bk_mesh_tree one = build(&torus, &d);
  ensure_exact(&one, "torus", 300);
  for (uint32_t threads = 2; threads <= 3; ++threads) {
    d.threads = threads;
    bk_mesh_tree many = build(&torus, &d);
    ENSURE_MSG(trees_same_bytes(&one, &many), "noisy torus: %u threads give another tree", threads);
    bk_mesh_tree_free(&many);
  }
  d.seed += 1;
  bk_mesh_tree other = build(&torus, &d);
  ENSURE(!trees_same_bytes(&one, &other));
  bk_mesh_tree_free(&other);
  d.seed -= 1;
  d.noise_amplitude = 0.01;
  bk_mesh_tree weaker = build(&torus, &d);
  ENSURE(!trees_same_bytes(&one, &weaker));
  bk_mesh_tree_free(&weaker);
  bk_mesh_tree_free(&one);
  bk_mesh_free(&torus);
}

// Brick cuts along its mortar: noise is refused, naming the field.
static void test_brick_refuses(void) {
  bk_fracture_def d = noisy_def(64, 0.02, 4.0);
  d.pattern = BK_PATTERN_BRICK;
  bk_error err = {0};
  ENSURE(!bk_fracture_def_validate(&d, &err) && strstr(err.message, "noise_amplitude") &&
         strstr(err.message, "brick"));
  d.pattern = BK_PATTERN_PLANES;
  ENSURE_MSG(bk_fracture_def_validate(&d, &err), "%s", err.message);
}

int main(void) {
  test_brick_refuses();
  test_bonds_measure_rough_faces();
  test_noise_resolution();
  test_threads_and_seeds();
  test_shapes();
  printf("test_noisy_planes: ok\n");
  return 0;
}
