// A fracture makes exactly the pieces asked for. A cut through a concave
// piece (a torus, a U) or through a piece made of separate shells gives more
// than two pieces; on the last split the tree may take fewer than that, so
// other cuts are tried, and when none makes few enough the nearest pieces
// are merged instead of leaving the tree with too many. Every tree must stay
// watertight at every node and keep the source's volume, and its leaves made
// of several shells must still give sound bonds and minimal node sets.
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <breakables/runtime.h>

#include "bk_fracture.h"
#include "ensure.h"
#include "plane_split.h"
#include "tree_bytes.h"

static const uint64_t seeds[] = {1, 77, 3000, 424242};
enum { SEED_COUNT = sizeof seeds / sizeof seeds[0] };

// Leaves made of more than one solid shell, over every tree checked: the
// merge must actually have been exercised.
static uint32_t multi_shell_leaves = 0;

static bk_mesh_tree build(const bk_mesh* m, uint32_t pieces, uint64_t seed) {
  bk_fracture_def desc = bk_default_fracture_def();
  desc.pieces = pieces;
  desc.seed = seed;
  bk_mesh_tree tree = {0};
  bk_error err = {0};
  ENSURE_MSG(bk_mesh_tree_build(m, &desc, &tree, &err), "%s", err.message);
  return tree;
}

// Solid shells of a mesh (cavities stay with their solid).
static uint32_t shell_count(const bk_mesh* m) {
  bk_mesh copy = {0};
  bk_mesh_copy(&copy, m);
  bk_mesh* shells = NULL;
  uint32_t count = bk_mesh_split_hulls(&copy, &shells);
  for (uint32_t i = 0; i < count; ++i)
    bk_mesh_free(&shells[i]);
  free(shells);
  return count;
}

// Bonds join two different leaves with a positive area and a unit normal;
// the minimal node set of all leaves is the root, of one leaf that leaf, of
// a subtree's leaves that subtree's node.
static void ensure_bonds_and_nodes(const bk_mesh_tree* tree, const char* name) {
  for (uint32_t b = 0; b < tree->bond_count; ++b) {
    const bk_bond* bond = &tree->bonds[b];
    ENSURE_MSG(bond->leaf_a < bond->leaf_b && bond->leaf_b < tree->leaf_count, "%s: bond %u joins %u and %u",
               name, b, bond->leaf_a, bond->leaf_b);
    ENSURE(bond->area > 0.0 && fabs(bk_v3_length(bond->normal) - 1.0) < 1e-9);
  }
  uint32_t* leaves = bk_alloc(sizeof(uint32_t) * tree->leaf_count);
  uint32_t* out = bk_alloc(sizeof(uint32_t) * tree->leaf_count);
  for (uint32_t i = 0; i < tree->node_count; ++i) {
    const bk_mesh_tree_node* n = &tree->nodes[i];
    uint32_t count = n->leaf_end - n->leaf_begin;
    for (uint32_t l = 0; l < count; ++l)
      leaves[l] = n->leaf_begin + l;
    ENSURE_MSG(bk_minimal_nodes(tree, leaves, count, out) == 1 && out[0] == i, "%s: node %u", name, i);
  }
  free(leaves);
  free(out);
}

// Exactly `pieces` leaves, every node closed, the children of every inner
// node and the leaves of the tree adding up to the source's volume, the
// tree passing the cache file's checks.
static void ensure_exact(const bk_mesh_tree* tree, const bk_mesh* source, uint32_t pieces, const char* name,
                         uint64_t seed) {
  ENSURE_MSG(tree->leaf_count == pieces, "%s, seed %llu: %u leaves for %u pieces", name,
             (unsigned long long)seed, tree->leaf_count, pieces);
  ENSURE(tree->shortfall.uncut == 0);
  bk_mesh_tree_stats st = bk_mesh_tree_measure(tree);
  ENSURE_MSG(st.open_nodes == 0, "%s: %u open nodes", name, st.open_nodes);
  ENSURE_REL(st.leaf_volume_sum, bk_mesh_volume(source), 1e-9);
  ENSURE(st.max_child_rel_error <= 1e-9);
  for (uint32_t l = 0; l < tree->leaf_count; ++l)
    if (shell_count(&bk_mesh_tree_leaf(tree, l)->mesh) > 1) multi_shell_leaves++;
  uint8_t* bytes = NULL;
  size_t size = 0;
  bk_error err = {0};
  ENSURE_MSG(bk_mesh_tree_save_memory(tree, name, &bytes, &size, &err), "%s", err.message);
  bk_mesh_tree loaded = {0};
  ENSURE_MSG(bk_mesh_tree_load_memory(bytes, size, name, &loaded, &err), "%s", err.message);
  ENSURE(loaded.leaf_count == tree->leaf_count && loaded.bond_count == tree->bond_count);
  bk_mesh_tree_free(&loaded);
  free(bytes);
  ensure_bonds_and_nodes(tree, name);
}

