// Refinement: a leaf of a tree fractured again and spliced in as its
// subtree, so a tree grows where it was hit. The pieces are a tree of their
// own (any pattern) whose moments are taken about the grown tree's origin;
// the splice appends their nodes, renumbers the leaves so every subtree still
// covers a contiguous range, and divides the leaf's bonds with its
// neighbours among the pieces that touch each bond's face.
#include <string.h>

#include "mesh_contact.h"
#include "tree_frame.h"

// A node's moments as the tree's build takes them: in the tree's frame,
// then scaled exactly to world units about its origin.
static bk_moments frame_moments(bk_tree_frame frame, const bk_mesh* mesh) {
  bk_mesh local = *mesh;
  local.positions = bk_alloc(sizeof(bk_vec3) * (mesh->position_count + 1u));
  memcpy(local.positions, mesh->positions, sizeof(bk_vec3) * mesh->position_count);
  bk_tree_frame_to_local(frame, &local);
  bk_moments m = bk_mesh_moments(&local);
  bk_free(local.positions);
  return bk_tree_frame_moments_to_world(frame, m);
}

bool bk_mesh_fracture_leaf(const bk_mesh* mesh, bk_aabb tree_bounds, const bk_fracture_def* def,
                           bk_mesh_tree* out, bk_error* err) {
  memset(out, 0, sizeof *out);
  if (!mesh || !def) return bk_error_set(err, "refine: mesh or def is NULL");
  if (!bk_v3_is_finite(tree_bounds.min) || !bk_v3_is_finite(tree_bounds.max) ||
      !(tree_bounds.max.x >= tree_bounds.min.x && tree_bounds.max.y >= tree_bounds.min.y &&
        tree_bounds.max.z >= tree_bounds.min.z))
    return bk_error_set(err, "refine: tree_bounds must be a finite, non-empty box");
  if (!bk_mesh_tree_build(mesh, def, out, err)) return false;
  bk_tree_frame frame = bk_tree_frame_of(tree_bounds);
  for (uint32_t i = 0; i < out->node_count; ++i)
    out->nodes[i].moments = frame_moments(frame, &out->nodes[i].mesh);
  return true;
}

// One divided bond: its part per piece (area 0: that piece does not touch it).
typedef struct divided {
  uint32_t bond, neighbour;  // the old bond, the leaf on its other side (old numbering)
  bk_contact_measure* parts; // per piece
  uint32_t part_count;       // pieces with area > 0
} divided;

// The parts measured ahead for this bond's neighbour (its node, its bond's
// area unchanged since), or NULL.
static const bk_contact_measure* measured(const bk_piece_contacts* contacts, uint32_t node, double area,
                                          uint32_t pieces) {
  for (uint32_t i = 0; contacts && i < contacts->neighbour_count; ++i)
    if (contacts->nodes[i] == node && contacts->bond_areas[i] == area && contacts->piece_count == pieces)
      return &contacts->parts[(size_t)i * pieces];
  return NULL;
}

// How each piece touches the face of each of the leaf's bonds: measured
// ahead (`contacts`), or here.
static bool divide_bonds(const bk_mesh_tree* tree, uint32_t leaf, const bk_mesh_tree* pieces,
                         const bk_piece_contacts* contacts, divided** out, uint32_t* out_count,
                         bk_error* err) {
  const bk_mesh_tree_node* node = bk_mesh_tree_leaf(tree, leaf);
  uint32_t count = 0;
  for (uint32_t j = 0; j < tree->bond_count; ++j)
    count += tree->bonds[j].leaf_a == leaf || tree->bonds[j].leaf_b == leaf;
  divided* list = bk_calloc(count + 1u, sizeof(divided));
  bk_piece_faces faces = {0};
  uint32_t at = 0;
  bool ok = true;
  for (uint32_t j = 0; j < tree->bond_count && ok; ++j) {
    const bk_bond* b = &tree->bonds[j];
    if (b->leaf_a != leaf && b->leaf_b != leaf) continue;
    divided* d = &list[at++];
    d->bond = j;
    d->neighbour = b->leaf_a == leaf ? b->leaf_b : b->leaf_a;
    d->parts = bk_calloc(pieces->leaf_count, sizeof(bk_contact_measure));
    const bk_mesh_tree_node* neighbour = bk_mesh_tree_leaf(tree, d->neighbour);
    const bk_contact_measure* ahead =
        measured(contacts, tree->leaf_nodes[d->neighbour], b->area, pieces->leaf_count);
    if (ahead) {
      memcpy(d->parts, ahead, sizeof(bk_contact_measure) * pieces->leaf_count);
    } else {
      if (!faces.sides) bk_piece_faces_make(&node->mesh, tree->nodes[0].bounds, pieces, &faces);
      bk_piece_faces_measure(&faces, &neighbour->mesh, b->area, d->parts);
    }
    for (uint32_t p = 0; p < pieces->leaf_count; ++p)
      d->part_count += d->parts[p].area > 0.0;
    if (!d->part_count)
      ok = bk_error_set(err, "refine: bond %u of leaf %u (with leaf %u) touches none of its pieces", j, leaf,
                        d->neighbour);
  }
  bk_piece_faces_free(&faces);
  *out = list;
  *out_count = at;
  return ok;
}

