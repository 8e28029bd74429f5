// The fracture command's pattern options (--pattern, --seeds, --clusters,
// ..., --noise, --threads): parsing, the checks between them, the files
// they name, their part of --help and of --json.
#pragma once

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include <breakables/authoring.h>

/// What the pattern options gathered besides the bk_fracture_def fields.
typedef struct pattern_options {
  uint32_t given;          ///< one bit per pattern option seen (in the order of its table)
  const char* seeds_path;  ///< --seeds FILE, or NULL
  const char* cutout_path; ///< --cutout FILE.png, or NULL
  bk_vec3* seed_points;    ///< read from seeds_path by pattern_options_finish (owned)
  uint8_t* cutout_pixels;  ///< decoded from cutout_path by pattern_options_finish (owned)
  /// A warning about the map ("" when none): more regions than its
  /// samples. The command prints it once the fracture goes ahead.
  char cutout_warning[400];
} pattern_options;

/// What app_pattern_option made of an argument.
typedef enum pattern_option_result {
  BK_PATTERN_OPTION_NOT_MINE, ///< not a pattern option: the caller goes on
  BK_PATTERN_OPTION_TAKEN,    ///< parsed into def / options; it took `value`, unless it is a flag
  BK_PATTERN_OPTION_REFUSED,  ///< a bad or missing value: one line was printed, exit with 2
} pattern_option_result;

/// Parses `arg` (with the next argument `value`, NULL when there is none)
/// when it is a pattern option: values are read strictly and checked
/// against the ranges --help states.
pattern_option_result app_pattern_option(const char* arg, const char* value, bk_fracture_def* def,
                                         pattern_options* options);
/// After every argument: refuses options of another pattern than the one
/// chosen ("--impact needs --pattern radial"), reads --seeds and --cutout
/// into def (a file that cannot be read or parsed: one line naming it, exit
/// code 1) and checks def with bk_fracture_def_validate (its message, which
/// names the field, is printed: exit code 2). Returns 0 when all is well.
int pattern_options_finish(pattern_options* options, bk_fracture_def* def);
/// Releases what pattern_options_finish read.
void pattern_options_free(pattern_options* options);

/// Writes the pattern options' part of `fracture --help`, with the ranges
/// parsing enforces and the defaults of bk_default_fracture_def.
void pattern_options_help(FILE* out);
/// Writes the JSON members of the pattern used (`"pattern": "radial",
/// "impact": [0, 0, 0], ...`, each preceded by ", "), from the def the
/// tree was built with.
void pattern_options_json(FILE* out, const bk_fracture_def* used, const pattern_options* options);

/// A number for JSON: the shortest text that reads back to it exactly, or
/// null when it is not finite.
void app_json_number(FILE* out, double value);
/// A number for JSON written by a printf format of one double ("%.3e") into
/// text (returned), or null when it is not finite: printf would write inf or
/// nan, which are not JSON, and one report field without a value is better
/// than a report no JSON reader can read.
const char* app_json_text(char* text, size_t size, const char* format, double value);
/// app_json_text into a buffer that lives until the end of the enclosing
/// block: printf("\"ms\": %s", BK_APP_JSON_NUMBER("%.3f", ms)).
#define BK_APP_JSON_NUMBER(format, value) app_json_text((char[48]){0}, 48, format, value)
/// A JSON string literal: quotes, backslashes and control characters escaped.
void app_json_string(FILE* out, const char* text);