static void ensure_exact_range(const bk_mesh* source, uint32_t first, uint32_t last, const char* name) {
  for (uint32_t pieces = first; pieces <= last; ++pieces)
    for (int s = 0; s < SEED_COUNT; ++s) {
      bk_mesh_tree tree = build(source, pieces, seeds[s]);
      ensure_exact(&tree, source, pieces, name, seeds[s]);
      bk_mesh_tree_free(&tree);
    }
}

// An axis-aligned box from `lo` to `hi`.
static void box_mesh(bk_mesh* m, bk_vec3 lo, bk_vec3 hi) {
  memset(m, 0, sizeof *m);
  bk_shape_build(BK_SHAPE_CUBE, m);
  bk_aabb box = bk_mesh_bounds(m);
  for (uint32_t i = 0; i < m->position_count; ++i) {
    bk_vec3 t = bk_v3_sub(m->positions[i], box.min); // 0..1 per axis
    m->positions[i] =
        bk_v3(lo.x + t.x * (hi.x - lo.x), lo.y + t.y * (hi.y - lo.y), lo.z + t.z * (hi.z - lo.z));
  }
}

// Boxes of side 1 from the origin, each `step` on from the one before, as one source.
static void box_row(bk_mesh* m, uint32_t count, bk_vec3 step) {
  box_mesh(m, bk_v3(0, 0, 0), bk_v3(1, 1, 1));
  for (uint32_t i = 1; i < count; ++i) {
    bk_mesh other = {0};
    bk_vec3 lo = bk_v3_scale(step, (double)i);
    box_mesh(&other, lo, bk_v3_add(lo, bk_v3(1, 1, 1)));
    bk_mesh_append(m, &other);
    bk_mesh_free(&other);
  }
}

