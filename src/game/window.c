// The window, its GL context and the renderer, and the options that scripted
// runs share.
#define _GNU_SOURCE // dl_iterate_phdr, RTLD_NODELETE
#include <GLFW/glfw3.h>
#include <dlfcn.h>
#include <link.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "window.h"

const char* app_shader_dir(void) {
  // Beside the assets the executable found, else the source tree.
  static char dir[4200];
  snprintf(dir, sizeof dir, "%s/../shaders", app_asset_dir());
  char probe[4300];
  snprintf(probe, sizeof probe, "%s/mesh.vert", dir);
  if (access(probe, R_OK) == 0) return dir;
  return BK_SHADER_DIR;
}

void camera_fit_planes(app_camera* camera, double distance) {
  if (!(distance > 0.0) || !isfinite(distance)) return; // the renderer's defaults
  // The defaults' ratio (4000:1) kept for a large model; a small one seen
  // from close needs a plane nearer than 5 cm, and gets a twentieth of its distance.
  camera->far_plane = fmax(200.0, 4.0 * distance);
  camera->near_plane = fmin(fmax(0.05, camera->far_plane / 4000.0), 0.05 * distance);
}

int parse_window_option(const char* command, int argc, char** argv, int* i, window_options* o) {
  static const char* const names[] = {"--width", "--height", "--frames", "--autofire", "--screenshot"};
  const char* arg = argv[*i];
  const char* value = NULL;
  int which = take_option(command, argc, argv, i, names, 5, &value);
  if (which < 0) return which == -1 ? 1 : 2;
  uint64_t number = 0;
  switch (which) {
  case 0:
  case 1:
    if (!option_u64(command, arg, value, 64, 8192, &number)) return 2;
    *(which == 0 ? &o->width : &o->height) = (int)number;
    return 0;
  case 2:
    if (!option_u64(command, arg, value, 1, 10000000, &number)) return 2;
    o->frames = (uint32_t)number;
    return 0;
  case 3:
    if (!option_u64(command, arg, value, 0, 10000, &number)) return 2;
    o->autofire = (uint32_t)number;
    return 0;
  default: {
    // Checked now, not after the run: a name and a place the picture can be saved as.
    const app_file shot = {"--screenshot", value, ".png", true};
    bk_error err = {0};
    if (!app_check_files(NULL, 0, &shot, 1, &err)) {
      fprintf(stderr, "breakables %s: %s\n", command, err.message);
      return 2;
    }
    o->screenshot = value;
    return 0;
  }
  }
}

// GLFW reports why it could not start through this callback: keep the reason
// for our own one-line error; once a window is open, print what comes.
static char glfw_reason[256];
static bool window_is_open;

static void glfw_error(int code, const char* message) {
  snprintf(glfw_reason, sizeof glfw_reason, "%s", message);
  if (window_is_open) fprintf(stderr, "breakables: GLFW error %d: %s\n", code, message);
}

bool window_open(const char* title, const window_options* o, void** window_out, app_renderer** renderer_out,
                 bk_error* err) {
  glfwSetErrorCallback(glfw_error);
  if (!glfwInit())
    return bk_error_set(err, "cannot open a window: %s (is there a display? try xvfb-run)", glfw_reason);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_SAMPLES, 0);               // software GL pays for every sample
  glfwWindowHint(GLFW_SRGB_CAPABLE, GLFW_FALSE); // the shaders encode sRGB (cheaper in software)
  GLFWwindow* window = glfwCreateWindow(o->width, o->height, title, NULL, NULL);
  if (!window) {
    glfwTerminate();
    return bk_error_set(err, "cannot open a %dx%d window with an OpenGL 3.3 core context", o->width,
                        o->height);
  }
  glfwMakeContextCurrent(window);
  glfwSwapInterval(o->frames ? 0 : 1); // scripted runs go as fast as they can
  char textures[4200];
  snprintf(textures, sizeof textures, "%s/textures", app_asset_dir());
  renderer_def desc = {
      .get_proc_address = glfwGetProcAddress, .shader_dir = app_shader_dir(), .texture_dir = textures};
  app_renderer* renderer = renderer_create(&desc, err);
  if (!renderer) {
    glfwDestroyWindow(window);
    glfwTerminate();
    return false;
  }
  *window_out = window;
  *renderer_out = renderer;
  window_is_open = true;
  return true;
}

// Mesa's DRI driver keeps a few allocations until exit, and glfwTerminate
// unloads it, after which a leak checker can no longer name the library they
// came from (so no suppression can match them). Pinning the loaded driver
// keeps it mapped until the process ends; it is about to anyway.
static int pin_gl_driver(struct dl_phdr_info* info, size_t size, void* unused) {
  (void)size;
  (void)unused;
  if (info->dlpi_name && strstr(info->dlpi_name, "_dri.so"))
    dlopen(info->dlpi_name, RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE);
  return 0;
}

void window_close(void* window, app_renderer* renderer) {
  window_is_open = false;
  renderer_destroy(renderer);
  glfwDestroyWindow((GLFWwindow*)window);
  dl_iterate_phdr(pin_gl_driver, NULL);
  glfwTerminate();
}
