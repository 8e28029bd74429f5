// The options sim and play share, in one table: each command's parsing and
// --help come from it, so the two cannot drift apart (they once took
// different --volley ranges and reported a missing value differently).
#include "scene_args.h"

#include <stdint.h>
#include <stdio.h>
#include <string.h>

enum {
  ARG_SCENE,
  ARG_MESH,
  ARG_SCALE,
  ARG_UNITS,
  ARG_MATERIAL,
  ARG_PATTERN,
  ARG_PIECES,
  ARG_SEED,
  ARG_VOLLEY,
  ARG_NO_STRESS,
  ARG_STRESS_SCALE,
  ARG_DROP,
  ARG_DROP_RADIUS,
  ARG_DROP_AT,
  ARG_MAX_MEMORY,
  ARG_BUDGET_MS,
  ARG_REFINE,
  ARG_REFINE_PIECES,
  ARG_COUNT
};

// Indexed by the enum above; the ranges are what the parsers below and
// the drop's, units' and memory guard's own parsers check.
static const scene_arg table[ARG_COUNT] = {
    [ARG_SCENE] = {"--scene", "NAME",
                   "wall, eggshell, pillar, slab, bunny, torus, showcase, tower, bridge, balcony (default: "
                   "sim's wall, play's showcase)"},
    [ARG_MESH] = {"--mesh", "PATH",
                  "your own model instead of a scene (what fracture --mesh reads, an .mtree, or a .glb/.gltf "
                  "exported by fracture): stood on the ground and shot at from the front"},
    [ARG_SCALE] = {"--scale", "S", "multiply a model file's size by S, 1e-6..1e6 (default: 1)", 1e-6, 1e6},
    [ARG_UNITS] = {"--units", "mm|cm|m|in",
                   "the unit of a model file whose format gives none (OBJ, STL, PLY, ...; FBX, glTF and "
                   "Collada give theirs; default: m)"},
    [ARG_MATERIAL] = {"--material", "NAME",
                      "stone, concrete, glass, porcelain, eggshell, wood: every object's material (default: "
                      "the scene's; stone for --mesh)"},
    [ARG_PATTERN] = {"--pattern", "NAME",
                     "how every object breaks: planes, voronoi, clustered, radial, brick or cutout (default: "
                     "each object's own: the walls brick, the pillar clustered, the bunny, torus, tower, "
                     "bridge and balcony radial round their aim points, the eggshell voronoi, the rest "
                     "planes); see 'breakables fracture --help'"},
    [ARG_PIECES] = {"--pieces", "N",
                    "fragments per object, 1..65536 (default: the scene's; cutout makes as many as its "
                    "fracture map has regions)",
                    1, 65536, true},
    [ARG_SEED] = {"--seed", "S", "fracture seed, 0..18446744073709551615 (default: 3000)", 0,
                  (double)UINT64_MAX, true},
    [ARG_VOLLEY] = {"--volley", "V",
                    "fire the shots within the first V STEPs, 1..10000000 (default: spread over the whole "
                    "run): the rest shows what the debris costs as it settles",
                    1, 10000000, true},
    [ARG_NO_STRESS] = {"--no-stress", NULL,
                       "no structural stress: what is still bonded to an anchor stays up however little "
                       "holds it"},
    [ARG_STRESS_SCALE] = {"--stress-scale", "X",
                          "every material's stress limits times X, 1e-6..1e6 (default 1; at 0.15 the "
                          "bridge and the balcony cannot carry their own weight)",
                          1e-6, 1e6},
    [ARG_DROP] = {"--drop", "KG",
                  "set a weight of KG, 1..1e6, down at rest on the top surface over the first object's "
                  "aim point (the bridge: the middle of its deck), for the structure to carry (20000 "
                  "breaks the bridge, 500 does not)",
                  BK_DROP_KG_MIN, BK_DROP_KG_MAX},
    [ARG_DROP_RADIUS] = {"--drop-radius", "M", "the weight's radius, 0.01..2 m (default 0.3)",
                         BK_DROP_RADIUS_MIN, BK_DROP_RADIUS_MAX},
    [ARG_DROP_AT] = {"--drop-at", "STEP",
                     "the STEP it is set down, 0..10000000, before the last (default 60: the structure has "
                     "settled)",
                     0, BK_DROP_AT_MAX, true},
    [ARG_MAX_MEMORY] = {"--max-memory", "MIB",
                        "memory each fracture may use, 1..1073741824 MiB (default: the available memory); a "
                        "tree estimated to need more is refused",
                        1, 1073741824.0, true},
    [ARG_BUDGET_MS] =
        {"--budget-ms", "X",
         "the physics budget per step, 0..1000 ms (default 8, half a 60 Hz frame; 0 turns it "
         "off): over it, the least important loose pieces (small, far from the eye, slow, long "
         "at rest) get cheaper: no contacts among themselves, then a fitted sphere or box, then "
         "frozen, then retired",
         0, BK_BUDGET_MS_MAX},
    [ARG_REFINE] = {"--refine", NULL,
                    "break where it is hit: a fragment struck hard enough is fractured again, radially round "
                    "the hit, and its pieces take the hit's damage (hard enough: enough to break a bond an "
                    "eighth of the fragment's cross-section, about the bonds of a wall of 1,024 fragments "
                    "near the hits on one of 64)"},
    [ARG_REFINE_PIECES] = {"--refine-pieces", "N",
                           "pieces per refinement, 2..1024 (default 32); implies --refine",
                           BK_REFINE_PIECES_MIN, BK_REFINE_PIECES_MAX, true},
};

