// The programs' shared helpers: number and option parsing, mesh and model
// sources, output files, the memory guard, warnings.
#pragma once

#include <stdbool.h>
#include <stdint.h>

#include <breakables/authoring.h>

/// Resolves --mesh: a built-in shape name, "bunny" (the bundled asset, scaled
/// to 1 unit tall standing on y = 0) or a path to an .obj file. Open meshes
/// with simple holes are repaired with a warning on stderr; anything else that
/// cannot be fractured is refused with a one-line error.
bool app_load_mesh(const char* spec, bk_mesh* out, bk_error* err);
/// app_load_mesh with a scene node to take (with its subtree; NULL = the
/// whole scene) from a model file: shells touching at a vertex or an edge are
/// split apart and simple holes closed (bk_mesh_repair), with a warning.
/// info (may be NULL) gets what the import found (materials, textures); the
/// caller releases it with bk_import_info_free.
bool app_load_model(const char* spec, const char* node, bk_mesh* out, bk_import_info* info, bk_error* err);
/// --scale S (a factor) and --units mm|cm|m|in (of a format that does not
/// state its own) for every model file the command loads (not the built-in
/// shapes). Sizes outside 1 cm..100 m across are warned about.
#define BK_MODEL_SCALE_MIN 1e-6
#define BK_MODEL_SCALE_MAX 1e6
#define BK_MODEL_SIZE_MIN 0.01
#define BK_MODEL_SIZE_MAX 100.0
/// The two options' lines for a command's --help.
#define BK_MODEL_UNITS_USAGE                                                                                 \
  "  --scale S             multiply a model file's size by S, 1e-06..1e+06 (default: 1)\n"                   \
  "  --units mm|cm|m|in    the unit of a model file whose format gives none (OBJ, STL,\n"                    \
  "                        PLY, ...; FBX, glTF and Collada give theirs; default: m)\n"
/// Parses --scale or --units for `command`: 0 if argv[*i] was one (its value
/// consumed), 1 if not, 2 on a bad value (one line printed naming the option).
int parse_model_units_option(const char* command, int argc, char** argv, int* i);
/// Back to scale 1 and no --units (for tests running several command lines).
void app_reset_model_units(void);
/// What --scale and --units set: the scale, and the unit's name (NULL: none given).
void app_model_units(double* scale, const char** units);
/// Scales a model file's mesh as --scale and --units ask (--units ignored,
/// with a warning, when info says the file gives its unit) and warns on
/// stderr when it is outside 1 cm..100 m across.
void app_apply_model_units(const char* path, bk_mesh* mesh, const bk_import_info* info);
/// The size warning for `mesh` into out (one line); false when its size is fine.
bool app_model_size_note(const bk_mesh* mesh, char* out, size_t size);
/// The materials a glTF export carries (bk_gltf_def.materials), with the
/// texture files read into memory so the export holds them.
typedef struct app_export_materials {
  bk_gltf_material* list;
  uint32_t count;
  char (*names)[64];
  void** files;               ///< texture file bytes read, 2 per material
  uint32_t textures_left_out; ///< textures not found or not PNG/JPEG (each warned on stderr)
} app_export_materials;
/// An imported model's materials (info may be NULL: one "surface"); `spec` names the model in warnings.
void app_export_materials_from_import(const bk_import_info* info, const char* spec,
                                      app_export_materials* out);
/// One of the game's materials ("stone", ...) with its albedo and interior textures.
void app_export_materials_from_look(const char* look, app_export_materials* out);
/// Releases what the two above made.
void app_export_materials_free(app_export_materials* m);
/// Directory holding assets/ content (next to the executable, or the source tree).
const char* app_asset_dir(void);
/// Parses a whole number in [min, max]: exactly [0-9]+ (no sign, blank, hex
/// or trailing text); false otherwise or on overflow. `out` is set only on success.
bool parse_u64(const char* text, uint64_t min, uint64_t max, uint64_t* out);
/// Parses a plain decimal number in [min, max]: exactly
/// [+-]?(D+[.D*]|.D+)([eE][+-]?D+)? (no blank, hex, inf or nan); false
/// otherwise, or when it is beyond a double or rounds out of the range (a
/// value that underflows to 0 is refused when min > 0). `out` is set only on success.
bool parse_double(const char* text, double min, double max, double* out);
/// parse_u64 for the value of a command's option; on failure prints one
/// line naming the option, its text and the range, e.g. "breakables fracture:
/// --seed ' -1' is not a whole number (0..18446744073709551615)".
bool option_u64(const char* command, const char* option, const char* text, uint64_t min, uint64_t max,
                uint64_t* out);
