// Fuzzes the .bkrec reader (recording_decode) straight from memory. A refused
// file must get one line naming the input and leave nothing allocated; an
// accepted one must hold what the reader promises (a scene first, steps in
// order, within the run) and encode back to exactly the same bytes. Each
// input is read twice: as it is (the header's checks), and with the header's
// size and checksum made right, so mutations reach the payload's parser.
// Crashes, undefined behaviour and leaks are findings too.
#include <stdlib.h>
#include <string.h>

#define XXH_INLINE_ALL
#include <xxhash.h>

#include "fuzz_util.h"
#include "recording.h"

const char bk_fuzz_harness[] = "fuzz_recording";

// Larger inputs only slow the search down: every feature of the format fits in far less.
enum { FUZZ_RECORDING_MAX_BYTES = 1 << 18 };

static void check(const uint8_t* data, size_t size) {
  recording rec = {{0}};
  bk_error err = {{0}};
  if (!recording_decode(data, size, "input.bkrec", &rec, &err)) {
    if (!err.message[0]) bk_fuzz_fail("refused without a message");
    if (strchr(err.message, '\n')) bk_fuzz_fail("message is not one line: %s", err.message);
    if (strncmp(err.message, "input.bkrec: ", 13) != 0)
      bk_fuzz_fail("message does not name the input: %s", err.message);
    if (rec.events || rec.scenes || rec.hashes) bk_fuzz_fail("refused but kept memory");
    return;
  }
  if (rec.event_count == 0 || rec.events[0].kind != RECORDING_SCENE || rec.events[0].step != 0)
    bk_fuzz_fail("accepted without a scene first");
  for (uint32_t i = 0; i < rec.event_count; ++i) {
    const recording_event* e = &rec.events[i];
    if (e->step >= rec.steps || (i > 0 && e->step < rec.events[i - 1].step))
      bk_fuzz_fail("event %u at step %llu is out of order or past the end", i, (unsigned long long)e->step);
    if (e->kind == RECORDING_SCENE && e->scene >= rec.scene_count) bk_fuzz_fail("event %u names no scene", i);
  }
  size_t again_size = 0;
  uint8_t* again = recording_encode(&rec, &again_size);
  if (again_size != size || memcmp(again, data, size) != 0)
    bk_fuzz_fail("an accepted file of %zu bytes encodes back to %zu other bytes", size, again_size);
  bk_free(again);
  recording_free(&rec);
}

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > FUZZ_RECORDING_MAX_BYTES) return 0;
  check(data, size);
  if (size < 32) return 0;
  uint8_t* fixed = malloc(size);
  if (!fixed) bk_fuzz_fail("out of memory");
  memcpy(fixed, data, size);
  uint64_t payload = size - 32, sum = XXH3_64bits(fixed + 32, payload);
  for (int i = 0; i < 8; ++i) {
    fixed[16 + i] = (uint8_t)(payload >> (8 * i));
    fixed[24 + i] = (uint8_t)(sum >> (8 * i));
  }
  check(fixed, size);
  free(fixed);
  return 0;
}
