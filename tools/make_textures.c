/*
 * make_textures: writes the game's material textures as PNG files.
 *
 *   make_textures OUTPUT_DIR
 *
 * Every texture is 256x256, tiles seamlessly in both directions and is fully
 * deterministic (fixed seeds, no rand()). For each material M in
 * stone, brick, concrete, porcelain, glass, eggshell and wood it writes
 *
 *   M_albedo.png           RGB surface colour (sRGB),
 *   M_normal.png           RGB tangent-space normal map of the same height field,
 *   M_interior.png         RGB colour of freshly broken / cut surfaces (sRGB),
 *   M_interior_normal.png  RGBA: tangent-space normal map of the broken
 *                          surface's relief, A = ambient occlusion (255 open),
 *
 * plus ground_albedo.png and ground_normal.png (stone paving slabs).
 *
 * Normal maps use the OpenGL convention: X right (+u), Y up towards image
 * row 0, Z out of the surface; stored as n * 0.5 + 0.5 (128, 128, 255 flat).
 *
 * tex.h lists the generator's parts: noise (tex_noise.c), output
 * (tex_output.c), outer surfaces (tex_surface.c) and the interiors
 * (tex_interior_masonry.c, tex_interior_vitreous.c, tex_interior_wood.c).
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <stb_image_write.h>

#include "tex.h"

typedef struct {
  const char* name;
  void (*surface)(Canvas*);
  void (*interior)(Canvas*);
  float normal_strength;
  /* the interior's: height texels per unit, occlusion exponent, and how
   * much of the occlusion darkens the interior colour too */
  float interior_strength, ao_strength, cavity;
} Material;

static const Material materials[] = {
    {"stone", make_stone, make_stone_interior, 6.0f, 8.0f, 1.0f, 0.5f},
    {"brick", make_brick, make_brick_interior, 5.0f, 7.0f, 1.0f, 0.5f},
    {"concrete", make_concrete, make_concrete_interior, 2.5f, 8.0f, 1.0f, 0.5f},
    {"porcelain", make_porcelain, make_porcelain_interior, 1.0f, 5.0f, 1.0f, 0.4f},
    {"glass", make_glass, make_glass_interior, 0.35f, 4.0f, 1.0f, 0.3f},
    {"eggshell", make_eggshell, make_eggshell_interior, 0.8f, 5.0f, 1.0f, 0.4f},
    {"wood", make_wood, make_wood_interior, 3.0f, 6.0f, 1.0f, 0.5f},
    {"ground", make_ground, NULL, 6.0f, 0.0f, 0.0f, 0.0f},
};

int main(int argc, char** argv) {
  if (argc != 2) {
    fprintf(stderr, "usage: %s OUTPUT_DIR\n", argv[0]);
    return 2;
  }
  tex_outdir = argv[1];
  if (mkdir(tex_outdir, 0777) != 0 && errno != EEXIST) {
    fprintf(stderr, "make_textures: cannot create %s: %s\n", tex_outdir, strerror(errno));
    return 1;
  }
  stbi_write_png_compression_level = 9;

  Canvas* cv = malloc(sizeof *cv);
  if (!cv) {
    fprintf(stderr, "make_textures: out of memory\n");
    return 1;
  }
  for (size_t m = 0; m < sizeof materials / sizeof materials[0]; m++) {
    const Material* mat = &materials[m];
    memset(cv, 0, sizeof *cv);
    mat->surface(cv);
    write_color(mat->name, "albedo", cv);
    write_normal(mat->name, cv, mat->normal_strength);
    if (mat->interior) {
      memset(cv, 0, sizeof *cv);
      mat->interior(cv);
      /* the occlusion darkens the colour too: normals and occlusion first */
      write_interior_normal(mat->name, cv, mat->interior_strength, mat->ao_strength, mat->cavity);
      write_color(mat->name, "interior", cv);
    }
  }
  free(cv);
  return tex_failed ? 1 : 0;
}
