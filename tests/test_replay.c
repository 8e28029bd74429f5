// Record and replay (.bkrec): a replay gives the state and world hash of its
// recording at every step (sim, and the game under a virtual display); a
// recording whose shot was edited parts from it at the step of that shot and
// says so in one line; damaged or hostile files are refused in one line
// without a crash; a recording never overwrites what the run reads.
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define RUN_STDERR_PATH BK_TEST_TMP "/replay_stderr.txt"
#include "run_exe.h"

#include "cli_util.h"
#include "recording.h"
#include "scenes.h"

#define TMP BK_TEST_TMP "/replay_"

// The "step S state_hash H world_hash W" lines of an output, in order.
static char* hash_lines(const char* text, uint32_t* count) {
  size_t size = strlen(text) + 1, used = 0;
  char* out = calloc(1, size);
  *count = 0;
  for (const char* p = text; *p;) {
    const char* end = strchr(p, '\n');
    size_t n = end ? (size_t)(end - p) + 1 : strlen(p);
    if (strncmp(p, "step ", 5) == 0) memcpy(out + used, p, n), used += n, (*count)++;
    p += n;
  }
  return out;
}

static char* json_hashes(const char* json) {
  static char both[64];
  const char* s = strstr(json, "\"state_hash\": \"");
  const char* w = strstr(json, "\"world_hash\": \"");
  ENSURE_MSG(s && w, "no hashes in %s", json);
  snprintf(both, sizeof both, "%.16s %.16s", s + 15, w + 15);
  return both;
}

static void read_recording(const char* path, recording* rec) {
  bk_error err = {0};
  ENSURE_MSG(recording_read(path, rec, &err), "%s", err.message);
}

static void test_wall_every_step(void) {
  remove(TMP "wall.bkrec");
  run_result* r = run("sim --scene wall --record " TMP "wall.bkrec --hash-every 1");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  uint32_t recorded_count = 0, replayed_count = 0;
  char* recorded = hash_lines(r->out, &recorded_count);
  r = run("sim --replay " TMP "wall.bkrec --hash-every 1");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  char* replayed = hash_lines(r->out, &replayed_count);
  ENSURE_MSG(recorded_count == 300 && replayed_count == 300, "%u and %u lines", recorded_count,
             replayed_count);
  ENSURE(strcmp(recorded, replayed) == 0); // every step's state and world hash
  free(recorded), free(replayed);
  // The end's hashes in the JSON, and the hashes checked at every step.
  r = run("sim --scene wall --json");
  char plain[64];
  snprintf(plain, sizeof plain, "%s", json_hashes(r->out));
  r = run("sim --replay " TMP "wall.bkrec --json");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  ENSURE_MSG(strcmp(json_hashes(r->out), plain) == 0, "%s vs %s", json_hashes(r->out), plain);
  ENSURE(json_number(r->out, "replay_steps_checked") == 300);
  ENSURE(json_number(r->out, "shots") == 3);
  // The same run recorded again gives the same bytes.
  remove(TMP "wall2.bkrec");
  r = run("sim --scene wall --record " TMP "wall2.bkrec");
  ENSURE(r->status == 0);
  size_t a_size = 0, b_size = 0;
  void *a = NULL, *b = NULL;
  bk_error err = {0};
  ENSURE(bk_file_read(TMP "wall.bkrec", 1 << 20, "1 MiB", &a, &a_size, &err));
  ENSURE(bk_file_read(TMP "wall2.bkrec", 1 << 20, "1 MiB", &b, &b_size, &err));
  ENSURE(a_size == b_size && memcmp(a, b, a_size) == 0);
  bk_free(a), bk_free(b);
}

