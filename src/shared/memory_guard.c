// The memory guard: a fracture that would not fit in memory is refused
// before it starts, with its estimate and the limit, instead of driving the
// machine into swap or the out-of-memory killer half-way.
#include <inttypes.h>
#include <math.h>
#include <stdatomic.h>
#include <stdio.h>
#include <string.h>

#include "app.h"

// Set once while parsing options, before any worker thread fractures; read by
// whichever thread builds a tree. 0 = use the available memory.
static _Atomic uint64_t max_memory_bytes;

enum { MIB = 1 << 20 };
// 1 PiB: far beyond any machine, small enough that bytes fit in 64 bits.
#define MAX_MEMORY_MIB_LIMIT 1073741824ull

bool app_parse_max_memory(const char* command, const char* text) {
  uint64_t mib = 0;
  if (!option_u64(command, "--max-memory", text, 1, MAX_MEMORY_MIB_LIMIT, &mib)) return false;
  atomic_store(&max_memory_bytes, mib * MIB);
  return true;
}

// MemAvailable from /proc/meminfo in bytes: what can be allocated without
// swapping (free memory plus reclaimable caches). 0 when unknown.
static uint64_t available_bytes(void) {
  FILE* f = fopen("/proc/meminfo", "r");
  if (!f) return 0;
  char line[256] = {0};
  uint64_t kib = 0;
  while (fgets(line, sizeof line, f))
    if (sscanf(line, "MemAvailable: %" SCNu64 " kB", &kib) == 1) break;
  fclose(f);
  return kib * 1024u;
}

// "8.9 GiB", "312 MiB", "0.4 MiB": two significant figures at least.
static void format_bytes(uint64_t bytes, char* out, size_t size) {
  double mib = (double)bytes / MIB;
  if (mib >= 1024.0)
    snprintf(out, size, "%.1f GiB", mib / 1024.0);
  else if (mib >= 10.0)
    snprintf(out, size, "%.0f MiB", mib);
  else
    snprintf(out, size, "%.1f MiB", mib);
}

bool app_check_fracture_memory(const char* mesh_spec, const bk_mesh* source, const bk_fracture_def* desc,
                               bool saving, bk_error* err) {
  uint64_t explicit_limit = atomic_load(&max_memory_bytes);
  uint64_t limit = explicit_limit ? explicit_limit : available_bytes();
  if (limit == 0) return true; // nothing known to compare against
  uint64_t need = bk_mesh_tree_estimate_bytes(source, desc);
  uint64_t file = saving ? bk_mesh_tree_estimate_file_bytes(source, desc) : 0;
  need = need > UINT64_MAX - file ? UINT64_MAX : need + file;
  if (need <= limit) return true;

  char need_text[32] = {0}, limit_text[32] = {0};
  format_bytes(need, need_text, sizeof need_text);
  format_bytes(limit, limit_text, sizeof limit_text);
  // The mesh by its file name, shortened so that the message always fits whole.
  const char* name = strrchr(mesh_spec, '/');
  name = name ? name + 1 : mesh_spec;
  const char* ellipsis = strlen(name) > 120 ? "..." : "";
  // What sets the size: the pieces asked for, or the map or the points that replace them.
  char what[64] = "";
  if (desc->pattern == BK_PATTERN_CUTOUT && desc->cutout_width)
    snprintf(what, sizeof what, "the %u x %u cutout map", desc->cutout_width, desc->cutout_height);
  else if (desc->pattern == BK_PATTERN_VORONOI && desc->seed_points)
    snprintf(what, sizeof what, "%u seed points", desc->seed_point_count);
  else
    snprintf(what, sizeof what, "--pieces %u",
             desc->pieces ? desc->pieces : bk_default_fracture_def().pieces);
  if (explicit_limit)
    return bk_error_set(
        err, "%s on %.120s%s needs about %s%s, more than --max-memory allows (%" PRIu64 " MiB)", what, name,
        ellipsis, need_text, saving ? " with its cache file" : "", explicit_limit / MIB);
  return bk_error_set(err,
                      "%s on %.120s%s needs about %s%s, more than the %s available "
                      "(--max-memory MIB overrides)",
                      what, name, ellipsis, need_text, saving ? " with its cache file" : "", limit_text);
}

// Decoding a PNG holds the file, its inflated rows and the image at the
// file's channels and depth, then converts it to 8-bit grey (stb_image);
// the cutout build then adds its labels and queue (9 bytes a pixel with
// the grey pixels, as bk_mesh_tree_estimate_bytes counts them).
bool app_check_map_memory(const char* path, uint32_t width, uint32_t height, int channels, bool sixteen_bit,
                          uint64_t file_bytes, bk_error* err) {
  uint64_t explicit_limit = atomic_load(&max_memory_bytes);
  uint64_t limit = explicit_limit ? explicit_limit : available_bytes();
  if (limit == 0) return true;
  double pixels = (double)width * (double)height, sample = (double)channels * (sixteen_bit ? 2.0 : 1.0);
  double decode = (double)file_bytes + pixels * (2.0 * sample + channels + 1.0);
  double need = fmax(decode, 9.0 * pixels);
  if (need <= (double)limit) return true;
  char need_text[32] = {0}, limit_text[32] = {0};
  format_bytes(need >= 1.8e19 ? UINT64_MAX : (uint64_t)need, need_text, sizeof need_text);
  format_bytes(limit, limit_text, sizeof limit_text);
  if (explicit_limit)
    return bk_error_set(err,
                        "%s: the %u x %u map needs about %s to decode and use, more than --max-memory "
                        "allows (%" PRIu64 " MiB)",
                        path, width, height, need_text, explicit_limit / MIB);
  return bk_error_set(err,
                      "%s: the %u x %u map needs about %s to decode and use, more than the %s available "
                      "(--max-memory MIB overrides)",
                      path, width, height, need_text, limit_text);
}
