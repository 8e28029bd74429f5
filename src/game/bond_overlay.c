// The bond overlays of the game (B, V; --overlay bonds, stress): each body's
// intact bonds as lines, coloured by their hit points or their stress.
#include "bond_overlay.h"
#include "interpolate.h"

// Green through yellow (half way) to red as t goes from 0 to 1.
static void ramp_color(double t, float out[4]) {
  float x = (float)fmin(fmax(t, 0.0), 1.0);
  out[0] = fminf(1.0f, 2.0f * x), out[1] = fminf(1.0f, 2.0f * (1.0f - x)), out[2] = 0.1f, out[3] = 0.9f;
}

// The intact bonds inside each body, as lines between the centroids of their
// fragments: coloured by the hit points they have left, or by the stress
// they carried at their cluster's last solve over its limit (grey where
// there is none: a moving cluster, or stress turned off). Stresses span
// decades (a standing structure's bonds mostly carry 1% to 10% of their
// limits), so their colour goes by decades: green up to 1%, yellow at 10%,
// red at the limit.
void game_draw_bonds(app_game* g, double alpha, bool by_stress) {
  bk_world* w = g->scene.world;
  const bk_runtime* rt = bk_world_runtime(w);
  bool solving = bk_world_stress(w);
  uint32_t bodies = bk_world_body_count(w);
  for (uint32_t i = 0; i < bodies; ++i) {
    bk_body_view v = {0};
    if (!bk_world_body_view(w, i, &v) || v.leaf_count < 2) continue;
    bk_transform model = lerp_transform(v.tree_to_world_previous, v.tree_to_world, alpha);
    for (uint32_t b = 0; b < v.tree->bond_count; ++b) {
      const bk_bond* bond = &v.tree->bonds[b];
      // Leaves are ascending: a bond outside their range is another body's.
      if (bond->leaf_a < v.leaves[0] || bond->leaf_a > v.leaves[v.leaf_count - 1]) continue;
      double initial = 0.0, left = bk_world_bond_health(w, v.breakable, b, &initial);
      if (left <= 0.0 || !bk_cluster_equal(bk_runtime_leaf_cluster(rt, v.breakable, bond->leaf_a), v.cluster))
        continue;
      float color[4] = {0.55f, 0.55f, 0.6f, 0.6f};
      bk_bond_stress stress = {0};
      if (!by_stress)
        ramp_color(1.0 - left / initial, color);
      else if (solving && bk_runtime_bond_stress(rt, v.breakable, b, &stress))
        ramp_color(1.0 + 0.5 * log10(fmax(stress.ratio, 0.01)), color); // decades: 1%, 10%, 100%
      bk_vec3 a = bk_mesh_tree_mass(v.tree, bk_mesh_tree_leaf(v.tree, bond->leaf_a)->moments).centroid;
      bk_vec3 c = bk_mesh_tree_mass(v.tree, bk_mesh_tree_leaf(v.tree, bond->leaf_b)->moments).centroid;
      renderer_draw_line(g->renderer, bk_transform_point(model, a), bk_transform_point(model, c), color);
    }
  }
}