// Twice the signed area of triangle a b c (positive when counter-clockwise).
static double cross2(const double a[2], const double b[2], const double c[2]) {
  return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

// A simple polygon (counter-clockwise, at most 64 corners) extruded from
// z = 0 to z = 1; its faces triangulated by ear clipping.
static void extrude(bk_mesh* m, const double (*outline)[2], uint32_t n) {
  enum { MAX_CORNERS = 64 };
  ENSURE(n >= 3 && n <= MAX_CORNERS);
  memset(m, 0, sizeof *m);
  for (uint32_t z = 0; z < 2; ++z)
    for (uint32_t i = 0; i < n; ++i) {
      uint32_t p = bk_mesh_add_position(m, bk_v3(outline[i][0], outline[i][1], (double)z));
      bk_corner c = {.position = p};
      bk_mesh_add_corner(m, &c);
    }
  uint32_t left[MAX_CORNERS] = {0}, remaining = n;
  for (uint32_t i = 0; i < n; ++i)
    left[i] = i;
  while (remaining >= 3) {
    uint32_t ear = UINT32_MAX;
    for (uint32_t i = 0; i < remaining && ear == UINT32_MAX; ++i) {
      const double* a = outline[left[(i + remaining - 1) % remaining]];
      const double* b = outline[left[i]];
      const double* c = outline[left[(i + 1) % remaining]];
      if (!(cross2(a, b, c) > 0.0)) continue; // reflex or straight: no ear
      bool empty = true;
      for (uint32_t j = 0; j < remaining && empty; ++j) {
        const double* q = outline[left[j]];
        if (q == a || q == b || q == c) continue;
        empty = !(cross2(a, b, q) >= 0.0 && cross2(b, c, q) >= 0.0 && cross2(c, a, q) >= 0.0);
      }
      if (empty) ear = i;
    }
    ENSURE(ear != UINT32_MAX);
    uint32_t a = left[(ear + remaining - 1) % remaining], b = left[ear], c = left[(ear + 1) % remaining];
    bk_mesh_add_triangle(m, a, c, b, BK_MATERIAL_OUTER, 0);             // bottom, facing -z
    bk_mesh_add_triangle(m, n + a, n + b, n + c, BK_MATERIAL_OUTER, 0); // top, facing +z
    memmove(&left[ear], &left[ear + 1], sizeof(uint32_t) * (remaining - ear - 1));
    remaining--;
  }
  for (uint32_t i = 0; i < n; ++i) { // side quads face outwards along the counter-clockwise outline
    uint32_t j = (i + 1) % n;
    bk_mesh_add_triangle(m, i, j, n + j, BK_MATERIAL_OUTER, 0);
    bk_mesh_add_triangle(m, i, n + j, n + i, BK_MATERIAL_OUTER, 0);
  }
  ENSURE(bk_mesh_is_closed(m));
}

// A U, 3 x 3 with a 1 x 2 notch: a cut across both arms makes three pieces.
static void u_shape(bk_mesh* m) {
  static const double outline[8][2] = {{0, 0}, {3, 0}, {3, 3}, {2, 3}, {2, 1}, {1, 1}, {1, 3}, {0, 3}};
  extrude(m, outline, 8);
  ENSURE_REL(bk_mesh_volume(m), 7.0, 1e-12);
}

// A comb: a bar 1 high with `teeth` teeth 1 wide, 1 apart and 6 high. Its
// centroid lies among the teeth, so most cuts through it cross several
// teeth, and on a last split sometimes none of the tries makes few enough
// pieces (the torus and the U always find one that does).
static void comb_shape(bk_mesh* m, uint32_t teeth) {
  double outline[64][2] = {{0}};
  uint32_t n = 0;
  double width = 2.0 * teeth - 1.0, height = 7.0;
  outline[n][0] = 0, outline[n++][1] = 0;
  outline[n][0] = width, outline[n++][1] = 0;
  for (uint32_t i = teeth; i-- > 0;) { // along the top, right to left
    outline[n][0] = 2.0 * i + 1.0, outline[n++][1] = height;
    outline[n][0] = 2.0 * i, outline[n++][1] = height;
    if (i == 0) break;
    outline[n][0] = 2.0 * i, outline[n++][1] = 1.0;
    outline[n][0] = 2.0 * i - 1.0, outline[n++][1] = 1.0;
  }
  extrude(m, outline, n);
  ENSURE_REL(bk_mesh_volume(m), width + 6.0 * teeth, 1e-12);
}

static void test_torus(void) {
  bk_mesh torus = {0};
  bk_shape_build(BK_SHAPE_TORUS, &torus);
  ensure_exact_range(&torus, 1, 40, "torus");
  bk_mesh_free(&torus);
}

static void test_u(void) {
  bk_mesh u = {0};
  u_shape(&u);
  ensure_exact_range(&u, 1, 40, "U");
  bk_mesh_free(&u);
}

// On a comb the merge is needed, not only further tries.
static void test_comb(void) {
  bk_mesh comb = {0};
  comb_shape(&comb, 6);
  uint32_t before = multi_shell_leaves;
  ensure_exact_range(&comb, 1, 24, "comb");
  ENSURE_MSG(multi_shell_leaves > before, "no comb leaf was merged");
  bk_mesh_free(&comb);
}

// Separate shells that overlap nothing: the root is cut by a plane, which
// may leave several shells on each side.
static void test_separate_shells(void) {
  bk_mesh two = {0}, five = {0};
  box_row(&two, 2, bk_v3(5, 0, 0));
  ensure_exact_range(&two, 1, 12, "two cubes");
  box_row(&five, 5, bk_v3(3, 0, 0));
  ENSURE(shell_count(&five) == 5);
  ensure_exact_range(&five, 1, 24, "five cubes");
  // Three pieces of five cubes: at least one leaf holds several cubes, and
  // the same seed gives the same tree, byte for byte.
  uint32_t before = multi_shell_leaves;
  bk_mesh_tree tree = build(&five, 3, 3000), again = build(&five, 3, 3000);
  ensure_exact(&tree, &five, 3, "five cubes", 3000);
  ENSURE(multi_shell_leaves > before);
  ENSURE(trees_same_bytes(&tree, &again));
  bk_mesh_tree_free(&tree);
  bk_mesh_tree_free(&again);
  bk_mesh_free(&two);
  bk_mesh_free(&five);
}

// Overlapping shells: the root's children are the shells (no plane cuts
// them together), so five of them with three pieces asked for are merged.
static void test_overlapping_shells(void) {
  bk_mesh chain = {0};
  // Each cube overlaps the next (offset in y and z too: coincident faces would only touch).
  box_row(&chain, 5, bk_v3(0.5, 0.1, 0.13));
  bk_mesh* parts = NULL;
  bk_fracture_overlap overlap = {0};
  uint32_t part_count = bk_mesh_split_overlapping_shells(&chain, &parts, &overlap);
  ENSURE_MSG(part_count == 5 && overlap.shells == 5, "%u parts, %u shells", part_count, overlap.shells);
  for (uint32_t i = 0; i < part_count; ++i)
    bk_mesh_free(&parts[i]);
  free(parts);
  ensure_exact_range(&chain, 1, 16, "five overlapping cubes");
  for (uint32_t pieces = 2; pieces <= 5; ++pieces) {
    bk_mesh_tree tree = build(&chain, pieces, 3000);
    ENSURE_MSG(tree.nodes[0].child_count == pieces, "%u children for %u pieces", tree.nodes[0].child_count,
               pieces);
    ENSURE(tree.overlap.pairs >= 4); // still reported
    // No cut made the root's children, so no bond joins them.
    ENSURE(tree.bond_count == 0);
    bk_mesh_tree_free(&tree);
  }
  bk_mesh_free(&chain);
}

// Tags the triangles of a mesh that lie in the plane y = `y` (a cap of cut `tag`).
static void tag_face_y(bk_mesh* m, double y, uint32_t tag) {
  for (uint32_t t = 0; t < m->triangle_count; ++t) {
    bool on = true;
    for (uint32_t k = 0; k < 3; ++k)
      on = on && m->positions[bk_mesh_tri_position(m, t, k)].y == y;
    if (on) m->tags[t] = tag;
  }
}

// The merge itself: the smallest piece joins its nearest on its side of the
// cut; a piece alone on its side joins one across the cut whose caps meet
// its own before a nearer one whose caps do not.
static void test_merge_order(void) {
  // Below the cut: cubes at x = 0, 3 and a small one at x = 7; above: a larger one at x = 20.
  bk_mesh pieces[4] = {{0}};
  box_mesh(&pieces[0], bk_v3(0, 0, 0), bk_v3(1, 1, 1));
  box_mesh(&pieces[1], bk_v3(3, 0, 0), bk_v3(4, 1, 1));
  box_mesh(&pieces[2], bk_v3(7, 0, 0), bk_v3(7.5, 0.5, 0.5));
  box_mesh(&pieces[3], bk_v3(20, 0, 0), bk_v3(21.2, 1.2, 1.2));
  bk_moments moments[4];
  for (int i = 0; i < 4; ++i)
    moments[i] = bk_mesh_moments(&pieces[i]);
  uint32_t count = bk_merge_pieces(pieces, moments, 4, 3, 0, 3);
  ENSURE(count == 3);
  // The small cube joined the cube at x = 3 (nearest on its side), not the
  // one at x = 20 above the cut.
  ENSURE(pieces[1].triangle_count == 24 && pieces[2].triangle_count == 12);
  ENSURE_REL(moments[1].v, 1.125, 1e-15);
  ENSURE(bk_mesh_is_closed(&pieces[1]));
  // Down to two: the cube at x = 0, the smallest, joins x = 3 below the cut.
  count = bk_merge_pieces(pieces, moments, count, 2, 0, 2);
  ENSURE(count == 2 && pieces[0].triangle_count == 36 && pieces[1].triangle_count == 12);
  ENSURE_REL(moments[0].v, 2.125, 1e-15);
  // Down to one: across the cut, as there is nothing else.
  count = bk_merge_pieces(pieces, moments, count, 1, 0, 1);
  ENSURE(count == 1 && pieces[0].triangle_count == 48 && bk_mesh_is_closed(&pieces[0]));
  ENSURE_REL(moments[0].v, 2.125 + 1.2 * 1.2 * 1.2, 1e-15);
  bk_mesh_free(&pieces[0]);

  // Cut 5 at y = 1: a small cube below, alone on its side; above it a large
  // cube whose cap meets the small one's, and a nearer cube whose cap does not.
  box_mesh(&pieces[0], bk_v3(0, 0.5, 0), bk_v3(0.5, 1, 0.5));
  box_mesh(&pieces[1], bk_v3(-1.1, 1, 0), bk_v3(-0.1, 2, 1));
  box_mesh(&pieces[2], bk_v3(0, 1, 0), bk_v3(4, 5, 4));
  for (int i = 0; i < 3; ++i) {
    tag_face_y(&pieces[i], 1.0, 5);
    moments[i] = bk_mesh_moments(&pieces[i]);
  }
  count = bk_merge_pieces(pieces, moments, 3, 1, 5, 2);
  ENSURE(count == 2 && pieces[0].triangle_count == 12 && pieces[1].triangle_count == 24);
  ENSURE_REL(moments[1].v, 64.125, 1e-15);
  bk_mesh_free(&pieces[0]);
  bk_mesh_free(&pieces[1]);
}

static bool same_pieces(const bk_plane_split* a, const bk_plane_split* b) {
  if (a->count != b->count || memcmp(&a->plane, &b->plane, sizeof a->plane) != 0) return false;
  for (uint32_t i = 0; i < a->count; ++i) {
    const bk_mesh *x = &a->pieces[i], *y = &b->pieces[i];
    if (x->position_count != y->position_count || x->triangle_count != y->triangle_count ||
        memcmp(x->positions, y->positions, sizeof(bk_vec3) * x->position_count) != 0 ||
        memcmp(x->indices, y->indices, sizeof(uint32_t) * 3 * x->triangle_count) != 0)
      return false;
  }
  return true;
}

// The threaded build splits leaves ahead with room for the pieces the tree
// could take then, and keeps such a split when its pieces fit what is left
// when it is taken (else makes it again). That is sound only if a split made
// with room for more, when it fits, is the split made with less room:
// checked on a comb, whose cuts often cross several teeth, for several
// nodes and seeds, with every room from 2 to 5.
static void test_split_room(void) {
  bk_mesh comb = {0};
  comb_shape(&comb, 6);
  bk_tree_frame frame = {0};
  bk_mesh local = {0};
  bk_error err = {0};
  ENSURE_MSG(bk_tree_frame_local_source(&comb, &frame, &local, &err), "%s", err.message);
  bk_label_planar_faces(&local);
  bk_mesh_tree_node node = {
      .mesh = local, .bounds = bk_mesh_bounds(&local), .moments = bk_mesh_moments(&local)};
  bk_plane_splitter* splitter = bk_plane_splitter_create();
  uint32_t fitted = 0, made_again = 0;
  for (uint64_t seed = 1; seed <= 12; ++seed)
    for (uint32_t index = 0; index < 3; ++index) {
      bk_fracture_def desc = bk_default_fracture_def();
      desc.seed = seed;
      bk_plane_split_context ctx = {&desc, &frame, NULL};
      bk_plane_split roomy = {0};
      bk_plane_split_node(splitter, &ctx, &node, index, UINT32_MAX, &roomy);
      ENSURE(roomy.count >= 2);
      for (uint32_t room = 2; room <= 5; ++room) {
        bk_plane_split tight = {0};
        bk_plane_split_node(splitter, &ctx, &node, index, room, &tight);
        ENSURE(tight.count >= 2 && tight.count <= room);
        if (roomy.count <= room) {
          ENSURE_MSG(same_pieces(&roomy, &tight), "seed %llu node %u room %u: another split",
                     (unsigned long long)seed, index, room);
          fitted++;
        } else {
          made_again++;
        }
        bk_plane_split_free(&tight);
      }
      bk_plane_split_free(&roomy);
    }
  ENSURE_MSG(fitted > 0 && made_again > 0, "%u fitted, %u made again: both cases must occur", fitted,
             made_again);
  bk_plane_splitter_destroy(splitter);
  bk_mesh_free(&local);
  bk_mesh_free(&comb);
}

int main(void) {
  RUN(test_merge_order);
  RUN(test_torus);
  RUN(test_u);
  RUN(test_comb);
  RUN(test_separate_shells);
  RUN(test_overlapping_shells);
  RUN(test_split_room);
  ENSURE_MSG(multi_shell_leaves > 0, "no leaf was made of several shells");
  fprintf(stderr, "  %u leaves made of several shells\n", multi_shell_leaves);
  puts("test_piece_count: ok");
  return 0;
}
