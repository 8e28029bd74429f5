// Fuzzes the whole authoring path of `breakables fracture --mesh FILE.obj`:
// OBJ bytes -> mesh (holes filled as the CLI does) -> mesh tree of a few pieces.
//
// Input: the first byte chooses the number of pieces (an ASCII digit '2'..'8'
// means itself, any other byte b means 2 + b % 7), the rest is the OBJ text.
// So a corpus file reads as a digit line followed by an OBJ, and a finding
// replays on the command line with
//   tail -c +2 INPUT > x.obj && breakables fracture --mesh x.obj --pieces N
// (the seed is the CLI's default).
//
// The planes cut has noisy faces when bit 4 of the last byte is set:
//   ... breakables fracture --mesh x.obj --pieces N --noise A
// Every input is also cut by one cell pattern (Voronoi, clustered or radial,
// by the last byte; with noisy faces when its bit 3 is set), which must
// meet the same checks and make exactly the pieces asked for when it builds:
//   ... breakables fracture --mesh x.obj --pieces N --pattern P [--noise A]
//
// Meshes the reader, the hole filler or the build refuses are fine. When a
// tree is built it must be sound: every node closed, leaf volumes summing to
// the root's and every node's children to their parent's within 1e-9
// relative, valid bonds, and a recorded reason for every piece short of the
// number asked for.
#include <math.h>
#include <string.h>

#include "fuzz_util.h"

const char bk_fuzz_harness[] = "fuzz_fracture";

// Keeps each run to milliseconds: a few hundred triangles cut into 8 pieces.
enum { FUZZ_FRACTURE_MAX_BYTES = 4096 };
#define FUZZ_FRACTURE_REL_TOLERANCE 1e-9

static uint32_t pieces_of(uint8_t b) { return b >= '2' && b <= '8' ? (uint32_t)(b - '0') : 2u + b % 7u; }

// The same repair as bk_app_load_mesh: an open mesh whose edges are each used
// once per direction gets its holes filled; anything else goes to the build as is.
static bool repair_like_the_cli(bk_mesh* mesh) {
  bk_closure closure = bk_mesh_check_closure(mesh);
  if (!closure.open_edges || closure.overused_edges) return true;
  bk_error err = {{0}};
  return bk_mesh_fill_holes(mesh, &err) >= 0;
}

static void check_tree(const bk_mesh_tree* tree, uint32_t pieces, uint64_t seed) {
  bk_mesh_tree_stats st = bk_mesh_tree_measure(tree);
  if (st.open_nodes)
    bk_fuzz_fail("--pieces %u --seed %llu: %u of %u nodes are not closed", pieces, (unsigned long long)seed,
                 st.open_nodes, tree->node_count);
  double leaf_error = fabs(st.leaf_volume_sum - st.source_volume) / fabs(st.source_volume);
  if (!(leaf_error <= FUZZ_FRACTURE_REL_TOLERANCE))
    bk_fuzz_fail("--pieces %u --seed %llu: leaf volumes sum to %.17g, the source has %.17g (%.3g relative)",
                 pieces, (unsigned long long)seed, st.leaf_volume_sum, st.source_volume, leaf_error);
  if (!(st.max_child_rel_error <= FUZZ_FRACTURE_REL_TOLERANCE))
    bk_fuzz_fail("--pieces %u --seed %llu: children's volumes miss their parent's by %.3g relative", pieces,
                 (unsigned long long)seed, st.max_child_rel_error);
  bk_fuzz_check_bonds(tree, "built tree");
  // Fewer pieces than asked is allowed only with the reason recorded (the CLI reports it).
  if (tree->leaf_count < pieces && tree->shortfall.uncut == 0)
    bk_fuzz_fail("--pieces %u --seed %llu: made %u pieces and recorded no piece that could not be cut",
                 pieces, (unsigned long long)seed, tree->leaf_count);
}

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1 || size > FUZZ_FRACTURE_MAX_BYTES) return 0;
  bk_fracture_def desc = bk_default_fracture_def();
  desc.pieces = pieces_of(data[0]);
  bk_mesh mesh = {0};
  bk_error err = {{0}};
  if (!bk_obj_parse((const char*)data + 1, size - 1, "input.obj", &mesh, &err)) return 0;
  if (!repair_like_the_cli(&mesh)) {
    bk_mesh_free(&mesh);
    return 0;
  }
  // Noise as the editor sets it: 2% of the size, four waves per size.
  bk_aabb box = bk_mesh_bounds(&mesh);
  double size_of = bk_v3_length(bk_v3_sub(box.max, box.min));
  double amplitude = isfinite(0.02 * size_of) ? 0.02 * size_of : 0.0;
  double frequency = isfinite(4.0 / size_of) && 4.0 / size_of > 0.0 ? 4.0 / size_of : 1.0;
  uint8_t last = data[size - 1];
  if (last & 16) desc.noise_amplitude = amplitude, desc.noise_frequency = frequency;
  bk_mesh_tree tree = {0};
  if (bk_mesh_tree_build(&mesh, &desc, &tree, &err)) {
    check_tree(&tree, desc.pieces, desc.seed);
    bk_mesh_tree_free(&tree);
  }
  desc.pattern = (bk_fracture_pattern)(BK_PATTERN_VORONOI + last % 3);
  desc.noise_amplitude = 0.0;
  if (last & 8) desc.noise_amplitude = amplitude, desc.noise_frequency = frequency;
  desc.impact = mesh.position_count ? mesh.positions[0] : bk_v3(0, 0, 0);
  if (bk_mesh_tree_build(&mesh, &desc, &tree, &err)) {
    check_tree(&tree, desc.pieces, desc.seed);
    if (tree.leaf_count != desc.pieces)
      bk_fuzz_fail("--pattern %s --pieces %u: made %u pieces", bk_fracture_pattern_name(desc.pattern),
                   desc.pieces, tree.leaf_count);
    bk_mesh_tree_free(&tree);
  }
  bk_mesh_free(&mesh);
  return 0;
}
