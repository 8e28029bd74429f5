// ui: a small immediate-mode C interface over Dear ImGui (GLFW + OpenGL 3
// backends). No ImGui or GLFW type crosses it: the window is a GLFWwindow*
// passed as void*. There is one UI per process.
//
// Each frame: ui_begin_frame(), then windows and widgets, then
// ui_end_frame() (which draws into the current framebuffer). Widgets are
// only valid between those two calls; outside them they do nothing and return
// false. Labels are also the widgets' ids within a window: "Speed##2" shows
// "Speed" with a distinct id, "##hidden" shows no label; ui_push_id tells
// apart widgets made in a loop.
#pragma once

#include <stdbool.h>
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(__GNUC__)
#define BK_UI_PRINTF(fmt_index, first_arg) __attribute__((format(printf, fmt_index, first_arg)))
#else
#define BK_UI_PRINTF(fmt_index, first_arg)
#endif

// ---------------------------------------------------------------- lifetime and frames

/// Creates the UI on a GLFW window whose OpenGL context (3.3 core or later)
/// is current. Installs ImGui's GLFW input callbacks, which chain to the
/// callbacks the application installed BEFORE this call (install yours first).
/// Dark style with slightly rounded corners; no imgui.ini is read or written.
/// Returns false if glfw_window is NULL, its context is older than 3.3, a UI
/// already exists, or a backend fails to initialise (nothing is left behind).
bool ui_create(void* glfw_window);
/// Destroys the UI, restoring the window's previous callbacks. Needs the same
/// GL context current. Does nothing if there is no UI.
void ui_destroy(void);
/// Scales text and every style size (padding, spacing, rounding) by `scale`
/// (clamped to [0.5, 4]; 1 = 13-pixel font). The font is rebuilt at the new
/// size, so text stays sharp; takes effect at the next ui_begin_frame. May
/// be called before ui_create.
void ui_set_scale(float scale);

/// Starts a UI frame (reads input and the window size). Does nothing if there
/// is no UI or a frame is already open.
void ui_begin_frame(void);
/// Ends the frame and draws the UI into the current framebuffer, over what is
/// there (GL state the drawing changes is restored). Does nothing outside a frame.
void ui_end_frame(void);

/// True when the mouse is over a UI window or dragging a widget: the
/// application should ignore the mouse then. Updated by ui_begin_frame.
bool ui_wants_mouse(void);
/// True when a UI text field has keyboard focus: the application should
/// ignore keys then. Updated by ui_begin_frame.
bool ui_wants_keyboard(void);

// ---------------------------------------------------------------- layout

/// Begins a window, placed at (x, y) with the given size (pixels) the first
/// time it appears; afterwards the user may move and resize it. With `open`
/// not NULL the window has a close button that sets *open to false. Returns
/// true when the window is expanded: add its widgets, then call
/// ui_end_window. Returns false when it is collapsed: do NOT call
/// ui_end_window then.
bool ui_begin_window(const char* title, float x, float y, float width, float height, bool* open);
/// Ends the window begun by a ui_begin_window that returned true.
void ui_end_window(void);
/// A header that folds the widgets after it; returns true when expanded (show
/// them). `default_open` is its state the first time it appears.
bool ui_collapsing_header(const char* label, bool default_open);
/// A horizontal line.
void ui_separator(void);
/// Puts the next widget on the same line as the previous one.
void ui_same_line(void);
/// Pushes an integer onto the id stack (for widgets made in a loop with the same labels).
void ui_push_id(int id);
/// Pops what ui_push_id pushed.
void ui_pop_id(void);

// ---------------------------------------------------------------- widgets

/// A button; true on the frame it is clicked.
bool ui_button(const char* label);
/// A checkbox over *value; true when the user toggled it.
bool ui_checkbox(const char* label, bool* value);
/// A slider over *value in [min, max]; `format` is printf-style for the
/// shown value (NULL = "%.3f"); `logarithmic` spaces values logarithmically.
/// Ctrl+click types a value. True when the value changed.
bool ui_slider_double(const char* label, double* value, double min, double max, const char* format,
                      bool logarithmic);
/// An integer slider over *value in [min, max]; true when the value changed.
bool ui_slider_int(const char* label, int* value, int min, int max);
/// An integer slider whose steps grow with the value (for ranges such as 1..65536).
bool ui_slider_int_log(const char* label, int* value, int min, int max);
/// A one-line text field editing buffer (capacity bytes, NUL included); true
/// when Enter is pressed in it.
bool ui_input_text(const char* label, char* buffer, size_t capacity);
/// A drop-down list of `count` items; *current is the selected index. True
/// when the selection changed.
bool ui_combo(const char* label, int* current, const char* const* items, int count);
/// A radio button that sets *value to `button_value` when clicked; shown
/// selected while *value == button_value. True when clicked.
bool ui_radio(const char* label, int* value, int button_value);
/// A line of text, printf-style.
void ui_text(const char* fmt, ...) BK_UI_PRINTF(1, 2);
/// A line of text in colour (r, g, b in [0, 1]), printf-style.
void ui_text_colored(float r, float g, float b, const char* fmt, ...) BK_UI_PRINTF(4, 5);
/// A progress bar across the window; `fraction` in [0, 1]; `overlay` is the
/// text on it (NULL = the percentage).
void ui_progress(float fraction, const char* overlay);
/// A line plot of `count` values, starting at index `offset` and wrapping
/// (for ring buffers; 0 otherwise), vertical range [min, max] (min >= max:
/// fit the data), `height` pixels tall (0 = default); `overlay` (may be NULL)
/// is drawn at the top of the plot.
void ui_plot(const char* label, const float* values, int count, int offset, float min, float max,
             float height, const char* overlay);
/// Shows `text` in a tooltip while the mouse is over the previous widget.
void ui_tooltip(const char* text);

// ---------------------------------------------------------------- overlay
// Shapes drawn over everything else of the frame (windows too), in pixels
// from the top left of the window, each colour r, g, b, a in [0, 1]. They
// take no input: the mouse stays the application's.

/// The window's size in pixels as the current frame sees it; 0 x 0 outside a frame.
void ui_display_size(float* width, float* height);
/// A line from (x0, y0) to (x1, y1), `thickness` pixels wide.
void ui_overlay_line(float x0, float y0, float x1, float y1, const float rgba[4], float thickness);
/// A filled rectangle from (x0, y0) to (x1, y1), its corners rounded by `rounding` pixels.
void ui_overlay_rect(float x0, float y0, float x1, float y1, const float rgba[4], float rounding);
/// `text` with its top left at (x, y), in the UI's font.
void ui_overlay_text(float x, float y, const float rgba[4], const char* text);
/// The size in pixels `text` takes in the UI's font (0 x 0 outside a frame).
void ui_text_size(const char* text, float* width, float* height);

#ifdef __cplusplus
}
#endif
