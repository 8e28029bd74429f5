// ui: the C interface of ui.h implemented over Dear ImGui with its GLFW
// and OpenGL 3 backends. This is the only translation unit that includes
// ImGui. ImGui reports misuse with assertions and allocates with malloc; none
// of what is called here throws, so no exception can leave these functions.
//
// State is one static struct: one ImGui context per process. A frame is open
// from ui_begin_frame to ui_end_frame; widget calls outside it are
// ignored instead of tripping ImGui's assertions.
#include "ui.h"

#include <cfloat>
#include <cmath>
#include <cstdarg>

#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

namespace {

const char* const glsl_version = "#version 330 core";
const float base_font_pixels = 13.0f; // ImGui's built-in font (ProggyClean) is drawn for 13 px
const float min_scale = 0.5f, max_scale = 4.0f;

struct UiState {
  bool created = false;
  bool in_frame = false;
  bool device_ready = false; // the OpenGL backend has made its GL objects (first frame)
  bool scale_dirty = false;  // font and style wait for the next frame to take the scale
  float scale = 1.0f;
  ImGuiStyle base_style; // dark style at scale 1
};

UiState state;

void make_base_style(ImGuiStyle* style) {
  ImGui::StyleColorsDark(style);
  style->WindowRounding = 6.0f;
  style->ChildRounding = 4.0f;
  style->FrameRounding = 4.0f;
  style->PopupRounding = 4.0f;
  style->ScrollbarRounding = 6.0f;
  style->GrabRounding = 3.0f;
  style->TabRounding = 4.0f;
  style->WindowBorderSize = 1.0f;
  style->FrameBorderSize = 0.0f;
  style->WindowPadding = ImVec2(10.0f, 10.0f);
  style->FramePadding = ImVec2(6.0f, 4.0f);
  style->ItemSpacing = ImVec2(8.0f, 6.0f);
  ImVec4* colors = style->Colors;
  colors[ImGuiCol_WindowBg].w = 0.92f;
  colors[ImGuiCol_TitleBg] = ImVec4(0.10f, 0.10f, 0.12f, 1.0f);
  colors[ImGuiCol_TitleBgActive] = ImVec4(0.16f, 0.29f, 0.48f, 1.0f);
}

/// Rebuilds the font atlas at the current scale and scales the style. Between
/// frames only (ImGui locks the atlas during a frame).
void apply_scale() {
  ImGuiIO& io = ImGui::GetIO();
  io.Fonts->Clear();
  ImFontConfig config;
  config.SizePixels = std::floor(base_font_pixels * state.scale + 0.5f);
  io.Fonts->AddFontDefault(&config);
  io.FontGlobalScale = 1.0f;
  if (state.device_ready) {
    ImGui_ImplOpenGL3_DestroyFontsTexture();
    ImGui_ImplOpenGL3_CreateFontsTexture();
  } // else the backend builds the texture with its other objects at the first frame
  ImGuiStyle& style = ImGui::GetStyle();
  style = state.base_style;
  style.ScaleAllSizes(state.scale);
  state.scale_dirty = false;
}

inline bool in_frame() { return state.in_frame; }

/// Packs a colour, each channel clamped to [0, 1] (NaN as 0).
ImU32 overlay_color(const float rgba[4]) {
  float c[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  for (int i = 0; i < 4; ++i)
    c[i] = rgba[i] >= 0.0f ? (rgba[i] <= 1.0f ? rgba[i] : 1.0f) : 0.0f;
  return ImGui::ColorConvertFloat4ToU32(ImVec4(c[0], c[1], c[2], c[3]));
}

} // namespace

extern "C" {

bool ui_create(void* glfw_window) {
  if (state.created || glfw_window == nullptr) return false;
  GLFWwindow* window = static_cast<GLFWwindow*>(glfw_window);
  if (glfwGetWindowAttrib(window, GLFW_CLIENT_API) != GLFW_OPENGL_API) return false;
  int major = glfwGetWindowAttrib(window, GLFW_CONTEXT_VERSION_MAJOR);
  int minor = glfwGetWindowAttrib(window, GLFW_CONTEXT_VERSION_MINOR);
  if (major < 3 || (major == 3 && minor < 3)) return false;

  IMGUI_CHECKVERSION();
  ImGuiContext* context = ImGui::CreateContext();
  if (context == nullptr) return false;
  ImGuiIO& io = ImGui::GetIO();
  io.IniFilename = nullptr; // window placement comes from the code, not from a file in the working directory
  io.LogFilename = nullptr;

  if (!ImGui_ImplGlfw_InitForOpenGL(window, true)) {
    ImGui::DestroyContext(context);
    return false;
  }
  if (!ImGui_ImplOpenGL3_Init(glsl_version)) {
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext(context);
    return false;
  }
  make_base_style(&state.base_style);
  state.created = true;
  state.in_frame = false;
  state.device_ready = false;
  apply_scale();
  return true;
}

void ui_destroy(void) {
  if (!state.created) return;
  if (state.in_frame) ImGui::EndFrame();
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  state.created = false;
  state.in_frame = false;
  state.device_ready = false;
}

void ui_set_scale(float scale) {
  if (!(scale >= min_scale)) scale = min_scale; // NaN too
  if (scale > max_scale) scale = max_scale;
  if (scale == state.scale) return;
  state.scale = scale;
  state.scale_dirty = true;
}

void ui_begin_frame(void) {
  if (!state.created || state.in_frame) return;
  if (state.scale_dirty) apply_scale();
  ImGui_ImplOpenGL3_NewFrame();
  state.device_ready = true;
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
  state.in_frame = true;
}

void ui_end_frame(void) {
  if (!state.in_frame) return;
  ImGui::Render();
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
  state.in_frame = false;
}

bool ui_wants_mouse(void) { return state.created && ImGui::GetIO().WantCaptureMouse; }

bool ui_wants_keyboard(void) { return state.created && ImGui::GetIO().WantCaptureKeyboard; }

bool ui_begin_window(const char* title, float x, float y, float width, float height, bool* open) {
  if (!in_frame() || (open != nullptr && !*open)) return false;
  ImGui::SetNextWindowPos(ImVec2(x, y), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(width, height), ImGuiCond_FirstUseEver);
  if (ImGui::Begin(title, open)) return true;
  ImGui::End(); // collapsed or clipped: ImGui still wants its End
  return false;
}

void ui_end_window(void) {
  if (in_frame()) ImGui::End();
}

bool ui_collapsing_header(const char* label, bool default_open) {
  if (!in_frame()) return false;
  return ImGui::CollapsingHeader(label,
                                 default_open ? ImGuiTreeNodeFlags_DefaultOpen : ImGuiTreeNodeFlags_None);
}

void ui_separator(void) {
  if (in_frame()) ImGui::Separator();
}

void ui_same_line(void) {
  if (in_frame()) ImGui::SameLine();
}

void ui_push_id(int id) {
  if (in_frame()) ImGui::PushID(id);
}

void ui_pop_id(void) {
  if (in_frame()) ImGui::PopID();
}

bool ui_button(const char* label) { return in_frame() && ImGui::Button(label); }

bool ui_checkbox(const char* label, bool* value) {
  return in_frame() && value != nullptr && ImGui::Checkbox(label, value);
}

bool ui_slider_double(const char* label, double* value, double min, double max, const char* format,
                      bool logarithmic) {
  if (!in_frame() || value == nullptr) return false;
  // AlwaysClamp: a value typed with Ctrl+click stays within the slider's
  // range too (the ranges are what keeps the simulation and the uvs finite).
  ImGuiSliderFlags flags = ImGuiSliderFlags_AlwaysClamp;
  if (logarithmic) flags |= ImGuiSliderFlags_Logarithmic;
  return ImGui::SliderScalar(label, ImGuiDataType_Double, value, &min, &max,
                             format != nullptr ? format : "%.3f", flags);
}

bool ui_slider_int(const char* label, int* value, int min, int max) {
  return in_frame() && value != nullptr &&
         ImGui::SliderInt(label, value, min, max, "%d", ImGuiSliderFlags_AlwaysClamp);
}

bool ui_slider_int_log(const char* label, int* value, int min, int max) {
  return in_frame() && value != nullptr &&
         ImGui::SliderInt(label, value, min, max, "%d",
                          ImGuiSliderFlags_AlwaysClamp | ImGuiSliderFlags_Logarithmic);
}

bool ui_input_text(const char* label, char* buffer, size_t capacity) {
  return in_frame() && buffer != nullptr && capacity > 0 &&
         ImGui::InputText(label, buffer, capacity, ImGuiInputTextFlags_EnterReturnsTrue);
}

bool ui_combo(const char* label, int* current, const char* const* items, int count) {
  if (!in_frame() || current == nullptr || items == nullptr || count < 0) return false;
  return ImGui::Combo(label, current, items, count);
}

bool ui_radio(const char* label, int* value, int button_value) {
  return in_frame() && value != nullptr && ImGui::RadioButton(label, value, button_value);
}

void ui_text(const char* fmt, ...) {
  if (!in_frame()) return;
  va_list args;
  va_start(args, fmt);
  ImGui::TextV(fmt, args);
  va_end(args);
}

void ui_text_colored(float r, float g, float b, const char* fmt, ...) {
  if (!in_frame()) return;
  va_list args;
  va_start(args, fmt);
  ImGui::TextColoredV(ImVec4(r, g, b, 1.0f), fmt, args);
  va_end(args);
}

void ui_progress(float fraction, const char* overlay) {
  if (in_frame()) ImGui::ProgressBar(fraction, ImVec2(-FLT_MIN, 0.0f), overlay);
}

void ui_plot(const char* label, const float* values, int count, int offset, float min, float max,
             float height, const char* overlay) {
  if (!in_frame() || values == nullptr || count < 0) return;
  if (!(min < max)) min = max = FLT_MAX; // ImGui fits the data to FLT_MAX bounds
  if (count > 0) {
    offset %= count;
    if (offset < 0) offset += count;
  } else {
    offset = 0;
  }
  ImGui::PlotLines(label, values, count, offset, overlay, min, max,
                   ImVec2(0.0f, height > 0.0f ? height : 0.0f));
}

void ui_tooltip(const char* text) {
  if (in_frame() && text != nullptr && ImGui::IsItemHovered()) ImGui::SetTooltip("%s", text);
}

void ui_display_size(float* width, float* height) {
  ImVec2 size = in_frame() ? ImGui::GetIO().DisplaySize : ImVec2(0.0f, 0.0f);
  if (width != nullptr) *width = size.x;
  if (height != nullptr) *height = size.y;
}

void ui_overlay_line(float x0, float y0, float x1, float y1, const float rgba[4], float thickness) {
  if (!in_frame() || rgba == nullptr) return;
  ImGui::GetForegroundDrawList()->AddLine(ImVec2(x0, y0), ImVec2(x1, y1), overlay_color(rgba), thickness);
}

void ui_overlay_rect(float x0, float y0, float x1, float y1, const float rgba[4], float rounding) {
  if (!in_frame() || rgba == nullptr) return;
  ImGui::GetForegroundDrawList()->AddRectFilled(ImVec2(x0, y0), ImVec2(x1, y1), overlay_color(rgba),
                                                rounding);
}

void ui_overlay_text(float x, float y, const float rgba[4], const char* text) {
  if (!in_frame() || rgba == nullptr || text == nullptr) return;
  ImGui::GetForegroundDrawList()->AddText(ImVec2(x, y), overlay_color(rgba), text);
}

void ui_text_size(const char* text, float* width, float* height) {
  ImVec2 size = in_frame() && text != nullptr ? ImGui::CalcTextSize(text) : ImVec2(0.0f, 0.0f);
  if (width != nullptr) *width = size.x;
  if (height != nullptr) *height = size.y;
}

} // extern "C"
