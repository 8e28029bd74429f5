// play --record DIR [--record-every K]: a scripted run's frames as numbered
// PNG files, for an animation made from them (scripts/make_hero.sh). The
// directory is the recording's alone: one holding anything else is refused,
// so that nothing the user had there is overwritten or mixed in. And
// --camera X,Y,Z: where its pictures are seen from.
#include <dirent.h>
#include <errno.h>
#include <fnmatch.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "recorder.h"

app_recorder default_recorder(void) { return (app_recorder){.dir = NULL, .every = 1}; }

// X,Y,Z: exactly three plain decimal numbers, each within BK_CAMERA_MAX.
static bool parse_camera(const char* command, const char* text, bk_vec3* out) {
  double xyz[3] = {0.0, 0.0, 0.0};
  const char* p = text;
  bool ok = true;
  for (int k = 0; k < 3 && ok; ++k) {
    size_t length = strcspn(p, ",");
    char part[64] = "";
    ok = length < sizeof part && (k < 2 ? p[length] == ',' : p[length] == '\0');
    snprintf(part, sizeof part, "%.*s", (int)(length < sizeof part ? length : 0), p);
    ok = ok && parse_double(part, -BK_CAMERA_MAX, BK_CAMERA_MAX, &xyz[k]);
    p += length + (p[length] == ',');
  }
  if (ok) {
    *out = bk_v3(xyz[0], xyz[1], xyz[2]);
    return true;
  }
  char shown[96] = "", limit[32] = "";
  quote_text(text, shown, sizeof shown);
  format_number(BK_CAMERA_MAX, limit, sizeof limit);
  fprintf(stderr, "breakables %s: --camera '%s' is not X,Y,Z (three decimal numbers, each -%s..%s m)\n",
          command, shown, limit, limit);
  return false;
}

int parse_record_option(const char* command, int argc, char** argv, int* i, app_recorder* recorder) {
  static const char* const names[] = {"--record", "--record-every", "--camera"};
  const char* arg = argv[*i];
  const char* value = NULL;
  int which = take_option(command, argc, argv, i, names, 3, &value);
  if (which < 0) return which == -1 ? 1 : 2;
  if (which == 2) {
    recorder->camera_given = true;
    return parse_camera(command, value, &recorder->camera) ? 0 : 2;
  }
  if (which == 1) {
    recorder->every_given = true;
    return option_u64(command, arg, value, 1, 10000000, &recorder->every) ? 0 : 2;
  }
  if (value[0] == '\0') {
    fprintf(stderr, "breakables %s: --record needs a directory, not an empty name\n", command);
    return 2;
  }
  recorder->dir = value;
  return 0;
}

static bool is_frame_name(const char* name) { return fnmatch("frame_*.png", name, 0) == 0; }

// The directory's entries: false (one line printed) at the first one that is
// not a regular frame_*.png file; `clear` deletes those, once all passed.
static bool scan_frames(const char* command, const char* dir, const char* shown, bool clear) {
  DIR* d = opendir(dir);
  if (!d) {
    fprintf(stderr, "breakables %s: --record '%s': cannot read the directory (%s)\n", command, shown,
            strerror(errno));
    return false;
  }
  bool ok = true;
  for (struct dirent* e = readdir(d); ok && e; e = readdir(d)) {
    if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0) continue;
    char path[4352] = "", name[96] = "";
    struct stat s = {0};
    snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
    if (!is_frame_name(e->d_name) || lstat(path, &s) != 0 || !S_ISREG(s.st_mode)) {
      quote_text(e->d_name, name, sizeof name);
      fprintf(stderr,
              "breakables %s: --record '%s' holds '%s', not an earlier recording's frame_*.png: "
              "give an empty or new directory\n",
              command, shown, name);
      ok = false;
    } else if (clear && unlink(path) != 0) {
      quote_text(e->d_name, name, sizeof name);
      fprintf(stderr, "breakables %s: --record '%s': cannot remove the earlier '%s' (%s)\n", command, shown,
              name, strerror(errno));
      ok = false;
    }
  }
  closedir(d);
  return ok;
}

bool recorder_prepare(const char* command, app_recorder* recorder, uint32_t frames) {
  if (!recorder->dir) {
    if (!recorder->every_given) return true;
    fprintf(stderr, "breakables %s: --record-every needs --record DIR (see 'breakables %s --help')\n",
            command, command);
    return false;
  }
  // An interactive run has no end: its frames would fill the disk.
  if (frames == 0) {
    fprintf(stderr, "breakables %s: --record needs --frames N (a scripted run)\n", command);
    return false;
  }
  uint64_t pictures = (frames + recorder->every - 1) / recorder->every;
  if (pictures > BK_RECORD_PICTURES_MAX) {
    fprintf(stderr,
            "breakables %s: --record would write %llu pictures, more than %d (raise --record-every or "
            "lower --frames)\n",
            command, (unsigned long long)pictures, BK_RECORD_PICTURES_MAX);
    return false;
  }
  const char* dir = recorder->dir;
  char shown[96] = "";
  quote_text(dir, shown, sizeof shown);
  if (strlen(dir) > 4096) {
    fprintf(stderr, "breakables %s: --record '%s': the path is too long\n", command, shown);
    return false;
  }
  struct stat s = {0};
  if (stat(dir, &s) != 0) {
    if (errno != ENOENT || mkdir(dir, 0777) != 0) {
      fprintf(stderr, "breakables %s: --record '%s': cannot make the directory (%s)\n", command, shown,
              strerror(errno));
      return false;
    }
  } else if (!S_ISDIR(s.st_mode)) {
    fprintf(stderr, "breakables %s: --record '%s' is not a directory\n", command, shown);
    return false;
  }
  // The mode bits decide (bk_file_check_write), as for every output: root
  // could write anywhere, but a directory made read-only is left alone.
  char first[4352] = "";
  snprintf(first, sizeof first, "%s/frame_00000.png", dir);
  bk_error err = {0};
  if (!bk_file_check_write(first, &err)) {
    fprintf(stderr, "breakables %s: --record '%s': cannot write there (%s)\n", command, shown, err.message);
    return false;
  }
  // Checked whole before anything is removed: a refusal leaves it as it was.
  return scan_frames(command, dir, shown, false) && scan_frames(command, dir, shown, true);
}

bool recorder_frame(app_recorder* recorder, app_renderer* renderer, uint32_t frame, int width, int height,
                    bk_error* err) {
  if (!recorder->dir || frame % recorder->every != 0) return true;
  char path[4352] = "";
  snprintf(path, sizeof path, "%s/frame_%05u.png", recorder->dir, recorder->written);
  if (!renderer_screenshot(renderer, width, height, path, err)) return false;
  recorder->written++;
  return true;
}
