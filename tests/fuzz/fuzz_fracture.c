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
// A third cut is the brick pattern or, when bit 5 of the last byte is set,
// the cut-out pattern. Brick: bricks of a half, a third, a quarter or a
// fifth of the source's width L and height H (by the second-to-last byte b:
// L / (2 + b % 4), H / (2 + b / 4 % 4)) from its bounds' low corner, courses
// shifted by (last byte >> 6) / 4 of a brick:
//   ... breakables fracture --mesh x.obj --pieces N --pattern brick
//       --brick-size L,H,0 --brick-origin X,Y,Z --brick-offset F
// Cut-out: a map of W x H pixels, W = 2 + b % 7 and H = 2 + b / 7 % 7, made
// of the W x H bytes before b (a line where a byte is odd; an OBJ comment
// line can carry them without changing the mesh), projected along axis
// (last byte >> 6) % 3 (--cutout MAP.png --cutout-axis x|y|z). Brick must make at
// most the pieces asked for; cut-out at most one per pixel of its map (its
// samples).
//
// Meshes the reader, the hole filler or the build refuses are fine. When a
// tree is built it must be sound: every node closed, leaf volumes summing to
// the root's and every node's children to their parent's within 1e-9
// relative, valid bonds, and a recorded reason for every piece short of the
// number asked for (cut-out asks for none: a region no sample falls in
// makes no piece).
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "fuzz_util.h"

const char bk_fuzz_harness[] = "fuzz_fracture";

// Keeps each run to milliseconds: a few hundred triangles cut into 8 pieces.
enum { FUZZ_FRACTURE_MAX_BYTES = 4096 };
#define FUZZ_FRACTURE_REL_TOLERANCE 1e-9

static uint32_t pieces_of(uint8_t b) { return b >= '2' && b <= '8' ? (uint32_t)(b - '0') : 2u + b % 7u; }

// The same repair as app_load_mesh: an open mesh whose edges are each used
// once per direction gets its holes filled; anything else goes to the build as is.
static bool repair_like_the_cli(bk_mesh* mesh) {
  bk_closure closure = bk_mesh_check_closure(mesh);
  if (!closure.open_edges || closure.overused_edges) return true;
  bk_error err = {{0}};
  return bk_mesh_fill_holes(mesh, &err) >= 0;
}

// `pieces`: the count asked for, or 0 when the pattern asks for none.
static void check_tree(const bk_mesh_tree* tree, uint32_t pieces, uint64_t seed,
                       bk_fracture_pattern pattern) {
  const char* name = bk_fracture_pattern_name(pattern);
  bk_mesh_tree_stats st = bk_mesh_tree_measure(tree);
  if (st.open_nodes)
    bk_fuzz_fail("--pattern %s --pieces %u --seed %llu: %u of %u nodes are not closed", name, pieces,
                 (unsigned long long)seed, st.open_nodes, tree->node_count);
  double leaf_error = fabs(st.leaf_volume_sum - st.source_volume) / fabs(st.source_volume);
  if (!(leaf_error <= FUZZ_FRACTURE_REL_TOLERANCE))
    bk_fuzz_fail("--pattern %s --pieces %u --seed %llu: leaf volumes sum to %.17g, the source has %.17g "
                 "(%.3g relative)",
                 name, pieces, (unsigned long long)seed, st.leaf_volume_sum, st.source_volume, leaf_error);
  if (!(st.max_child_rel_error <= FUZZ_FRACTURE_REL_TOLERANCE))
    bk_fuzz_fail(
        "--pattern %s --pieces %u --seed %llu: children's volumes miss their parent's by %.3g relative", name,
        pieces, (unsigned long long)seed, st.max_child_rel_error);
  char what[64] = {0};
  snprintf(what, sizeof what, "--pattern %s --pieces %u", name, pieces);
  bk_fuzz_check_bonds(tree, what);
  // Fewer pieces than asked is allowed only with the reason recorded (the CLI reports it).
  if (tree->leaf_count < pieces && tree->shortfall.uncut == 0 && tree->shortfall.cells_joined == 0)
    bk_fuzz_fail(
        "--pattern %s --pieces %u --seed %llu: made %u pieces and recorded no piece that could not be cut",
        name, pieces, (unsigned long long)seed, tree->leaf_count);
}

