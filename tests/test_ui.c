// UI layer: every call is harmless without a UI or outside a frame; with a
// display (e.g. under xvfb-run), a hidden 3.3 core window: the UI draws into
// the bound framebuffer (an FBO here) without GL errors, text shows, the
// scale enlarges it, input callbacks installed before ui_create are
// chained and given back by ui_destroy, and create/destroy cycles work.
// Without a display the GL part is skipped.
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <GLFW/glfw3.h>

#include "ensure.h"
#include "hud.h"
#include "ui.h"

enum { width = 800, height = 720 };

static PFNGLGENFRAMEBUFFERSPROC gen_framebuffers;
static PFNGLBINDFRAMEBUFFERPROC bind_framebuffer;
static PFNGLFRAMEBUFFERTEXTURE2DPROC framebuffer_texture_2d;
static PFNGLCHECKFRAMEBUFFERSTATUSPROC check_framebuffer_status;
static PFNGLDELETEFRAMEBUFFERSPROC delete_framebuffers;

static int focus_calls;
static void on_focus(GLFWwindow* window, int focused) {
  (void)window;
  (void)focused;
  focus_calls++;
}

static void test_without_ui(void) {
  ENSURE(!ui_create(NULL));
  ENSURE(!ui_wants_mouse());
  ENSURE(!ui_wants_keyboard());
  ui_begin_frame(); // no UI: nothing happens
  bool open = true, check = false;
  double d = 1.0;
  int i = 3, current = 0;
  const char* const items[] = {"a", "b"};
  float values[4] = {1, 2, 3, 4};
  ENSURE(!ui_begin_window("w", 0, 0, 100, 100, &open));
  ENSURE(!ui_collapsing_header("h", true));
  ENSURE(!ui_button("b"));
  ENSURE(!ui_checkbox("c", &check) && !check);
  ENSURE(!ui_slider_double("d", &d, 0, 2, NULL, true) && d == 1.0);
  ENSURE(!ui_slider_int("i", &i, 0, 9) && i == 3);
  ENSURE(!ui_combo("m", &current, items, 2) && current == 0);
  ENSURE(!ui_radio("r", &i, 5) && i == 3);
  ui_text("%d", i);
  ui_text_colored(1, 0, 0, "%s", "x");
  ui_progress(0.5f, NULL);
  ui_plot("p", values, 4, 0, 0, 0, 0, NULL);
  ui_tooltip("t");
  ui_separator();
  ui_same_line();
  ui_push_id(1);
  ui_pop_id();
  ui_end_window();
  ui_end_frame();
  const float white[4] = {1, 1, 1, 1};
  float w = -1.0f, h = -1.0f;
  ui_display_size(&w, &h);
  ENSURE(w == 0.0f && h == 0.0f);
  ui_text_size("text", &w, &h);
  ENSURE(w == 0.0f && h == 0.0f);
  ui_overlay_line(0, 0, 10, 10, white, 1);
  ui_overlay_rect(0, 0, 10, 10, white, 0);
  ui_overlay_text(0, 0, white, "t");
  hud_draw(0.0);
  ui_set_scale(1.0f);
  ui_destroy();
}

// The game's hint: shown in full at first, gone a few seconds later,
// fading in between without a jump; both forms name the panel's key.
static void test_hud_fade(void) {
  ENSURE(hud_hint_alpha(0.0) == 1.0f && hud_hint_alpha(3.0) == 1.0f);
  ENSURE(hud_hint_alpha(10.0) == 0.0f && hud_hint_alpha(1e9) == 0.0f);
  ENSURE(hud_hint_alpha(NAN) == 1.0f);
  float previous = 1.0f;
  for (double t = 5.0; t <= 8.0; t += 0.05) {
    float a = hud_hint_alpha(t);
    ENSURE_MSG(a <= previous && previous - a < 0.1f, "alpha %g at %g s after %g", a, t, previous);
    previous = a;
  }
  float middle = hud_hint_alpha(6.75);
  ENSURE(middle > 0.2f && middle < 0.8f);
  ENSURE(strstr(hud_hint(false), "F1: panel") && strstr(hud_hint(true), "F1: panel"));
  ENSURE(strlen(hud_hint(true)) < strlen(hud_hint(false)));
}

