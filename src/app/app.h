// Internal to the executable: subcommands and shared helpers.
#pragma once

#include <stdbool.h>
#include <stdint.h>

#include "bk_fracture.h"

/// Subcommand entry points; argv[0] is the subcommand name. Return the exit code.
int bk_cmd_fracture(int argc, char** argv);

/// Resolves --mesh: a built-in shape name, "bunny" (the bundled asset, scaled
/// to 1 unit tall standing on y = 0) or a path to an .obj file. Open meshes
/// with simple holes are repaired with a warning on stderr; anything else that
/// cannot be fractured is refused with a one-line error.
bool bk_app_load_mesh(const char* spec, bk_mesh* out, bk_error* err);
/// Directory holding assets/ content (next to the executable, or the source tree).
const char* bk_app_asset_dir(void);
/// Parses a whole unsigned number in [min, max]; false on junk or overflow.
bool bk_parse_u64(const char* text, uint64_t min, uint64_t max, uint64_t* out);
/// Parses a finite double in (min, max]; false on junk, NaN or out of range.
bool bk_parse_double(const char* text, double min_exclusive, double max_inclusive, double* out);
/// Monotonic clock in milliseconds.
double bk_now_ms(void);
/// Peak resident memory of this process in MiB.
double bk_peak_rss_mb(void);