/// The command line with every `--name=value` (GNU form) given as the two
/// arguments `--name` `value`, so that each command's parser takes both
/// forms alike; other arguments are kept as they are. The new array (and
/// *argc) stays valid until the program exits.
char** split_option_values(int* argc, char** argv);
/// Which of `names` argv[*i] is (-1: none of them), taking its value into
/// *value and moving *i past it; -2 when the value is missing, with the
/// message printed. For a command's group of options that each take one.
int take_option(const char* command, int argc, char** argv, int* i, const char* const* names, int count,
                const char** value);
/// parse_double for the value of a command's option, with the same kind of message.
bool option_double(const char* command, const char* option, const char* text, double min, double max,
                   double* out);
/// The shortest text of a number that reads back exactly: plain from 0.0001
/// to 9999 (0.1, 2000), else with a bare exponent (1e-6, 1e5), as the range
/// messages of option_double write their bounds.
void format_number(double value, char* out, size_t size);
/// Monotonic clock in milliseconds.
double app_now_ms(void);
/// Peak resident memory of this process in MiB.
double app_peak_rss_mb(void);

/// Parses the value of --max-memory (MiB) for `command` and makes it the
/// limit app_check_fracture_memory uses; prints one line and returns false
/// on a bad value.
bool app_parse_max_memory(const char* command, const char* text);
/// Refuses a fracture of `source` by `desc` whose estimated memory
/// (bk_mesh_tree_estimate_bytes, plus the file when `saving`) exceeds the
/// limit: --max-memory when given, else MemAvailable from /proc/meminfo (no
/// check when that is unknown). err gets one line with the estimate and the
/// limit, naming the request by its pieces and `mesh_spec`.
bool app_check_fracture_memory(const char* mesh_spec, const bk_mesh* source, const bk_fracture_def* desc,
                               bool saving, bk_error* err);
/// What app_load_model last repaired on this thread (all zero after a
/// built-in shape or before any load).
const bk_repair_info* app_last_repair(void);
/// The repairs of `r` as one line ("removed 1 triangles given twice; ..."),
/// "" when there were none; returns its length.
size_t app_repair_text(const bk_repair_info* r, char* out, size_t size);
/// Refuses, before it is decoded, a fracture map (`path`, its header read:
/// width x height, `channels`, 16 bits a channel or 8) whose decoding with
/// the build's use of it would exceed the same limit; `file_bytes` are held
/// while it decodes. err gets one line naming the file, its size, the
/// estimate and the limit.
bool app_check_map_memory(const char* path, uint32_t width, uint32_t height, int channels, bool sixteen_bit,
                          uint64_t file_bytes, bk_error* err);

/// The game's fracture map for the cutout pattern: a square of side
/// `*size` pixels (grey, row 0 at the top) with a cobweb of cracks, as
/// glass breaks round a hit at its centre. Made once, never freed.
const uint8_t* app_cutout_map(uint32_t* size);
/// Writes target's path relative to the directory of from_file (for a URI
/// in a file written there); false if either cannot be resolved or it does
/// not fit in capacity bytes.
bool app_relative_path(const char* from_file, const char* target, char* out, size_t capacity);

/// Median of values (sorted in place); 0 for none.
double app_median(double* values, uint32_t count);
/// The p-th percentile (0..100, nearest rank) of values (sorted in place); 0 for none.
double app_percentile(double* values, uint32_t count, double p);
/// The largest of values (0 for none, or when all are negative).
double app_maximum(const double* values, uint32_t count);

/// Prints "breakables: warning: <text>" on stderr, the text escaped like
/// every error (bk_escape_text): warnings quote names from model files.
void app_warning(const char* format, ...) __attribute__((format(printf, 1, 2)));
/// An option's text as it can be shown in a one-line message: control
/// characters as \xNN (bk_escape_text), long text cut short with "...".
void quote_text(const char* text, char* out, size_t size);

/// A file a command reads or writes, named by its option ("--out").
typedef struct app_file {
  const char* option;
  const char* path;       ///< NULL: not given (skipped)
  const char* extensions; ///< outputs: the accepted endings, space-separated (".glb .gltf"); NULL = any
  bool any_case;          ///< the endings match in any case (".GLB")
} app_file;
/// Checks a command's output files before any work (output_files.c): each
/// ends in one of its extensions, bk_file_check_write accepts it (directory
/// there, target not read-only nor a directory), none is one of the inputs
/// and no two are the same file (bk_file_same). False with one line in err
/// naming the option, the file and why.
bool app_check_files(const app_file* inputs, uint32_t input_count, const app_file* outputs,
                     uint32_t output_count, bk_error* err);

/// Appends name number `index` of `count` to a list in out ("a", "a or b",
/// "a, b or c"); returns the new length (at most size - 1 is written).
size_t append_name(char* out, size_t size, size_t used, uint32_t index, uint32_t count, const char* name);
