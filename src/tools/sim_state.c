// sim's state options: the world saved to a file after --at steps
// (bk_world_save_state), or loaded from one before the first step.
#include "sim_state.h"

#include <inttypes.h>
#include <string.h>
#include <time.h>

#include "app.h"

const char* const sim_state_help =
    "  --save-state F.bkstate  write the world's state (bk_world_save_state) after --at steps\n"
    "  --at STEP        the steps before --save-state saves, 0..--steps (default: all of them)\n"
    "  --load-state F.bkstate  start from a saved state (saved with the same scene options;\n"
    "                   a state of other trees is refused); no scripted shots unless --shots;\n"
    "                   --steps 0 reports the loaded state's hashes\n";

sim_state sim_state_default(void) { return (sim_state){0}; }

static double cpu_ms(void) {
  struct timespec t = {0};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

int sim_state_parse(int argc, char** argv, int* i, sim_state* s) {
  const char* arg = argv[*i];
  bool save = strcmp(arg, "--save-state") == 0, load = strcmp(arg, "--load-state") == 0;
  bool at = strcmp(arg, "--at") == 0;
  if (!save && !load && !at) return 1;
  if (*i + 1 >= argc) {
    fprintf(stderr, "breakables sim: %s needs a value\n", arg);
    return 2;
  }
  const char* value = argv[++*i];
  if (save) s->save_path = value;
  if (load) s->load_path = value;
  if (at) {
    if (!option_u64("sim", arg, value, 0, 1000000, &s->at)) return 2;
    s->at_given = true;
  }
  return 0;
}

int sim_state_check(sim_state* s, uint64_t steps) {
  if (s->at_given && !s->save_path) {
    fprintf(stderr, "breakables sim: --at needs --save-state\n");
    return 2;
  }
  if (s->at_given && s->at > steps) {
    fprintf(stderr, "breakables sim: --at %" PRIu64 " is past the run's %" PRIu64 " steps\n", s->at, steps);
    return 2;
  }
  if (steps == 0 && !s->load_path) {
    fprintf(stderr, "breakables sim: --steps 0 needs --load-state (the state to report)\n");
    return 2;
  }
  if (!s->at_given) s->at = steps;
  return 0;
}

bool sim_state_load(sim_state* s, bk_world* world) {
  if (!s->load_path) return true;
  void* data = NULL;
  size_t size = 0;
  bk_error err = {0};
  bool ok = bk_file_read(s->load_path, (uint64_t)1 << 32, "4 GiB", &data, &size, &err);
  double start = cpu_ms();
  ok = ok && bk_world_load_state(world, data, size, &err);
  s->load_ms = cpu_ms() - start;
  bk_free(data);
  if (!ok) fprintf(stderr, "breakables sim: --load-state %s: %s\n", s->load_path, err.message);
  return ok;
}

static const bk_atomic_messages write_messages = {"cannot create a temporary file beside it",
                                                  "cannot write the state", "cannot replace it"};

bool sim_state_after(sim_state* s, const bk_world* world, uint64_t done) {
  if (!s->save_path || done != s->at || s->bytes) return true;
  bk_error err = {0};
  double start = cpu_ms();
  size_t size = bk_world_state_size(world);
  uint8_t* data = bk_alloc(size + 1u);
  bool ok = bk_world_save_state(world, data, size, &err) == size;
  s->save_ms = cpu_ms() - start;
  bk_atomic_file file = {0};
  if (ok) ok = bk_file_begin_atomic(s->save_path, &write_messages, &file, &err);
  if (ok) {
    fwrite(data, 1, size, file.stream); // a short write leaves the stream in error, which commit reports
    ok = bk_file_commit_atomic(&file, s->save_path, &write_messages, &err);
  }
  bk_free(data);
  if (!ok) {
    fprintf(stderr, "breakables sim: --save-state %s: %s\n", s->save_path, err.message);
    s->failed = true;
    return false;
  }
  s->bytes = size;
  return true;
}

void sim_state_json(const sim_state* s, FILE* out) {
  if (s->save_path) fprintf(out, "\"state_bytes\": %zu, \"state_save_ms\": %.3f, ", s->bytes, s->save_ms);
  if (s->load_path) fprintf(out, "\"state_load_ms\": %.3f, ", s->load_ms);
}