static void draw(bool* second_open) {
  static bool check = true;
  static double speed = 2.5, mass = 10.0;
  static int pieces = 64, material = 1, mode = 0;
  static const char* const materials[] = {"stone", "glass", "porcelain"};
  static float history[32];
  for (int k = 0; k < 32; k++)
    history[k] = (float)(k % 7);
  if (ui_begin_window("Test", 10, 10, 380, 700, NULL)) {
    ui_text("Frame text %d", 42);
    ui_text_colored(1.0f, 0.5f, 0.0f, "Coloured");
    ui_separator();
    if (ui_collapsing_header("Settings", true)) {
      ENSURE(!ui_checkbox("Check", &check));
      ENSURE(!ui_slider_double("Speed", &speed, 0.0, 10.0, "%.1f", false));
      ENSURE(!ui_slider_double("Mass", &mass, 0.01, 1000.0, NULL, true));
      ENSURE(!ui_slider_int("Pieces", &pieces, 2, 4096));
      ENSURE(!ui_combo("Material", &material, materials, 3));
      ENSURE(!ui_radio("One", &mode, 0));
      ui_same_line();
      ENSURE(!ui_radio("Two", &mode, 1));
    }
    for (int k = 0; k < 2; k++) {
      ui_push_id(k);
      ENSURE(!ui_button("Same label"));
      ui_pop_id();
    }
    ui_tooltip("tip");
    ui_progress(0.3f, "loading");
    ui_plot("Plot", history, 32, 5, 0.0f, 0.0f, 40.0f, "overlay");
    ui_end_window();
  }
  if (ui_begin_window("Closable", 420, 10, 200, 100, second_open)) {
    ui_text("second");
    ui_end_window();
  }
}

static int gl_error_count(void) {
  int count = 0;
  while (glGetError() != GL_NO_ERROR)
    count++;
  return count;
}

/// Renders a few frames into the bound framebuffer over a known clear colour;
/// returns how many pixels are near-white (text) and checks the background.
static long render_and_count_text(uint8_t* pixels) {
  bool second_open = true;
  for (int frame = 0; frame < 3; frame++) {
    glViewport(0, 0, width, height);
    glClearColor(0.0f, 0.5f, 0.0f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    ui_begin_frame();
    ui_begin_frame(); // a second begin inside a frame is ignored
    draw(&second_open);
    ui_end_frame();
    ui_end_frame(); // and so is a second end
    ENSURE(gl_error_count() == 0);
  }
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, pixels);
  ENSURE(gl_error_count() == 0);
  // Bottom-right corner (row 0 is the bottom): no window there.
  const uint8_t* corner = pixels + ((size_t)0 * width + (width - 5)) * 4;
  ENSURE(corner[0] < 8 && corner[1] > 120 && corner[1] < 136 && corner[2] < 8);
  long text = 0, dark = 0;
  for (int y = 0; y < height; y++) {
    for (int x = 0; x < 390; x++) {
      const uint8_t* p = pixels + ((size_t)y * width + x) * 4;
      if (p[0] > 200 && p[1] > 200 && p[2] > 200) text++;
      if (p[0] < 40 && p[1] < 40 && p[2] < 40) dark++;
    }
  }
  ENSURE_MSG(dark > 100000, "window background pixels: %ld", dark); // the dark window covers most of its rect
  return text;
}

static bool is_clear(const uint8_t* p) { return p[0] < 8 && p[1] > 120 && p[1] < 136 && p[2] < 8; }

/// Draws the HUD `seconds` after the start over the clear colour; counts
/// the pixels it changed near the centre and along the bottom.
static void draw_hud(uint8_t* pixels, double seconds, long* centre, long* bottom) {
  glViewport(0, 0, width, height);
  glClearColor(0.0f, 0.5f, 0.0f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  ui_begin_frame();
  hud_draw(seconds);
  ui_end_frame();
  ENSURE(gl_error_count() == 0);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, pixels);
  *centre = *bottom = 0;
  for (int y = 0; y < height; y++)
    for (int x = 0; x < width; x++) {
      bool changed = !is_clear(pixels + ((size_t)y * width + x) * 4);
      if (abs(x - width / 2) <= 30 && abs(y - height / 2) <= 30) *centre += changed;
      if (y < 80) *bottom += changed; // row 0 is the bottom
    }
}

// The crosshair marks the centre at any time (light arms over a dark
// outline, with the centre point itself marked); the hint covers part of
// the bottom at first and nothing once faded.
static void check_hud(uint8_t* pixels) {
  long centre = 0, bottom = 0, centre_late = 0, bottom_late = 0;
  draw_hud(pixels, 0.0, &centre, &bottom);
  const uint8_t* middle = pixels + ((size_t)(height / 2) * width + width / 2) * 4;
  ENSURE_MSG(middle[0] > 200 && middle[1] > 200 && middle[2] > 200, "centre %u %u %u", middle[0], middle[1],
             middle[2]);
  long light = 0;
  for (int d = 0; d <= 30; d++) { // along the arm to the right
    const uint8_t* p = pixels + ((size_t)(height / 2) * width + width / 2 + d) * 4;
    light += p[0] > 200 && p[1] > 200 && p[2] > 200;
  }
  ENSURE_MSG(light >= 8, "light pixels along the right arm: %ld", light);
  ENSURE_MSG(centre > 60 && centre < 61 * 61 / 4, "crosshair pixels: %ld", centre);
  ENSURE_MSG(bottom > 2000, "hint pixels at 0 s: %ld", bottom);
  draw_hud(pixels, 10.0, &centre_late, &bottom_late);
  ENSURE_MSG(centre_late == centre, "crosshair pixels %ld at 10 s, %ld at 0 s", centre_late, centre);
  ENSURE_MSG(bottom_late == 0, "hint pixels at 10 s: %ld", bottom_late);
  fprintf(stderr, "  hud: crosshair %ld pixels; hint %ld pixels at 0 s, %ld at 10 s\n", centre, bottom,
          bottom_late);
}

