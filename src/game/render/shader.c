// Shader programs from files, with the GL info log in the error on failure.
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render_internal.h"

// A regular file only (bk_file_read), NUL-terminated.
static char* read_text(const char* path) {
  void* data = NULL;
  size_t size = 0;
  bk_error err = {{0}};
  if (!bk_file_read(path, (uint64_t)1 << 24, "16 MiB", &data, &size, &err)) return NULL;
  char* text = bk_realloc(data, size + 1);
  text[size] = 0;
  return text;
}

// One line of the info log is enough to name the problem.
static void first_line(char* log) {
  char* newline = strchr(log, '\n');
  if (newline) *newline = 0;
}

// Right after the #version line, which GLSL wants first, come the variant
// (may be NULL) as a macro and the shared functions of common.glsl. A variant
// lets one file make several programs without runtime branches, whose both
// sides a software renderer would execute.
static GLuint compile(const char* path, GLenum type, const char* variant, const char* common, bk_error* err) {
  char* source = read_text(path);
  if (!source) return bk_error_set(err, "%s: cannot read shader", path), 0;
  GLuint shader = glCreateShader(type);
  char* newline = strchr(source, '\n');
  GLint version_length = newline ? (GLint)(newline - source + 1) : 0;
  // Each space-separated word of the variant a macro (e.g. "SURFACE GLASS").
  char define[256] = "";
  size_t used = 0;
  for (const char* word = variant; word && *word;) {
    size_t length = strcspn(word, " ");
    if (length > 0 && used + length + 12 < sizeof define)
      used += (size_t)snprintf(define + used, sizeof define - used, "#define %.*s 1\n", (int)length, word);
    word += length;
    word += strspn(word, " ");
  }
  // Keeps the info log's line numbers those of the file.
  const char* line_reset = "\n#line 2\n";
  const char* sources[5] = {source, define, common, line_reset, source + version_length};
  const GLint lengths[5] = {version_length, -1, -1, -1, -1};
  glShaderSource(shader, 5, sources, lengths);
  glCompileShader(shader);
  free(source);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[1024] = {0};
    glGetShaderInfoLog(shader, sizeof log, NULL, log);
    first_line(log);
    bk_error_set(err, "%s%s%s%s: shader does not compile: %s", path, variant ? " (" : "",
                 variant ? variant : "", variant ? ")" : "", log);
    glDeleteShader(shader);
    return 0;
  }
  return shader;
}

GLuint shader_load(const char* dir, const char* name, const char* variant, bk_error* err) {
  char path[1024];
  snprintf(path, sizeof path, "%s/common.glsl", dir);
  char* common = read_text(path);
  if (!common) return bk_error_set(err, "%s: cannot read shader", path), 0;
  snprintf(path, sizeof path, "%s/%s.vert", dir, name);
  GLuint vertex_shader = compile(path, GL_VERTEX_SHADER, variant, common, err);
  snprintf(path, sizeof path, "%s/%s.frag", dir, name);
  GLuint fragment = vertex_shader ? compile(path, GL_FRAGMENT_SHADER, variant, common, err) : 0;
  free(common);
  if (!fragment) {
    if (vertex_shader) glDeleteShader(vertex_shader);
    return 0;
  }
  GLuint program = glCreateProgram();
  glAttachShader(program, vertex_shader);
  glAttachShader(program, fragment);
  glLinkProgram(program);
  glDeleteShader(vertex_shader);
  glDeleteShader(fragment);
  GLint ok = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[1024] = {0};
    glGetProgramInfoLog(program, sizeof log, NULL, log);
    first_line(log);
    bk_error_set(err, "%s/%s%s%s%s: shaders do not link: %s", dir, name, variant ? " (" : "",
                 variant ? variant : "", variant ? ")" : "", log);
    glDeleteProgram(program);
    return 0;
  }
  return program;
}
