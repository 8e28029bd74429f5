/* PNG output of the texture generator: colour, normal maps, and interior
 * normal maps with ambient occlusion in alpha (see tex.h). */
#include <stdio.h>
#include <stdlib.h>

#include <stb_image_write.h>

#include <breakables/base.h>

#include "tex.h"

const char* tex_outdir = ".";
int tex_failed;

static unsigned char to8(float x) { return (unsigned char)lrintf(clampf(x, 0.0f, 1.0f) * 255.0f); }

static void write_to_stream(void* context, void* data, int size) {
  fwrite(data, 1, (size_t)size, context); /* a short write leaves the stream in error: commit reports it */
}

/* Written beside the target and renamed over it (bk_file_begin_atomic), like
 * every file the project writes: a symlink planted there is never followed. */
static void write_png(const char* name, const unsigned char* px, int channels) {
  static const bk_atomic_messages messages = {"cannot write", "cannot write", "cannot write"};
  char path[4096];
  snprintf(path, sizeof path, "%s/%s.png", tex_outdir, name);
  bk_atomic_file file = {0};
  bk_error err = {{0}};
  bool ok = bk_file_begin_atomic(path, &messages, &file, &err);
  if (ok && !stbi_write_png_to_func(write_to_stream, file.stream, N, N, channels, px, N * channels)) {
    bk_file_abort_atomic(&file);
    ok = bk_error_set(&err, "%s: cannot encode the PNG", path);
  }
  if (ok) ok = bk_file_commit_atomic(&file, path, &messages, &err);
  if (!ok) {
    fprintf(stderr, "make_textures: %s\n", err.message);
    tex_failed = 1;
    return;
  }
  printf("wrote %s\n", path);
}

void write_color(const char* mat, const char* kind, const Canvas* cv) {
  static unsigned char px[N * N * 3];
  for (int i = 0; i < N * N; i++) {
    px[3 * i + 0] = to8(cv->c[i].r);
    px[3 * i + 1] = to8(cv->c[i].g);
    px[3 * i + 2] = to8(cv->c[i].b);
  }
  char name[256];
  snprintf(name, sizeof name, "%s_%s", mat, kind);
  write_png(name, px, 3);
}

/* A small deterministic triangular dither (+-1 byte): nearly flat normal
 * maps (glass, porcelain) and smooth occlusion would otherwise show 8-bit
 * contour bands in their highlights. */
static float dither(int x, int y, uint32_t channel) {
  return (hashf((uint32_t)x, (uint32_t)y, 0xD1u + channel) +
          hashf((uint32_t)x, (uint32_t)y, 0xD4u + channel) - 1.0f) /
         255.0f;
}

/* Tangent-space normals from the height field by central differences
 * (wrapping at the borders, so the map tiles as the heights do). `strength`
 * is the height, in texels, that a height difference of 1.0 represents;
 * `channels` is the stride of `px` (3, or 4 with alpha left alone). */
static void encode_normals(const float* h, float strength, unsigned char* px, int channels) {
  for (int y = 0; y < N; y++)
    for (int x = 0; x < N; x++) {
      int xl = (x + N - 1) % N, xr = (x + 1) % N;
      int yu = (y + N - 1) % N, yd = (y + 1) % N;
      float dhdx = 0.5f * (h[y * N + xr] - h[y * N + xl]) * strength;
      float dhdy = 0.5f * (h[yu * N + x] - h[yd * N + x]) * strength; /* +Y = up */
      float nx = -dhdx, ny = -dhdy, nz = 1.0f;
      float len = sqrtf(nx * nx + ny * ny + nz * nz);
      float e[3] = {nx / len, ny / len, nz / len};
      for (int k = 0; k < 3; k++)
        px[channels * (y * N + x) + k] = to8(e[k] * 0.5f + 0.5f + dither(x, y, (uint32_t)k));
    }
}

