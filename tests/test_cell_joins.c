// A cell pattern never fails where the planes pattern succeeds: the Collada
// duck of assimp-testmodels has a surface that crosses itself, and where a
// cut face between two cells meets that crossing its outline crosses too and
// cannot be triangulated ("the cut face between cells 48 and 127 cannot be
// triangulated", radial at 128 pieces). The two cells are then kept as one
// piece, the tree records it (shortfall.cells_joined) and says so in its
// warning, every node stays closed and the leaves keep the source's volume;
// `fracture --json` lists the warning. Every cell pattern goes through the
// same faces, so each is tried.
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bk_fracture.h"
#include "ensure.h"

#ifdef BK_BREAKABLES_EXE
#define RUN_STDERR_PATH BK_TEST_TMP "/test_cell_joins_stderr.txt"
#include "run_exe.h"
// run_exe.h first: cli_util.h's expect_error runs the command.
#include "cli_util.h"
#endif

#define DUCK "/usr/share/assimp/models/Collada/duck.dae"

typedef struct join_case {
  bk_fracture_pattern pattern;
  uint32_t pieces;
  uint64_t seed; ///< one whose faces failed before cells could be joined
} join_case;

static void check_case(const bk_mesh* duck, join_case c) {
  bk_fracture_def d = bk_default_fracture_def();
  d.pattern = c.pattern;
  d.pieces = c.pieces;
  d.seed = c.seed;
  const char* name = bk_fracture_pattern_name(c.pattern);
  bk_mesh_tree tree = {0};
  bk_error err = {0};
  ENSURE_MSG(bk_mesh_tree_build(duck, &d, &tree, &err), "%s %u seed %llu: %s", name, c.pieces,
             (unsigned long long)c.seed, err.message);
  uint32_t joined = tree.shortfall.cells_joined;
  ENSURE_MSG(joined > 0, "%s %u seed %llu: no cells joined", name, c.pieces, (unsigned long long)c.seed);
  // A joined pair is one piece: at most one fewer per pair, never more.
  ENSURE_MSG(tree.leaf_count <= c.pieces && tree.leaf_count + joined >= c.pieces, "%s: %u leaves, %u joined",
             name, tree.leaf_count, joined);
  char text[400];
  ENSURE(bk_mesh_tree_shortfall_text(&tree, text, sizeof text));
  ENSURE_MSG(strstr(text, "could not be made") && strstr(text, "kept as one piece"), "%s", text);
  bk_mesh_tree_stats st = bk_mesh_tree_measure(&tree);
  ENSURE_MSG(st.open_nodes == 0, "%s: %u open nodes", name, st.open_nodes);
  ENSURE_MSG(fabs(st.leaf_volume_sum - st.source_volume) <= 1e-9 * st.source_volume,
             "%s: leaves %.17g, source %.17g", name, st.leaf_volume_sum, st.source_volume);
  ENSURE_MSG(st.max_child_rel_error <= 1e-9, "%s: children miss their parent by %g", name,
             st.max_child_rel_error);
  for (uint32_t l = 0; l < tree.leaf_count; ++l)
    ENSURE_MSG(bk_mesh_tree_leaf(&tree, l)->moments.v > 0.0, "%s: leaf %u has volume %g", name, l,
               bk_mesh_tree_leaf(&tree, l)->moments.v);
  for (uint32_t b = 0; b < tree.bond_count; ++b)
    ENSURE(tree.bonds[b].area > 0.0 && tree.bonds[b].leaf_a < tree.bonds[b].leaf_b);
  printf("%s %u seed %llu: %u leaves, %u cut face(s) joined\n", name, c.pieces, (unsigned long long)c.seed,
         tree.leaf_count, joined);
  bk_mesh_tree_free(&tree);
}

static void test_duck(void) {
  FILE* f = fopen(DUCK, "rb");
  ENSURE_MSG(f != NULL, "%s is missing: scripts/setup.sh installs assimp-testmodels", DUCK);
  fclose(f);
  bk_mesh duck = {0};
  bk_import_info info = {0};
  bk_error err = {0};
  ENSURE_MSG(bk_model_import(DUCK, NULL, &duck, &info, &err), "%s", err.message);
  bk_import_info_free(&info);
  const join_case cases[] = {
      {BK_PATTERN_RADIAL, 128, 3000}, // the default seed: "cells 48 and 127"
      {BK_PATTERN_RADIAL, 128, 1},    {BK_PATTERN_RADIAL, 256, 21},  {BK_PATTERN_RADIAL, 256, 39},
      {BK_PATTERN_VORONOI, 64, 4},    {BK_PATTERN_CLUSTERED, 64, 5},
  };
  for (size_t i = 0; i < sizeof cases / sizeof *cases; ++i)
    check_case(&duck, cases[i]);
  bk_mesh_free(&duck);
}

#ifdef BK_BREAKABLES_EXE
// The command line says it: a warning on stderr and in the JSON, exit 0.
static void test_cli_warning(void) {
  run_result* r = run("fracture --mesh " DUCK " --pattern radial --pieces 128 --json");
  ENSURE_MSG(r->status == 0, "exit %d: %s", r->status, r->err);
  ENSURE_MSG(strstr(r->err, "warning") && strstr(r->err, "1 cut face between cells could not be made"), "%s",
             r->err);
  const char* warnings = strstr(r->out, "\"warnings\": [");
  ENSURE_MSG(warnings && strstr(warnings, "1 cut face between cells could not be made"), "%s", r->out);
  ENSURE(strstr(r->out, "\"watertight\": true") && json_number(r->out, "volume_rel_error") < 1e-9);
  ENSURE(json_number(r->out, "pieces_made") == 128);
}
#endif

int main(void) {
  test_duck();
#ifdef BK_BREAKABLES_EXE
  test_cli_warning();
#endif
  puts("test_cell_joins: ok");
  return 0;
}
