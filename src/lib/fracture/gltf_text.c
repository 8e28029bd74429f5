// The JSON text of a glTF export: a growing buffer and the writers of
// numbers, strings, URIs and base64 the exporter uses.
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bk_fracture.h"
#include "gltf_internal.h"

void bk_tb_reserve(text_buffer* t, size_t extra) {
  if (t->size + extra + 1 <= t->capacity) return;
  size_t capacity = t->capacity ? t->capacity : 65536;
  while (capacity < t->size + extra + 1)
    capacity *= 2;
  t->data = bk_realloc(t->data, capacity);
  t->capacity = capacity;
}

void bk_tb_raw(text_buffer* t, const char* s) {
  size_t n = strlen(s);
  bk_tb_reserve(t, n);
  memcpy(t->data + t->size, s, n + 1);
  t->size += n;
}

void bk_tb_fmt(text_buffer* t, const char* fmt, ...) {
  va_list args;
  va_start(args, fmt);
  bk_tb_reserve(t, 64);
  int n = vsnprintf(t->data + t->size, t->capacity - t->size, fmt, args);
  va_end(args);
  if (n >= 0 && (size_t)n >= t->capacity - t->size) {
    bk_tb_reserve(t, (size_t)n);
    va_start(args, fmt);
    n = vsnprintf(t->data + t->size, t->capacity - t->size, fmt, args);
    va_end(args);
  }
  if (n > 0) t->size += (size_t)n;
}

// Doubles with %.17g read back exactly. The values written are finite (the
// tree is validated and the def checked first), but printf would write a
// non-finite one as inf or nan, which no JSON reader takes: such a value
// becomes null, so the file always stays JSON. A float is written as its
// exact double.
void bk_tb_double(text_buffer* t, double v) {
  if (isfinite(v))
    bk_tb_fmt(t, "%.17g", v);
  else
    bk_tb_raw(t, "null");
}

void bk_tb_doubles(text_buffer* t, const double* v, int n) {
  bk_tb_raw(t, "[");
  for (int i = 0; i < n; ++i) {
    if (i) bk_tb_raw(t, ",");
    bk_tb_double(t, v[i]);
  }
  bk_tb_raw(t, "]");
}

void bk_tb_string(text_buffer* t, const char* s) {
  bk_tb_raw(t, "\"");
  for (const unsigned char* c = (const unsigned char*)s; *c; ++c) {
    if (*c == '"' || *c == '\\')
      bk_tb_fmt(t, "\\%c", *c);
    else if (*c < 0x20)
      bk_tb_fmt(t, "\\u%04x", *c);
    else {
      bk_tb_reserve(t, 1);
      t->data[t->size++] = (char)*c;
      t->data[t->size] = '\0';
    }
  }
  bk_tb_raw(t, "\"");
}

// A path as a URI reference: letters, digits and -._~/ stay, the rest is %XX.
void bk_tb_uri(text_buffer* t, const char* path) {
  bk_tb_raw(t, "\"");
  for (const unsigned char* c = (const unsigned char*)path; *c; ++c) {
    if ((*c >= 'a' && *c <= 'z') || (*c >= 'A' && *c <= 'Z') || (*c >= '0' && *c <= '9') ||
        strchr("-._~/", *c))
      bk_tb_fmt(t, "%c", *c);
    else
      bk_tb_fmt(t, "%%%02X", *c);
  }
  bk_tb_raw(t, "\"");
}

void bk_tb_base64(text_buffer* t, const uint8_t* data, size_t size) {
  static const char alphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  bk_tb_reserve(t, (size + 2) / 3 * 4);
  char* out = t->data + t->size;
  size_t i = 0;
  for (; i + 3 <= size; i += 3) {
    uint32_t v = (uint32_t)data[i] << 16 | (uint32_t)data[i + 1] << 8 | data[i + 2];
    *out++ = alphabet[v >> 18];
    *out++ = alphabet[(v >> 12) & 63];
    *out++ = alphabet[(v >> 6) & 63];
    *out++ = alphabet[v & 63];
  }
  if (i < size) {
    uint32_t v = (uint32_t)data[i] << 16 | (i + 1 < size ? (uint32_t)data[i + 1] << 8 : 0);
    *out++ = alphabet[v >> 18];
    *out++ = alphabet[(v >> 12) & 63];
    *out++ = i + 1 < size ? alphabet[(v >> 6) & 63] : '=';
    *out++ = '=';
  }
  t->size = (size_t)(out - t->data);
  t->data[t->size] = '\0';
}
