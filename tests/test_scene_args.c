// The options sim and play share come from one table (src/scenes/scene_args.c):
// each entry parses into its field in both commands, both --help texts list
// it with its range, both refuse the same bad values with the same message
// (but for the command's name), and the GNU form --name=value works.
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "scene_args.h"

#define RUN_STDERR_PATH BK_TEST_TMP "/scene_args_stderr.txt"
#include "run_exe.h"

// Parses one option (and its value) for `command` into fresh defaults.
static int parse_one(const char* command, const char* name, const char* value, scene_args* out) {
  char* argv[3] = {(char*)command, (char*)name, (char*)value};
  int argc = value ? 3 : 2, i = 1;
  *out = default_scene_args("wall");
  int status = scene_args_parse(command, argc, argv, &i, out);
  if (status == 0) ENSURE_MSG(i == argc - 1, "%s: consumed up to %d of %d", name, i, argc);
  return status;
}

static void test_each_field_is_set(void) {
  scene_args a = {0};
  const char* commands[2] = {"sim", "play"};
  for (int c = 0; c < 2; ++c) {
    const char* command = commands[c];
    ENSURE(parse_one(command, "--scene", "tower", &a) == 0 && a.scene_given &&
           strcmp(a.scene_name, "tower") == 0);
    ENSURE(parse_one(command, "--mesh", "rock.obj", &a) == 0 && strcmp(a.mesh, "rock.obj") == 0);
    ENSURE(parse_one(command, "--material", "glass", &a) == 0 && strcmp(a.material, "glass") == 0);
    ENSURE(parse_one(command, "--pattern", "voronoi", &a) == 0 && a.options.pattern == BK_PATTERN_VORONOI);
    ENSURE(parse_one(command, "--pieces", "64", &a) == 0 && a.options.pieces == 64);
    ENSURE(parse_one(command, "--seed", "18446744073709551615", &a) == 0 && a.options.seed == UINT64_MAX);
    ENSURE(parse_one(command, "--volley", "10000000", &a) == 0 && a.volley == 10000000);
    ENSURE(parse_one(command, "--no-stress", NULL, &a) == 0 && !a.options.stress);
    ENSURE(parse_one(command, "--stress-scale", "0.15", &a) == 0 && a.options.stress_scale == 0.15);
    ENSURE(parse_one(command, "--budget-ms", "0", &a) == 0 && a.options.physics_budget_ms == 0.0);
    ENSURE(parse_one(command, "--budget-ms", "12.5", &a) == 0 && a.options.physics_budget_ms == 12.5);
    ENSURE(parse_one(command, "--drop", "20000", &a) == 0 && a.drop.kg == 20000.0);
    ENSURE(parse_one(command, "--drop-radius", "0.5", &a) == 0 && a.drop.radius == 0.5 &&
           a.drop.radius_given);
    ENSURE(parse_one(command, "--drop-at", "90", &a) == 0 && a.drop.at == 90 && a.drop.at_given);
    ENSURE(parse_one(command, "--refine", NULL, &a) == 0 && a.options.refine &&
           a.options.refine_pieces == BK_REFINE_PIECES_DEFAULT && a.options.stress);
    ENSURE(parse_one(command, "--refine-pieces", "1024", &a) == 0 && a.options.refine &&
           a.options.refine_pieces == 1024);
    ENSURE(parse_one(command, "--no-stress", NULL, &a) == 0 && !a.options.refine);
    ENSURE(parse_one(command, "--max-memory", "4096", &a) == 0);
    ENSURE(parse_one(command, "--scale", "2", &a) == 0);
    ENSURE(parse_one(command, "--units", "cm", &a) == 0);
    // Not a shared option: left to the command.
    ENSURE(parse_one(command, "--steps", "10", &a) == 1);
    ENSURE(parse_one(command, "--frames", "10", &a) == 1);
    // Bad values and a missing one: refused, the value not taken.
    ENSURE(parse_one(command, "--pieces", "0", &a) == 2 && a.options.pieces == 0);
    ENSURE(parse_one(command, "--pieces", "65537", &a) == 2);
    ENSURE(parse_one(command, "--pattern", "zigzag", &a) == 2 && a.options.pattern == -1);
    ENSURE(parse_one(command, "--stress-scale", "nan", &a) == 2 && a.options.stress_scale == 1.0);
    ENSURE(parse_one(command, "--seed", NULL, &a) == 2);
    ENSURE(parse_one(command, "--refine-pieces", "1", &a) == 2 && !a.options.refine &&
           a.options.refine_pieces == BK_REFINE_PIECES_DEFAULT);
  }
  printf("each shared option sets its field in sim and play; bad values are refused\n");
}