static void test_volley_and_weight(void) {
  remove(TMP "volley.bkrec");
  run_result* r =
      run("sim --scene wall --shots 5 --volley 100 --drop 2000 --record " TMP "volley.bkrec --json");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  char recorded[64];
  snprintf(recorded, sizeof recorded, "%s", json_hashes(r->out));
  recording rec = {0};
  read_recording(TMP "volley.bkrec", &rec);
  uint32_t fires = 0, weights = 0;
  for (uint32_t i = 0; i < rec.event_count; ++i) {
    fires += rec.events[i].kind == RECORDING_FIRE;
    weights += rec.events[i].kind == RECORDING_WEIGHT;
    if (rec.events[i].kind == RECORDING_FIRE) ENSURE(rec.events[i].step < 100); // the volley's
    if (rec.events[i].kind == RECORDING_WEIGHT)
      ENSURE(rec.events[i].step == 60 && rec.events[i].weight.kg == 2000);
  }
  ENSURE(fires == 5 && weights == 1 && rec.steps == 300 && rec.has_hashes);
  ENSURE(strcmp(rec.scenes[0].name, "wall") == 0);
  recording_free(&rec);
  r = run("sim --replay " TMP "volley.bkrec --json");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  ENSURE(strcmp(json_hashes(r->out), recorded) == 0);
  ENSURE(json_number(r->out, "shots") == 5);
  ENSURE(json_number(r->out, "replay_steps_checked") == 300);
  // The hashes differ from a run without the weight: it was replayed.
  r = run("sim --scene wall --shots 5 --volley 100 --json");
  ENSURE(strcmp(json_hashes(r->out), recorded) != 0);
}

// The third shot moved a little: the replay parts at that shot's step.
static void test_edited_shot(void) {
  recording rec = {0};
  read_recording(TMP "volley.bkrec", &rec);
  uint64_t step = 0;
  for (uint32_t i = 0, seen = 0; i < rec.event_count; ++i)
    if (rec.events[i].kind == RECORDING_FIRE && ++seen == 3) {
      rec.events[i].fire.velocity.y += 0.5;
      step = rec.events[i].step;
    }
  bk_error err = {0};
  ENSURE_MSG(recording_write(&rec, TMP "edited.bkrec", &err), "%s", err.message);
  recording_free(&rec);
  char message[96];
  snprintf(message, sizeof message, "replay: step %llu differs: ", (unsigned long long)step + 1);
  expect_error("sim --replay " TMP "edited.bkrec", 1, message);
}

static void write_bytes(const char* path, const uint8_t* data, size_t size) {
  FILE* f = fopen(path, "wb");
  ENSURE(f != NULL);
  ENSURE(fwrite(data, 1, size, f) == size);
  fclose(f);
}

// The recording re-encoded with one change (the checksum made right).
static void write_changed(recording* rec, const char* path) {
  size_t size = 0;
  uint8_t* data = recording_encode(rec, &size);
  write_bytes(path, data, size);
  bk_free(data);
}

