// play --record DIR --record-every K and --camera X,Y,Z, run as a user
// would (the recordings under a virtual display: xvfb-run, Mesa's software
// OpenGL): the directory gets exactly the frames asked for, numbered from 0,
// each the window's size; an earlier recording's frames are replaced; bad
// values and a directory holding anything else are refused in one line
// naming the option, with nothing in the directory touched.
#include <dirent.h>
#include <stb_image.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define RUN_STDERR_PATH BK_TEST_TMP "/recorder_stderr.txt"
#include "run_exe.h"

#define DISPLAY_RUN "xvfb-run -a -s '-screen 0 1280x720x24' "

// Runs `args` under a virtual display (run_exe.h's run takes the executable first).
static run_result* run_windowed(const char* args) {
  static run_result result;
  char command[4096] = {0};
  snprintf(command, sizeof command, DISPLAY_RUN "'%s' %s 2>'%s'", BK_BREAKABLES_EXE, args, RUN_STDERR_PATH);
  FILE* pipe = popen(command, "r");
  ENSURE(pipe != NULL);
  run_read_all(pipe, result.out, sizeof result.out);
  int status = pclose(pipe);
  result.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  FILE* err = fopen(RUN_STDERR_PATH, "rb");
  ENSURE(err != NULL);
  run_read_all(err, result.err, sizeof result.err);
  fclose(err);
  if (result.status != 0)
    fprintf(stderr, "'%s' failed (%d):\n%s%s", args, result.status, result.out, result.err);
  return &result;
}

// A directory emptied (files only: the test makes no subdirectories) or made.
static void fresh_dir(const char* dir) {
  DIR* d = opendir(dir);
  if (d) {
    for (struct dirent* e = readdir(d); e; e = readdir(d)) {
      if (e->d_name[0] == '.') continue;
      char path[1024];
      snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
      ENSURE(remove(path) == 0);
    }
    closedir(d);
  } else {
    ENSURE(mkdir(dir, 0777) == 0);
  }
}

static int count_entries(const char* dir) {
  DIR* d = opendir(dir);
  ENSURE(d != NULL);
  int n = 0;
  for (struct dirent* e = readdir(d); e; e = readdir(d))
    n += strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0;
  closedir(d);
  return n;
}

static void write_text(const char* path, const char* text) {
  FILE* f = fopen(path, "wb");
  ENSURE(f != NULL);
  fputs(text, f);
  fclose(f);
}

static bool has_text(const char* path, const char* text) {
  char buffer[256] = {0};
  FILE* f = fopen(path, "rb");
  if (!f) return false;
  size_t n = fread(buffer, 1, sizeof buffer - 1, f);
  fclose(f);
  buffer[n] = 0;
  return strcmp(buffer, text) == 0;
}

static bool exists(const char* path) { return access(path, F_OK) == 0; }

// Every 3rd of 12 frames: frames 0, 3, 6, 9 as frame_00000 .. frame_00003,
// each 320x180; an earlier recording's frames (a higher number among them)
// are gone.
static void test_record_frames(void) {
  const char* dir = BK_TEST_TMP "/recorder_frames";
  fresh_dir(dir);
  write_text(BK_TEST_TMP "/recorder_frames/frame_00007.png", "an earlier recording's");
  char args[1024];
  snprintf(
      args, sizeof args,
      "play --scene wall --frames 12 --autofire 1 --record '%s' --record-every 3 --width 320 --height 180 "
      "--hide-panel",
      dir);
  run_result* r = run_windowed(args);
  ENSURE(r->status == 0);
  unsigned frames = 0;
  ENSURE_MSG(sscanf(r->out, "frames %u,", &frames) == 1 && frames == 12, "summary: %s", r->out);
  ENSURE_MSG(count_entries(dir) == 4, "%d files in %s, not 12 / 3 = 4", count_entries(dir), dir);
  for (int i = 0; i < 4; ++i) {
    char path[1024];
    snprintf(path, sizeof path, "%s/frame_%05d.png", dir, i);
    int w = 0, h = 0, channels = 0;
    ENSURE_MSG(stbi_info(path, &w, &h, &channels) == 1, "%s is not a picture", path);
    ENSURE_MSG(w == 320 && h == 180, "%s is %dx%d, not the window's 320x180", path, w, h);
  }
  ENSURE(!exists(BK_TEST_TMP "/recorder_frames/frame_00007.png"));
  // Every frame by default: 5 frames, 5 pictures, the 4 before replaced.
  snprintf(args, sizeof args, "play --scene wall --frames 5 --record '%s' --width 160 --height 90", dir);
  ENSURE(run_windowed(args)->status == 0);
  ENSURE(count_entries(dir) == 5);
  int w = 0, h = 0, channels = 0;
  ENSURE(stbi_info(BK_TEST_TMP "/recorder_frames/frame_00004.png", &w, &h, &channels) == 1 && w == 160);
}

// A bad option: exit status 2 and one line on stderr that names it.
static void expect_refused(const char* args, const char* option) {
  run_result* r = run(args);
  ENSURE_MSG(r->status == 2, "'%s' exited with %d", args, r->status);
  ENSURE_MSG(count_lines(r->err) == 1 && strstr(r->err, option) != NULL, "'%s' said: %s", args, r->err);
  ENSURE_MSG(r->out[0] == 0, "'%s' printed: %s", args, r->out);
}

