// Internal to the executable: a scripted run's pictures: recorded picture
// by picture (play --record DIR), for animations made from its frames, and
// seen from where the command line puts the camera (--camera).
#pragma once

#include "app.h"
#include "render.h"

/// At most this many pictures a recording (frame_00000.png .. frame_99999.png:
/// names of one width sort in frame order, and 1280x720 frames take about
/// 1 MB each).
enum { BK_RECORD_PICTURES_MAX = 100000 };

/// --camera's coordinates: each within this many m of the origin.
#define BK_CAMERA_MAX 1000.0

/// --record, --record-every and --camera.
typedef struct app_recorder {
  const char* dir;   ///< where the pictures go; NULL: no recording
  uint64_t every;    ///< every K-th frame is written: frames 0, K, 2K, ...
  bool every_given;  ///< --record-every was on the command line
  uint32_t written;  ///< pictures written so far
  bk_vec3 camera;    ///< where the camera stands, looking at the scene's target
  bool camera_given; ///< --camera was on the command line (else: the scene's camera)
} app_recorder;

/// No recording, every frame when there is one.
app_recorder default_recorder(void);
/// Parses --record, --record-every and --camera for `command`: returns 0 if `argv[*i]`
/// was one of them (consuming its value), 1 if not ours, 2 on a bad value
/// (one line printed, naming the option).
int parse_record_option(const char* command, int argc, char** argv, int* i, app_recorder* recorder);
/// Checks the options against the run's `frames` (0: not scripted) and
/// readies the directory: made if missing; refused if it holds anything but
/// an earlier recording's frame_*.png files, which are removed so that the
/// directory ends up holding this run's pictures only. False with one line
/// printed, naming the option, and nothing touched, on any problem.
bool recorder_prepare(const char* command, app_recorder* recorder, uint32_t frames);
/// Writes the picture drawn for `frame` (before the buffers swap) as the
/// next DIR/frame_NNNNN.png when the frame is one of those recorded.
bool recorder_frame(app_recorder* recorder, app_renderer* renderer, uint32_t frame, int width, int height,
                    bk_error* err);