// Every entry of the table in both commands' --help, with its range, and
// refused beyond it by both with the same message.
static void test_table_drives_both_commands(void) {
  uint32_t count = 0;
  const scene_arg* table = scene_arg_table(&count);
  ENSURE(count >= 11);
  static char help[2][1 << 16];
  const char* commands[2] = {"sim", "play"};
  for (int c = 0; c < 2; ++c) {
    char args[64] = "";
    snprintf(args, sizeof args, "%s --help", commands[c]);
    run_result* r = run(args);
    ENSURE_MSG(r->status == 0, "%s --help: status %d", commands[c], r->status);
    snprintf(help[c], sizeof help[c], "%s", r->out);
  }
  for (uint32_t k = 0; k < count; ++k) {
    const scene_arg* e = &table[k];
    for (int c = 0; c < 2; ++c) {
      char line[96] = "";
      snprintf(line, sizeof line, "\n  %s", e->name);
      ENSURE_MSG(strstr(help[c], line), "%s --help does not list %s", commands[c], e->name);
    }
    if (e->min == 0.0 && e->max == 0.0) continue;
    // The range as the help states it ("1..65536"), then one beyond it.
    char range[96] = "", beyond[64] = "";
    if (e->whole && e->max >= (double)UINT64_MAX)
      snprintf(range, sizeof range, "%.0f..18446744073709551615", e->min);
    else if (e->whole)
      snprintf(range, sizeof range, "%.0f..%.0f", e->min, e->max);
    else {
      // As the error messages write them (format_number: "1e-6..1e6").
      char low[32] = "", high[32] = "";
      format_number(e->min, low, sizeof low);
      format_number(e->max, high, sizeof high);
      snprintf(range, sizeof range, "%s..%s", low, high);
    }
    ENSURE_MSG(strstr(e->help, range), "%s's help does not state its range %s", e->name, range);
    if (e->whole && e->max >= (double)UINT64_MAX)
      snprintf(beyond, sizeof beyond, "18446744073709551616");
    else if (e->whole)
      snprintf(beyond, sizeof beyond, "%.0f", e->max + 1.0);
    else
      snprintf(beyond, sizeof beyond, "%g", e->max * 10.0);
    char message[2][512] = {"", ""};
    for (int c = 0; c < 2; ++c) {
      char args[256] = "";
      // The GNU form, for half of them.
      snprintf(args, sizeof args, k % 2 ? "%s %s=%s --frames 1" : "%s %s %s --frames 1", commands[c], e->name,
               beyond);
      if (c == 0)
        snprintf(args, sizeof args, k % 2 ? "sim %s=%s --steps 1" : "sim %s %s --steps 1", e->name, beyond);
      run_result* r = run(args);
      ENSURE_MSG(r->status == 2, "%s: status %d for %s", args, r->status, beyond);
      ENSURE_MSG(count_lines(r->err) == 1 && strstr(r->err, e->name) && strstr(r->err, "out of range"),
                 "%s: %s", args, r->err);
      const char* after = strchr(r->err, ':'); // "breakables sim: ..." without the command
      snprintf(message[c], sizeof message[c], "%.500s", after ? after : r->err);
    }
    ENSURE_MSG(strcmp(message[0], message[1]) == 0, "sim and play differ on %s: %s / %s", e->name, message[0],
               message[1]);
  }
  printf("%u shared options: in both --help texts with their ranges, refused alike beyond them\n", count);
}

int main(void) {
  test_each_field_is_set();
  test_table_drives_both_commands();
  return 0;
}