static void test_with_display(void) {
  if (!glfwInit()) {
    fprintf(stderr, "  no display: GL part skipped\n");
    return;
  }
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
  GLFWwindow* window = glfwCreateWindow(width, height, "test_ui", NULL, NULL);
  if (!window) {
    fprintf(stderr, "  no OpenGL 3.3 core context: GL part skipped\n");
    glfwTerminate();
    return;
  }
  glfwMakeContextCurrent(window);
  gen_framebuffers = (PFNGLGENFRAMEBUFFERSPROC)glfwGetProcAddress("glGenFramebuffers");
  bind_framebuffer = (PFNGLBINDFRAMEBUFFERPROC)glfwGetProcAddress("glBindFramebuffer");
  framebuffer_texture_2d = (PFNGLFRAMEBUFFERTEXTURE2DPROC)glfwGetProcAddress("glFramebufferTexture2D");
  check_framebuffer_status = (PFNGLCHECKFRAMEBUFFERSTATUSPROC)glfwGetProcAddress("glCheckFramebufferStatus");
  delete_framebuffers = (PFNGLDELETEFRAMEBUFFERSPROC)glfwGetProcAddress("glDeleteFramebuffers");
  ENSURE(gen_framebuffers && bind_framebuffer && framebuffer_texture_2d && check_framebuffer_status &&
         delete_framebuffers);

  // A hidden window's default framebuffer may have no pixels: draw into an FBO.
  GLuint texture = 0, fbo = 0;
  glGenTextures(1, &texture);
  glBindTexture(GL_TEXTURE_2D, texture);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
  glBindTexture(GL_TEXTURE_2D, 0);
  gen_framebuffers(1, &fbo);
  bind_framebuffer(GL_FRAMEBUFFER, fbo);
  framebuffer_texture_2d(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture, 0);
  ENSURE(check_framebuffer_status(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE);
  ENSURE(gl_error_count() == 0);

  glfwSetWindowFocusCallback(window, on_focus);
  uint8_t* pixels = malloc((size_t)width * height * 4);
  ENSURE(pixels);
  long text_small = 0;
  for (int cycle = 0; cycle < 2; cycle++) {
    ui_set_scale(1.0f);
    ENSURE(ui_create(window));
    ENSURE(!ui_create(window)); // one UI at a time
    // ImGui's callback is installed over ours (and calls ours).
    GLFWwindowfocusfun installed = glfwSetWindowFocusCallback(window, NULL);
    ENSURE(installed != NULL && installed != on_focus);
    glfwSetWindowFocusCallback(window, installed);
    int before = focus_calls;
    installed(window, GLFW_TRUE);
    ENSURE(focus_calls == before + 1);

    long text = render_and_count_text(pixels);
    ENSURE_MSG(text > 500, "text pixels: %ld", text);
    if (cycle == 0)
      text_small = text;
    else
      ENSURE_MSG(labs(text - text_small) < text_small / 20, "%ld vs %ld", text, text_small);
    // Larger scale (applied mid-lifetime: the font texture is rebuilt): more text pixels
    // (the window is tall enough to show everything at 1.5).
    ui_set_scale(1.5f);
    long text_large = render_and_count_text(pixels);
    ENSURE_MSG(text_large > text * 13 / 10, "scaled text pixels: %ld vs %ld", text_large, text);
    if (cycle == 0) fprintf(stderr, "  text pixels: %ld at scale 1, %ld at 1.5\n", text, text_large);
    if (cycle == 0) check_hud(pixels);

    ui_begin_frame();
    ui_destroy(); // inside a frame: allowed
    ui_destroy(); // twice: nothing
    ENSURE(!ui_wants_mouse());
    ENSURE(glfwSetWindowFocusCallback(window, on_focus) == on_focus); // ours is back
    ENSURE(gl_error_count() == 0);
  }
  free(pixels);
  bind_framebuffer(GL_FRAMEBUFFER, 0);
  delete_framebuffers(1, &fbo);
  glDeleteTextures(1, &texture);
  glfwDestroyWindow(window);
  // No glfwTerminate: closing the display unloads the GL driver, and
  // LeakSanitizer then reports the driver's never-freed allocations with
  // unknown frames that no suppression can name. Exiting keeps it loaded.
}

int main(void) {
  RUN(test_without_ui);
  RUN(test_hud_fade);
  RUN(test_with_display);
  return 0;
}