static void free_divided(divided* list, uint32_t count) {
  for (uint32_t i = 0; i < count; ++i)
    bk_free(list[i].parts);
  bk_free(list);
}

// Leaf numbers after the splice: the leaf's pieces take its place.
static inline uint32_t moved_leaf(uint32_t l, uint32_t leaf, uint32_t grow) {
  return l > leaf ? l + grow : l;
}

static bk_bond part_bond(const bk_bond* old, const divided* d, uint32_t piece, double total, uint32_t leaf,
                         uint32_t grow) {
  const bk_contact_measure* m = &d->parts[piece];
  uint32_t a = leaf + piece, b = moved_leaf(d->neighbour, leaf, grow);
  // m's normal points from the piece to the neighbour; a bond's from leaf_a.
  bk_vec3 normal = a < b ? m->normal : bk_v3_scale(m->normal, -1.0);
  if (!(bk_v3_length(normal) > 0.5)) normal = old->normal;
  return (bk_bond){.leaf_a = a < b ? a : b,
                   .leaf_b = a < b ? b : a,
                   .area = old->area * (m->area / total),
                   .centroid = m->centroid,
                   .normal = normal};
}

bool bk_mesh_tree_splice(bk_mesh_tree* tree, uint32_t leaf, bk_mesh_tree* pieces, bk_splice_info* info,
                         bk_error* err) {
  return bk_mesh_tree_splice_measured(tree, leaf, pieces, NULL, info, err);
}