static void test_hostile(void) {
  void* file = NULL;
  size_t size = 0;
  bk_error err = {0};
  ENSURE(bk_file_read(TMP "volley.bkrec", 1 << 20, "1 MiB", &file, &size, &err));
  uint8_t* bytes = file;
  const char* bad = TMP "bad.bkrec";
  const char* replay_bad = "sim --replay " TMP "bad.bkrec";
  // Truncated anywhere: in the header, in the events, in the hashes.
  size_t cuts[] = {0, 1, 7, 8, 20, 31, 32, 33, 40, 100, 200, size / 2, size - 16, size - 1};
  for (size_t k = 0; k < sizeof cuts / sizeof *cuts; ++k) {
    write_bytes(bad, bytes, cuts[k]);
    expect_error(replay_bad, 1, "truncated");
  }
  // A byte flipped: the header's fields or the payload's checksum.
  size_t flips[] = {0, 5, 8, 12, 16, 22, 24, 32, 50, size / 2, size - 1};
  for (size_t k = 0; k < sizeof flips / sizeof *flips; ++k) {
    uint8_t* copy = malloc(size);
    memcpy(copy, bytes, size);
    copy[flips[k]] ^= 0x40;
    write_bytes(bad, copy, size);
    const char* why = flips[k] < 8     ? "not a recording (bad magic)"
                      : flips[k] < 12  ? "is not supported"
                      : flips[k] < 16  ? "byte-order"
                      : flips[k] == 16 ? "trailing bytes: the header says" // a smaller payload
                      : flips[k] < 24  ? "larger than a recording may be"
                                       : "checksum mismatch";
    expect_error(replay_bad, 1, why);
    free(copy);
  }
  // Another version.
  uint8_t* copy = malloc(size);
  memcpy(copy, bytes, size);
  copy[8] = 2;
  write_bytes(bad, copy, size);
  expect_error(replay_bad, 1, "version 2 is not supported");
  free(copy);
  bk_free(file);
  // Valid checksums over bad contents: an unknown event, a step out of
  // order, a NaN, a value out of range, an event past the end.
  recording rec = {0};
  read_recording(TMP "volley.bkrec", &rec);
  uint32_t fire = 2; // after the scene and the focus
  ENSURE(rec.events[fire].kind == RECORDING_FIRE && rec.events[fire].step > 0);
  recording_kind kind = rec.events[fire].kind;
  rec.events[fire].kind = (recording_kind)99;
  write_changed(&rec, bad);
  expect_error(replay_bad, 1, "event 2 is of an unknown kind (99)");
  rec.events[fire].kind = kind;
  uint64_t step = rec.events[fire + 1].step;
  rec.events[fire + 1].step = 0;
  write_changed(&rec, bad);
  expect_error(replay_bad, 1, "event 3: step 0 out of order");
  rec.events[fire + 1].step = step;
  double speed = rec.events[fire].fire.velocity.x;
  rec.events[fire].fire.velocity.x = NAN;
  write_changed(&rec, bad);
  expect_error(replay_bad, 1, "a shot's velocity is NaN");
  rec.events[fire].fire.velocity.x = speed;
  rec.scenes[0].options.copies = 0;
  write_changed(&rec, bad);
  expect_error(replay_bad, 1, "copies is out of range");
  rec.scenes[0].options.copies = 1;
  rec.events[rec.event_count - 1].step = rec.steps;
  write_changed(&rec, bad);
  expect_error(replay_bad, 1, "past the run's end");
  recording_free(&rec);
  // Not a recording at all, and no file.
  write_file("replay_text.bkrec", "step 1 state_hash 0 world_hash 0\nstep 2 state_hash 0 world_hash 0\n");
  expect_error("sim --replay " TMP "text.bkrec", 1, "not a recording (bad magic)");
  expect_error("sim --replay " TMP "missing.bkrec", 1, "missing.bkrec");
}

static void test_files(void) {
  // Never over what the run reads, only to .bkrec, and no scene options with a replay.
  write_file("replay_model.bkrec", "not a model");
  expect_error("sim --mesh " TMP "model.bkrec --record " TMP "model.bkrec", 1, "refusing to overwrite");
  expect_error("sim --scene wall --record " TMP "wall.txt", 1, "must end in .bkrec");
  expect_error("sim --replay " TMP "wall.bkrec --export-obj " TMP "wall.bkrec", 1, ".obj");
  expect_error("sim --replay " TMP "wall.bkrec --pieces 12", 2, "'--pieces' cannot be given with it");
  expect_error("sim --replay " TMP "wall.bkrec --shots 2", 2, "'--shots' cannot be given with it");
  expect_error("sim --replay " TMP "wall.bkrec --record " TMP "again.bkrec", 2, "cannot be used together");
  expect_error("sim --record", 2, "--record");
  expect_error("sim --scene wall --record " TMP "x.bkrec --load-state " TMP "x.bkstate", 2,
               "--record and --load-state cannot be used together");
}

// What the game's panel changes (a material by one setter and by a whole
// material, stress, the budget) and where its camera is, written into a
// recording without hashes: sim and the game replay them alike, and they
// change the run.
static const char* const panel_recording = TMP "panel.bkrec";

static void insert_event(recording* rec, const recording_event* e) {
  recording_add(rec, e);
  uint32_t i = rec->event_count - 1;
  for (; i > 0 && rec->events[i - 1].step > e->step; --i)
    rec->events[i] = rec->events[i - 1];
  rec->events[i] = *e;
}