void write_normal(const char* mat, const Canvas* cv, float strength) {
  static unsigned char px[N * N * 3];
  encode_normals(cv->h, strength, px, 3);
  char name[256];
  snprintf(name, sizeof name, "%s_normal", mat);
  write_png(name, px, 3);
}

/* Mean of a wrapped N x N field over the (2r + 1)^2 texels around each one:
 * two running sums (rows, then columns), in double so that they do not
 * drift. */
static void box_mean(const float* in, float* out, float* tmp, int r) {
  const double scale = 1.0 / (double)(2 * r + 1);
  for (int y = 0; y < N; y++) {
    double sum = 0.0;
    for (int k = -r; k <= r; k++)
      sum += in[y * N + (k + N) % N];
    for (int x = 0; x < N; x++) {
      tmp[y * N + x] = (float)(sum * scale);
      sum += in[y * N + (x + r + 1) % N] - in[y * N + (x - r + N) % N];
    }
  }
  for (int x = 0; x < N; x++) {
    double sum = 0.0;
    for (int k = -r; k <= r; k++)
      sum += tmp[((k + N) % N) * N + x];
    for (int y = 0; y < N; y++) {
      out[y * N + x] = (float)(sum * scale);
      sum += tmp[((y + r + 1) % N) * N + x] - tmp[((y - r + N) % N) * N + x];
    }
  }
}

/* Ambient occlusion of a height field (texels): how far each texel lies
 * below the mean of its neighbourhood at four radii. A texel d below the
 * mean height r texels around sees the sky above a horizon raised by about
 * atan(d / r), which leaves cos^2 of it, 1 / (1 + (d / r)^2), of the cosine-
 * weighted hemisphere open; the radii's fractions are multiplied (a pit in a
 * valley is darker than either) and raised to `strength`. Texels above
 * their surroundings are open. */
static void occlusion(const float* height, float strength, float* ao) {
  static const int radii[4] = {2, 5, 12, 28};
  float* mean = malloc(sizeof(float) * N * N);
  float* tmp = malloc(sizeof(float) * N * N);
  if (!mean || !tmp) {
    fprintf(stderr, "make_textures: out of memory\n");
    tex_failed = 1;
    for (int i = 0; i < N * N; i++)
      ao[i] = 1.0f;
    free(mean);
    free(tmp);
    return;
  }
  for (int i = 0; i < N * N; i++)
    ao[i] = 1.0f;
  for (int k = 0; k < 4; k++) {
    box_mean(height, mean, tmp, radii[k]);
    for (int i = 0; i < N * N; i++) {
      float t = fmaxf(mean[i] - height[i], 0.0f) / (float)radii[k];
      ao[i] *= 1.0f / (1.0f + t * t);
    }
  }
  for (int i = 0; i < N * N; i++)
    ao[i] = powf(ao[i], strength);
  free(mean);
  free(tmp);
}

/* The albedo is darkened by `cavity` of the occlusion as well: ambient
 * occlusion darkens the sky light only, and without it pores and crevices
 * in direct sun would read as bright as the surface around them (a normal
 * map casts no shadows). */
void write_interior_normal(const char* mat, Canvas* cv, float strength, float ao_strength, float cavity) {
  static unsigned char px[N * N * 4];
  static float height[N * N], ao[N * N];
  for (int i = 0; i < N * N; i++)
    height[i] = cv->h[i] * strength;
  occlusion(height, ao_strength, ao);
  for (int i = 0; i < N * N; i++) {
    ao[i] *= 1.0f - clampf(cv->occ[i], 0.0f, 1.0f);
    cv->c[i] = scale3(cv->c[i], mixf(1.0f, ao[i], cavity));
  }
  encode_normals(cv->h, strength, px, 4);
  for (int y = 0; y < N; y++)
    for (int x = 0; x < N; x++)
      px[4 * (y * N + x) + 3] = to8(ao[y * N + x] + dither(x, y, 3u));
  char name[256];
  snprintf(name, sizeof name, "%s_interior_normal", mat);
  write_png(name, px, 4);
}
