// Fuzzes the seed-point reader of `fracture --seeds` (seed_points_parse)
// straight from memory. An accepted text must give at least one point, every
// coordinate finite, and the points written back as text must read back the
// same; a refused one must get one line naming the input, and no points.
// Crashes, undefined behaviour and leaks are findings too.
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_util.h"
#include "seed_points.h"

const char bk_fuzz_harness[] = "fuzz_seeds";

// Larger inputs only slow the search down: every feature of the format fits in far less.
enum { FUZZ_SEEDS_MAX_BYTES = 1 << 16 };

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > FUZZ_SEEDS_MAX_BYTES) return 0;
  bk_vec3* points = NULL;
  uint32_t count = 0;
  bk_error err = {{0}};
  if (!seed_points_parse((const char*)data, size, "input.txt", &points, &count, &err)) {
    if (!err.message[0]) bk_fuzz_fail("refused without a message");
    if (strchr(err.message, '\n')) bk_fuzz_fail("message is not one line: %s", err.message);
    if (strncmp(err.message, "input.txt", 9) != 0)
      bk_fuzz_fail("message does not name the input: %s", err.message);
    if (points || count) bk_fuzz_fail("refused but left %u points behind", count);
    return 0;
  }
  if (count == 0 || !points) bk_fuzz_fail("accepted without points");
  // %.17g reads back exactly and is a plain decimal the reader must take.
  size_t capacity = (size_t)count * 3 * 26 + 1, used = 0;
  char* text = malloc(capacity);
  if (!text) bk_fuzz_fail("out of memory");
  for (uint32_t i = 0; i < count; ++i) {
    bk_vec3 p = points[i];
    if (!isfinite(p.x) || !isfinite(p.y) || !isfinite(p.z))
      bk_fuzz_fail("point %u is not finite: %g %g %g", i, p.x, p.y, p.z);
    used += (size_t)snprintf(text + used, capacity - used, "%.17g %.17g %.17g\n", p.x, p.y, p.z);
  }
  bk_vec3* again = NULL;
  uint32_t again_count = 0;
  if (!seed_points_parse(text, used, "written.txt", &again, &again_count, &err))
    bk_fuzz_fail("the points written back are refused: %s", err.message);
  if (again_count != count) bk_fuzz_fail("%u points read back as %u", count, again_count);
  for (uint32_t i = 0; i < count; ++i)
    if (again[i].x != points[i].x || again[i].y != points[i].y || again[i].z != points[i].z)
      bk_fuzz_fail("point %u changed when read back", i);
  free(text);
  free(again);
  free(points);
  return 0;
}