// The volley's recording without hashes plus panel event `which` (0..3; 4: the
// focus, with the budget of 3), or all of them (-1).
static void write_panel_recording(int which) {
  recording rec = {0};
  read_recording(TMP "volley.bkrec", &rec);
  rec.has_hashes = false;
  bk_material stone = *bk_material_find("stone");
  stone.frailty *= 4.0;
  recording_event events[5] = {
      {.step = 30, .kind = RECORDING_MATERIAL},
      {.step = 40, .kind = RECORDING_MATERIAL},
      {.step = 45, .kind = RECORDING_STRESS, .stress = false},
      {.step = 50, .kind = RECORDING_BUDGET, .budget_ms = 0.05},
      {.step = 55, .kind = RECORDING_FOCUS, .focus = {3.0, 1.0, 5.0}},
  };
  const bk_material* materials[2] = {bk_material_find("glass"), &stone};
  recording_setter setters[2] = {RECORDING_SET_MATERIAL, RECORDING_SET_FRAILTY};
  for (int k = 0; k < 2; ++k) {
    recording_add_material(&rec, events[k].step, 0, setters[k], materials[k]);
    events[k] = rec.events[--rec.event_count];
  }
  for (int k = 0; k < 5; ++k)
    if (which < 0 || which == k || (which == 4 && k == 3)) insert_event(&rec, &events[k]);
  write_changed(&rec, panel_recording);
  recording_free(&rec);
}

static void test_panel_events(void) {
  run_result* r = run("sim --replay " TMP "volley.bkrec --json");
  char plain[64];
  snprintf(plain, sizeof plain, "%s", json_hashes(r->out));
  // Each changes the run (the focus: what a tight budget spares).
  char budget_only[64] = "";
  for (int which = 0; which <= 5; ++which) {
    write_panel_recording(which == 5 ? -1 : which);
    r = run("sim --replay " TMP "panel.bkrec --json");
    ENSURE_MSG(r->status == 0, "%s", r->err);
    ENSURE(json_number(r->out, "replay_steps_checked") == 0); // no hashes to check
    const char* against = which == 4 ? budget_only : plain;
    ENSURE_MSG(strcmp(json_hashes(r->out), against) != 0, "panel event %d changed nothing", which);
    if (which == 3) snprintf(budget_only, sizeof budget_only, "%s", json_hashes(r->out));
  }
}

