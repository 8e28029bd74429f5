// The options `sim` and `play` share: which scene or model, how it breaks,
// the world's budget and stress, a weight to carry. One table holds them
// (scene_args.c); both commands parse, and print in --help, from it.
#pragma once

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "scene_run.h"

/// What the shared options set.
typedef struct scene_args {
  const char* scene_name; ///< the command's default until --scene
  bool scene_given;
  const char* mesh;     ///< --mesh PATH, or NULL
  const char* material; ///< --material NAME, or NULL
  uint64_t volley;      ///< --volley: 0 = the shots spread over the whole run
  scene_options options;
  app_drop drop;
} scene_args;

/// The defaults: `scene_name` until --scene, the scene options' and the
/// drop's defaults.
scene_args default_scene_args(const char* scene_name);

/// One shared option, as the table lists it.
typedef struct scene_arg {
  const char* name;  ///< "--pieces"
  const char* value; ///< what its value is called in the help ("N"); NULL for a flag
  /// The help text. "STEP" stands for what the command counts in: sim's
  /// steps, play's frames.
  const char* help;
  /// A number's range (both 0 for text and flags); the help states it.
  double min, max;
  bool whole; ///< a whole number (else a real one)
} scene_arg;

/// The table, `*count` entries (the drop's and the model units' options too).
const scene_arg* scene_arg_table(uint32_t* count);

/// Parses argv[*i] for `command` ("sim" or "play"): 0 when it was a shared
/// option (its value consumed, *i moved past it), 1 when it is not one, 2 on
/// a bad or missing value (one line printed on stderr naming the option).
int scene_args_parse(const char* command, int argc, char** argv, int* i, scene_args* args);

/// The options' lines of `command`'s --help: each name and value at two
/// spaces, its text from column `column`, wrapped within `width` columns.
void scene_args_help(const char* command, int column, int width, FILE* out);