// A build may refuse its input, but never for what it made itself: the
// pieces it made failing the tree's own check is a defect of the builder
// (the cell patterns refuse a source whose surface crosses itself where a
// cell's piece is no solid with a message of their own, which is allowed).
static bool build(const bk_mesh* mesh, const bk_fracture_def* desc, bk_mesh_tree* tree) {
  bk_error err = {{0}};
  if (bk_mesh_tree_build(mesh, desc, tree, &err)) return true;
  if (strstr(err.message, "pieces made are not valid"))
    bk_fuzz_fail("--pattern %s --pieces %u: %s", bk_fracture_pattern_name(desc->pattern), desc->pieces,
                 err.message);
  return false;
}

// Brick: at most the pieces asked for, fewer only with the reason recorded.
static void check_brick(const bk_mesh* mesh, bk_fracture_def desc, bk_aabb box, const uint8_t* data,
                        size_t size) {
  uint8_t b = size >= 2 ? data[size - 2] : 0, last = data[size - 1];
  desc.pattern = BK_PATTERN_BRICK;
  desc.brick_size =
      bk_v3((box.max.x - box.min.x) / (2 + b % 4), (box.max.y - box.min.y) / (2 + b / 4 % 4), 0.0);
  desc.brick_origin = box.min;
  desc.brick_offset = (last >> 6) / 4.0;
  bk_mesh_tree tree = {0};
  if (!build(mesh, &desc, &tree)) return;
  check_tree(&tree, desc.pieces, desc.seed, desc.pattern);
  if (tree.leaf_count > desc.pieces)
    bk_fuzz_fail("--pattern brick --pieces %u: made %u pieces", desc.pieces, tree.leaf_count);
  bk_mesh_tree_free(&tree);
}

// Cut-out: a tiny map from the input's bytes. Its every pixel is a sample
// (a map under 3,000 pixels is sampled pixel by pixel), and a piece is made
// of samples: at most one per pixel. (One per region does not hold: a
// region whose prism the source cuts in two, say a U-shaped region across a
// cube, makes two.)
static void check_cutout(const bk_mesh* mesh, bk_fracture_def desc, const uint8_t* data, size_t size) {
  uint8_t b = size >= 2 ? data[size - 2] : 0, last = data[size - 1];
  uint32_t w = 2 + b % 7, h = 2 + b / 7 % 7;
  if (size < (size_t)w * h + 2) return;
  uint8_t pixels[64] = {0};
  for (uint32_t i = 0; i < w * h; ++i)
    pixels[i] = data[size - 2 - w * h + i] & 1 ? 255 : 0;
  desc.pattern = BK_PATTERN_CUTOUT;
  desc.cutout_pixels = pixels;
  desc.cutout_width = w;
  desc.cutout_height = h;
  desc.cutout_axis = (last >> 6) % 3;
  bk_mesh_tree tree = {0};
  if (!build(mesh, &desc, &tree)) return;
  check_tree(&tree, 0, desc.seed, desc.pattern);
  if (tree.leaf_count > w * h)
    bk_fuzz_fail("--pattern cutout (a %u x %u map, axis %u): made %u pieces", w, h, desc.cutout_axis,
                 tree.leaf_count);
  bk_mesh_tree_free(&tree);
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
  if (build(&mesh, &desc, &tree)) {
    check_tree(&tree, desc.pieces, desc.seed, desc.pattern);
    bk_mesh_tree_free(&tree);
  }
  desc.pattern = (bk_fracture_pattern)(BK_PATTERN_VORONOI + last % 3);
  desc.noise_amplitude = 0.0;
  if (last & 8) desc.noise_amplitude = amplitude, desc.noise_frequency = frequency;
  desc.impact = mesh.position_count ? mesh.positions[0] : bk_v3(0, 0, 0);
  if (build(&mesh, &desc, &tree)) {
    check_tree(&tree, desc.pieces, desc.seed, desc.pattern);
    // Exactly the pieces asked for, unless cells were joined where the
    // source's surface crosses itself (recorded, and checked by check_tree).
    bool joined = tree.leaf_count < desc.pieces && tree.shortfall.cells_joined > 0;
    if (tree.leaf_count != desc.pieces && !joined)
      bk_fuzz_fail("--pattern %s --pieces %u: made %u pieces", bk_fracture_pattern_name(desc.pattern),
                   desc.pieces, tree.leaf_count);
    bk_mesh_tree_free(&tree);
  }
  desc.noise_amplitude = 0.0;
  if (last & 32)
    check_cutout(&mesh, desc, data, size);
  else
    check_brick(&mesh, desc, box, data, size);
  bk_mesh_free(&mesh);
  return 0;
}
