// The game's fracture map for the cutout pattern: the cobweb of cracks a
// pane of glass shows round a hit. The cutout pattern needs a map, and the
// game and the simulator take no file for it, so they draw this one.
#include <math.h>
#include <pthread.h>

#include "app.h"

enum {
  MAP_SIZE =
      256,   ///< pixels a side: the cracks' corners stay where they are meant to be within half a percent
  RAYS = 9,  ///< cracks running out from the hit
  RINGS = 3, ///< rings of cracks joining them
};

static uint8_t map[MAP_SIZE * MAP_SIZE];
static pthread_once_t map_once = PTHREAD_ONCE_INIT;

// Distance from p to the segment a-b (pixel units).
static double segment_distance(double px, double py, double ax, double ay, double bx, double by) {
  double dx = bx - ax, dy = by - ay, length2 = dx * dx + dy * dy;
  double t = length2 > 0.0 ? ((px - ax) * dx + (py - ay) * dy) / length2 : 0.0;
  t = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
  double ex = ax + t * dx - px, ey = ay + t * dy - py;
  return sqrt(ex * ex + ey * ey);
}

// Marks the pixels within 1.5 pixels of a crack: three pixels wide, so a
// region never leaks into the next one through a diagonal.
static void draw_crack(double ax, double ay, double bx, double by) {
  int x0 = (int)floor(fmin(ax, bx) - 2.0), x1 = (int)ceil(fmax(ax, bx) + 2.0);
  int y0 = (int)floor(fmin(ay, by) - 2.0), y1 = (int)ceil(fmax(ay, by) + 2.0);
  for (int y = y0 < 0 ? 0 : y0; y <= y1 && y < MAP_SIZE; ++y)
    for (int x = x0 < 0 ? 0 : x0; x <= x1 && x < MAP_SIZE; ++x)
      if (segment_distance(x + 0.5, y + 0.5, ax, ay, bx, by) <= 1.5) map[y * MAP_SIZE + x] = 255;
}

static void draw_map(void) {
  // Fixed, uneven angles and radii (a regular web looks drawn, not broken);
  // the rays run past the map's edge so every region between them is closed.
  static const double angles[RAYS] = {0.15, 0.78, 1.35, 2.05, 2.60, 3.30, 3.95, 4.70, 5.45};
  static const double radii[RINGS] = {0.11, 0.24, 0.40};
  static const double wobble[RAYS] = {1.0, 0.86, 1.12, 0.93, 1.05, 0.82, 1.1, 0.95, 0.88};
  const double centre = 0.5 * MAP_SIZE;
  for (int r = 0; r < RAYS; ++r)
    draw_crack(centre, centre, centre + MAP_SIZE * cos(angles[r]), centre + MAP_SIZE * sin(angles[r]));
  for (int ring = 0; ring < RINGS; ++ring)
    for (int r = 0; r < RAYS; ++r) {
      int next = (r + 1) % RAYS;
      // Each ring crosses a ray at its own distance, so the rings are not circles.
      double a = MAP_SIZE * radii[ring] * wobble[(r + ring) % RAYS];
      double b = MAP_SIZE * radii[ring] * wobble[(next + ring) % RAYS];
      draw_crack(centre + a * cos(angles[r]), centre + a * sin(angles[r]), centre + b * cos(angles[next]),
                 centre + b * sin(angles[next]));
    }
}

const uint8_t* app_cutout_map(uint32_t* size) {
  // The panel's worker and the main thread may both ask: drawn exactly once.
  pthread_once(&map_once, draw_map);
  *size = MAP_SIZE;
  return map;
}