// The game: a scripted run with autofire recorded, played back, the same
// hashes at the end (and every step checked on the way).
static char game_out[1 << 14];
static int play(const char* args) {
  char command[2048];
  snprintf(command, sizeof command, "xvfb-run -a -s '-screen 0 1280x720x24' '%s' %s 2>'%s'",
           BK_BREAKABLES_EXE, args, RUN_STDERR_PATH);
  FILE* pipe = popen(command, "r");
  ENSURE(pipe != NULL);
  size_t n = fread(game_out, 1, sizeof game_out - 1, pipe);
  game_out[n] = 0;
  int status = pclose(pipe);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

static void game_hashes(char out[64]) {
  const char* at = strstr(game_out, "state_hash ");
  ENSURE_MSG(at != NULL, "no hashes in %s", game_out);
  snprintf(out, 64, "%.63s", at);
  char* newline = strchr(out, '\n');
  if (newline) *newline = 0;
  char* steps = strstr(out, " steps");
  ENSURE(steps != NULL);
  *steps = 0;
}

static void test_game(void) {
  if (system("command -v xvfb-run >/dev/null 2>&1") != 0) {
    fprintf(stderr, "xvfb-run is missing: scripts/setup.sh installs it\n");
    exit(1);
  }
  remove(TMP "game.bkrec");
  const char* small = "--width 320 --height 180 --hide-panel --hide-hud";
  char args[1024];
  snprintf(args, sizeof args, "play --scene wall --frames 300 --autofire 3 --record-input %sgame.bkrec %s",
           TMP, small);
  ENSURE_MSG(play(args) == 0, "%s", game_out);
  char recorded[64], replayed[64];
  game_hashes(recorded);
  ENSURE(strstr(game_out, "steps 300 recorded") != NULL);
  recording rec = {0};
  read_recording(TMP "game.bkrec", &rec);
  uint32_t fires = 0;
  for (uint32_t i = 0; i < rec.event_count; ++i)
    fires += rec.events[i].kind == RECORDING_FIRE;
  ENSURE(fires == 3 && rec.steps == 300 && rec.has_hashes);
  recording_free(&rec);
  snprintf(args, sizeof args, "play --replay %sgame.bkrec --frames 300 %s", TMP, small);
  ENSURE_MSG(play(args) == 0, "%s", game_out);
  game_hashes(replayed);
  ENSURE_MSG(strcmp(recorded, replayed) == 0, "%s vs %s", recorded, replayed);
  // sim replays the game's recording the same way, and the game sim's.
  run_result* r = run("sim --replay " TMP "game.bkrec --json");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  ENSURE(json_number(r->out, "replay_steps_checked") == 300);
  snprintf(args, sizeof args, "play --replay %svolley.bkrec --frames 300 %s", TMP, small);
  ENSURE_MSG(play(args) == 0, "%s", game_out);
  game_hashes(replayed);
  r = run("sim --replay " TMP "volley.bkrec --json");
  char sim_hashes[64];
  snprintf(sim_hashes, sizeof sim_hashes, "state_hash %.16s world_hash %.16s", json_hashes(r->out),
           json_hashes(r->out) + 17);
  ENSURE_MSG(strcmp(sim_hashes, replayed) == 0, "%s vs %s", sim_hashes, replayed);
  // The panel's changes, the same in the game as in sim.
  r = run("sim --replay " TMP "panel.bkrec --json");
  snprintf(sim_hashes, sizeof sim_hashes, "state_hash %.16s world_hash %.16s", json_hashes(r->out),
           json_hashes(r->out) + 17);
  snprintf(args, sizeof args, "play --replay %spanel.bkrec --frames 300 %s", TMP, small);
  ENSURE_MSG(play(args) == 0, "%s", game_out);
  game_hashes(replayed);
  ENSURE_MSG(strcmp(sim_hashes, replayed) == 0, "%s vs %s", sim_hashes, replayed);
  // A scene switch (a number key, or the panel's reset) at step 150: the
  // game loads the pillar there and runs it as sim runs it alone; sim
  // cannot switch, and says so.
  read_recording(TMP "volley.bkrec", &rec);
  rec.has_hashes = false;
  recording_scene pillar = rec.scenes[0];
  snprintf(pillar.name, sizeof pillar.name, "pillar");
  recording_add_scene(&rec, 150, &pillar);
  recording_add(&rec,
                &(recording_event){.step = 150, .kind = RECORDING_FOCUS, .focus = scene_find("pillar")->eye});
  rec.steps = 300;
  write_changed(&rec, TMP "switch.bkrec");
  recording_free(&rec);
  expect_error("sim --replay " TMP "switch.bkrec", 1,
               "the scene changes at step 150 (only play replays that)");
  r = run("sim --scene pillar --shots 0 --steps 150 --json");
  snprintf(sim_hashes, sizeof sim_hashes, "state_hash %.16s world_hash %.16s", json_hashes(r->out),
           json_hashes(r->out) + 17);
  snprintf(args, sizeof args, "play --replay %sswitch.bkrec --frames 300 %s", TMP, small);
  ENSURE_MSG(play(args) == 0, "%s", game_out);
  game_hashes(replayed);
  ENSURE_MSG(strcmp(sim_hashes, replayed) == 0, "%s vs %s", sim_hashes, replayed);
  // The game refuses what would change the run with a replay.
  snprintf(args, sizeof args, "play --replay %sgame.bkrec --frames 10 --autofire 2 %s", TMP, small);
  ENSURE(play(args) == 2);
}

int main(void) {
  setenv("BREAKABLES_CACHE_DIR", BK_TEST_TMP "/cache", 1);
  RUN(test_wall_every_step);
  RUN(test_volley_and_weight);
  RUN(test_edited_shot);
  RUN(test_hostile);
  RUN(test_files);
  RUN(test_panel_events);
  RUN(test_game);
  printf("replay ok\n");
  return 0;
}