static void test_bad_values(void) {
  const char* dir = BK_TEST_TMP "/recorder_bad";
  char args[1024];
  const char* const cases[][2] = {
      {"play --frames 10 --record '%s' --record-every 0", "--record-every"},
      {"play --frames 10 --record '%s' --record-every 1.5", "--record-every"},
      {"play --frames 10 --record '%s' --record-every 10000001", "--record-every"},
      {"play --frames 10 --record '%s' --record-every", "--record-every"},
      {"play --frames 10 --record-every 2 --screenshot '%s.png'", "--record-every"}, // without --record
      {"play --record '%s'", "--record"},                                            // without --frames
      {"play --frames 10 --record ''%s", "--record"},                                // an empty name
      {"play --frames 200000 --record '%s'", "--record"},                            // 200000 pictures
      {"play --frames 10 --record '%s/no/such' --record-every 2", "--record"},
      {"play --frames 10 --camera 1,2 --screenshot '%s.png'", "--camera"},
      {"play --frames 10 --camera 1,2,3,4 --screenshot '%s.png'", "--camera"},
      {"play --frames 10 --camera 1,x,3 --screenshot '%s.png'", "--camera"},
      {"play --frames 10 --camera 0,1001,0 --screenshot '%s.png'", "--camera"},
  };
  for (size_t i = 0; i < sizeof cases / sizeof *cases; ++i) {
    remove(dir);
    snprintf(args, sizeof args, cases[i][0], i == 6 ? "" : dir);
    expect_refused(args, cases[i][1]);
    ENSURE_MSG(!exists(dir), "'%s' made %s", args, dir);
  }
  // The help states the options and their ranges.
  run_result* help = run("play --help");
  ENSURE(help->status == 0 && strstr(help->out, "--record DIR") && strstr(help->out, "--record-every K") &&
         strstr(help->out, "1..10000000") && strstr(help->out, "--camera X,Y,Z") &&
         strstr(help->out, "-1000..1000 m"));
  // Not a directory: the file is left as it was.
  write_text(dir, "a file");
  snprintf(args, sizeof args, "play --frames 10 --record '%s'", dir);
  expect_refused(args, "--record");
  ENSURE(has_text(dir, "a file"));
  remove(dir);
}

// A directory holding anything but frame_*.png files is refused whole: the
// user's file and the frames beside it stay as they were.
static void test_other_files(void) {
  const char* dir = BK_TEST_TMP "/recorder_other";
  fresh_dir(dir);
  write_text(BK_TEST_TMP "/recorder_other/notes.txt", "keep me");
  write_text(BK_TEST_TMP "/recorder_other/frame_00000.png", "kept too");
  char args[1024];
  snprintf(args, sizeof args, "play --scene wall --frames 4 --record '%s'", dir);
  expect_refused(args, "--record");
  ENSURE(strstr(run_result_storage.err, "notes.txt") != NULL);
  ENSURE(count_entries(dir) == 2);
  ENSURE(has_text(BK_TEST_TMP "/recorder_other/notes.txt", "keep me"));
  ENSURE(has_text(BK_TEST_TMP "/recorder_other/frame_00000.png", "kept too"));
  // So is a directory among the frames.
  fresh_dir(dir);
  ENSURE(mkdir(BK_TEST_TMP "/recorder_other/frame_00001.png", 0777) == 0);
  expect_refused(args, "--record");
  ENSURE(exists(BK_TEST_TMP "/recorder_other/frame_00001.png"));
  ENSURE(rmdir(BK_TEST_TMP "/recorder_other/frame_00001.png") == 0);
}

// The picture's pixels, for comparing two runs.
static unsigned char* load(const char* path, int* size) {
  int w = 0, h = 0, channels = 0;
  unsigned char* pixels = stbi_load(path, &w, &h, &channels, 3);
  ENSURE_MSG(pixels != NULL, "cannot read %s", path);
  *size = w * h * 3;
  return pixels;
}

// --camera at the scene's own camera (the wall's: 0.5,1.0,2.3) draws the
// same picture as no --camera; elsewhere, another.
static void test_camera(void) {
  const char* names[3] = {BK_TEST_TMP "/recorder_cam_default.png", BK_TEST_TMP "/recorder_cam_same.png",
                          BK_TEST_TMP "/recorder_cam_other.png"};
  const char* cameras[3] = {"", "--camera 0.5,1.0,2.3", "--camera -1.5,2,2.5"};
  unsigned char* pixels[3] = {NULL, NULL, NULL};
  int sizes[3] = {0, 0, 0};
  for (int i = 0; i < 3; ++i) {
    char args[1024];
    snprintf(args, sizeof args, "play --scene wall --frames 2 %s --width 320 --height 180 --screenshot '%s'",
             cameras[i], names[i]);
    ENSURE(run_windowed(args)->status == 0);
    pixels[i] = load(names[i], &sizes[i]);
  }
  ENSURE(sizes[0] == sizes[1] && sizes[0] == sizes[2]);
  int differ_same = 0, differ_other = 0;
  for (int k = 0; k < sizes[0]; ++k) {
    differ_same += abs(pixels[0][k] - pixels[1][k]) > 2;
    differ_other += abs(pixels[0][k] - pixels[2][k]) > 2;
  }
  ENSURE_MSG(differ_same == 0, "the scene's own camera drew another picture (%d bytes differ)", differ_same);
  ENSURE_MSG(differ_other > sizes[0] / 10,
             "another camera drew nearly the same picture (%d of %d bytes differ)", differ_other, sizes[0]);
  for (int i = 0; i < 3; ++i)
    stbi_image_free(pixels[i]);
}

int main(void) {
  RUN(test_bad_values);
  RUN(test_other_files);
  RUN(test_record_frames);
  RUN(test_camera);
  return 0;
}