const scene_arg* scene_arg_table(uint32_t* count) {
  *count = ARG_COUNT;
  return table;
}

scene_args default_scene_args(const char* scene_name) {
  scene_args a = {.scene_name = scene_name,
                  .scene_given = false,
                  .mesh = NULL,
                  .material = NULL,
                  .volley = 0,
                  .options = default_scene_options(),
                  .drop = default_drop()};
  return a;
}

static int find(const char* name) {
  for (int k = 0; k < ARG_COUNT; ++k)
    if (strcmp(name, table[k].name) == 0) return k;
  return -1;
}

int scene_args_parse(const char* command, int argc, char** argv, int* i, scene_args* a) {
  int which = find(argv[*i]);
  if (which < 0) return 1;
  // These have parsers of their own (the editor and fracture take --scale
  // and --units too); the table only lists them.
  if (which == ARG_SCALE || which == ARG_UNITS) return parse_model_units_option(command, argc, argv, i);
  if (which == ARG_DROP || which == ARG_DROP_RADIUS || which == ARG_DROP_AT)
    return parse_drop_option(command, argc, argv, i, &a->drop);
  const scene_arg* arg = &table[which];
  if (!arg->value) {
    if (which == ARG_NO_STRESS) a->options.stress = false;
    if (which == ARG_REFINE) a->options.refine = true;
    return 0;
  }
  const char* value = NULL;
  const char* const names[1] = {arg->name};
  if (take_option(command, argc, argv, i, names, 1, &value) < 0) return 2;
  uint64_t number = 0;
  bool ok = true;
  if (arg->whole && which != ARG_MAX_MEMORY) {
    uint64_t max = arg->max >= (double)UINT64_MAX ? UINT64_MAX : (uint64_t)arg->max;
    ok = option_u64(command, arg->name, value, (uint64_t)arg->min, max, &number);
  }
  if (!ok) return 2;
  switch (which) {
  case ARG_SCENE:
    a->scene_name = value;
    a->scene_given = true;
    break;
  case ARG_MESH:
    a->mesh = value;
    break;
  case ARG_MATERIAL:
    a->material = value;
    break;
  case ARG_PATTERN: {
    bk_fracture_pattern pattern = BK_PATTERN_PLANES;
    bk_error err = {0};
    if (!scene_pattern_from_name(value, &pattern, &err)) {
      fprintf(stderr, "breakables %s: %s\n", command, err.message);
      return 2;
    }
    a->options.pattern = (int)pattern;
    break;
  }
  case ARG_PIECES:
    a->options.pieces = (uint32_t)number;
    break;
  case ARG_SEED:
    a->options.seed = number;
    break;
  case ARG_VOLLEY:
    a->volley = number;
    break;
  case ARG_STRESS_SCALE:
    ok = option_double(command, arg->name, value, arg->min, arg->max, &a->options.stress_scale);
    break;
  case ARG_MAX_MEMORY:
    ok = app_parse_max_memory(command, value);
    break;
  case ARG_BUDGET_MS:
    ok = app_parse_budget_ms(command, value, &a->options);
    break;
  case ARG_REFINE_PIECES:
    a->options.refine_pieces = (uint32_t)number;
    a->options.refine = true; // asking for pieces asks for refinement
    break;
  default:
    break;
  }
  return ok ? 0 : 2;
}

// Writes `text` from column `column` (the first line continues where the
// caller stopped, at `at`), breaking at spaces within `width`.
static void wrap(const char* text, int at, int column, int width, FILE* out) {
  const char* p = text;
  while (*p) {
    const char* end = p;
    const char* fits = NULL;
    while (*end && end - p <= width - at) {
      if (*end == ' ') fits = end;
      ++end;
    }
    if (!*end) fits = end;                                             // the rest fits
    if (!fits) fits = strchr(p, ' ') ? strchr(p, ' ') : p + strlen(p); // one long word
    fprintf(out, "%.*s\n", (int)(fits - p), p);
    p = *fits ? fits + 1 : fits;
    if (*p) fprintf(out, "%*s", column, "");
    at = column;
  }
}

void scene_args_help(const char* command, int column, int width, FILE* out) {
  const char* unit = strcmp(command, "play") == 0 ? "frame" : "step";
  for (int k = 0; k < ARG_COUNT; ++k) {
    char head[64] = "", text[600] = "";
    snprintf(head, sizeof head, "  %s%s%s", table[k].name, table[k].value ? " " : "",
             table[k].value ? table[k].value : "");
    if (table[k].value && strcmp(table[k].value, "STEP") == 0)
      snprintf(head, sizeof head, "  %s %s", table[k].name, strcmp(unit, "frame") == 0 ? "FRAME" : "STEP");
    // "STEP" in the text is the command's unit.
    const char* from = table[k].help;
    size_t used = 0;
    while (*from && used + 8 < sizeof text) {
      if (strncmp(from, "STEP", 4) == 0) {
        used += (size_t)snprintf(text + used, sizeof text - used, "%s", unit);
        from += 4;
      } else {
        text[used++] = *from++;
      }
    }
    text[used] = '\0';
    int len = (int)strlen(head);
    if (len + 1 > column) {
      fprintf(out, "%s\n%*s", head, column, "");
      len = column;
    } else {
      fprintf(out, "%s%*s", head, column - len, "");
      len = column;
    }
    wrap(text, len, column, width, out);
  }
}