bool bk_mesh_tree_splice_measured(bk_mesh_tree* tree, uint32_t leaf, bk_mesh_tree* pieces,
                                  const bk_piece_contacts* contacts, bk_splice_info* info, bk_error* err) {
  if (info) memset(info, 0, sizeof *info);
  if (!tree || !pieces || leaf >= tree->leaf_count)
    return bk_error_set(err, "refine: leaf %u is not a leaf of the tree", leaf);
  if (pieces->leaf_count < 2 || pieces->node_count < 3 || pieces->nodes[0].child_count == 0)
    return bk_error_set(err, "refine: the pieces of leaf %u are %u leaves (at least 2 needed)", leaf,
                        pieces->leaf_count);
  uint32_t node = tree->leaf_nodes[leaf];
  double volume = tree->nodes[node].moments.v, sum = 0.0;
  for (uint32_t p = 0; p < pieces->leaf_count; ++p)
    sum += bk_mesh_tree_leaf(pieces, p)->moments.v;
  if (!(fabs(sum - volume) <= 1e-9 * fabs(volume)))
    return bk_error_set(err, "refine: the pieces of leaf %u have volume %.17g, the leaf %.17g", leaf, sum,
                        volume);
  divided* list = NULL;
  uint32_t list_count = 0;
  if (!divide_bonds(tree, leaf, pieces, contacts, &list, &list_count, err)) {
    free_divided(list, list_count);
    return false;
  }

  // Nodes: the pieces' nodes but their root appended; the leaf is their root.
  uint32_t k = pieces->leaf_count, grow = k - 1;
  uint32_t base = tree->node_count, added = pieces->node_count - 1;
  tree->nodes = bk_realloc(tree->nodes, sizeof(bk_mesh_tree_node) * (base + added));
  for (uint32_t i = 0; i < base; ++i) {
    bk_mesh_tree_node* n = &tree->nodes[i];
    if (n->leaf_begin > leaf) n->leaf_begin += grow;
    if (n->leaf_end > leaf) n->leaf_end += grow;
  }
  const bk_mesh_tree_node* root = &pieces->nodes[0];
  bk_mesh_tree_node* at = &tree->nodes[node];
  uint32_t depth = at->depth;
  at->first_child = base + root->first_child - 1;
  at->child_count = root->child_count;
  at->plane = root->plane;
  for (uint32_t j = 1; j < pieces->node_count; ++j) {
    bk_mesh_tree_node n = pieces->nodes[j];
    n.parent = n.parent == 0 ? node : base + n.parent - 1;
    if (n.child_count) n.first_child = base + n.first_child - 1;
    n.leaf_begin += leaf;
    n.leaf_end += leaf;
    n.depth += depth;
    if (n.depth > tree->max_depth) tree->max_depth = n.depth;
    tree->nodes[base + j - 1] = n;
    memset(&pieces->nodes[j].mesh, 0, sizeof(bk_mesh)); // moved
  }
  tree->node_count = base + added;
  // Leaves: the pieces' nodes in the leaf's place.
  uint32_t leaves = tree->leaf_count + grow;
  uint32_t* leaf_nodes = bk_alloc(sizeof(uint32_t) * leaves);
  memcpy(leaf_nodes, tree->leaf_nodes, sizeof(uint32_t) * leaf);
  for (uint32_t p = 0; p < k; ++p)
    leaf_nodes[leaf + p] = base + pieces->leaf_nodes[p] - 1;
  memcpy(leaf_nodes + leaf + k, tree->leaf_nodes + leaf + 1,
         sizeof(uint32_t) * (tree->leaf_count - leaf - 1));
  bk_free(tree->leaf_nodes);
  tree->leaf_nodes = leaf_nodes;
  tree->leaf_count = leaves;

  // Bonds: every old bond renumbered; a divided one's first part keeps its
  // index, its other parts and the pieces' own bonds are appended.
  uint32_t extra = pieces->bond_count;
  for (uint32_t i = 0; i < list_count; ++i)
    extra += list[i].part_count - 1;
  uint32_t old_bonds = tree->bond_count;
  tree->bonds = bk_realloc(tree->bonds, sizeof(bk_bond) * (old_bonds + extra + 1u));
  for (uint32_t j = 0; j < old_bonds; ++j) {
    bk_bond* b = &tree->bonds[j];
    b->leaf_a = moved_leaf(b->leaf_a, leaf, grow);
    b->leaf_b = moved_leaf(b->leaf_b, leaf, grow);
  }
  uint32_t next = old_bonds;
  for (uint32_t i = 0; i < list_count; ++i) {
    const divided* d = &list[i];
    bk_bond old = tree->bonds[d->bond];
    double total = 0.0;
    for (uint32_t p = 0; p < k; ++p)
      total += d->parts[p].area;
    bool first = true;
    for (uint32_t p = 0; p < k; ++p) {
      if (!(d->parts[p].area > 0.0)) continue;
      tree->bonds[first ? d->bond : next++] = part_bond(&old, d, p, total, leaf, grow);
      first = false;
    }
  }
  for (uint32_t j = 0; j < pieces->bond_count; ++j) {
    bk_bond b = pieces->bonds[j];
    b.leaf_a += leaf;
    b.leaf_b += leaf;
    tree->bonds[next++] = b;
  }
  tree->bond_count = next;
  if (info)
    *info = (bk_splice_info){.leaf = leaf,
                             .leaf_count = k,
                             .node = node,
                             .first_node = base,
                             .node_count = added,
                             .first_bond = old_bonds,
                             .bond_count = next - old_bonds,
                             .bonds_divided = list_count};
  free_divided(list, list_count);
  bk_mesh_tree_free(pieces);
  return true;
}
