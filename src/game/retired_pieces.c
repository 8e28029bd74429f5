// Pieces the physics budget retired, fading out while they follow the path
// they were on: the world no longer simulates them, so they fly on
// ballistically (no collisions: they are gone within a second, and a ring of
// fixed size bounds what they cost) and stop where they reach the ground.
#include "retired_pieces.h"

#include <math.h>

// Slower than this a piece was at rest or nearly: drawing it flying off
// would show a jolt the world never had.
static const double still_speed = 0.05, still_spin = 0.5;
static const double never = 1e9; // s: it does not reach the ground within any fade

void retired_pieces_init(app_retired_pieces* list, double fade_seconds, bk_vec3 gravity) {
  list->first = 0;
  list->count = 0;
  list->pushed_out = 0;
  list->fade_seconds = fade_seconds > 0.0 ? fade_seconds : 1.0;
  list->gravity = gravity;
}

// The turn a piece has made by time t: its spin held constant.
static bk_quat turn(bk_vec3 spin, double t) {
  double rate = bk_v3_length(spin);
  return rate > 0.0 ? bk_quat_axis_angle(bk_v3_scale(spin, 1.0 / rate), rate * t) : bk_quat_identity();
}

static bk_vec3 center_at(const app_retired_pieces* list, const retired_piece* p, double t) {
  return bk_v3_add(p->center,
                   bk_v3_add(bk_v3_scale(p->velocity, t), bk_v3_scale(list->gravity, 0.5 * t * t)));
}

// When the centre, falling as it does, comes down through `height`
// (never: it does not). The centre starts at or above it.
static double time_to_height(const app_retired_pieces* list, const retired_piece* p, double height) {
  double a = 0.5 * list->gravity.y, b = p->velocity.y, c = fmax(0.0, p->center.y - height);
  if (a == 0.0) return b < 0.0 ? c / -b : never;
  double d = b * b - 4.0 * a * c;
  if (d < 0.0) return never; // pulled up faster than it falls
  double r1 = (-b - sqrt(d)) / (2.0 * a), r2 = (-b + sqrt(d)) / (2.0 * a);
  if (a < 0.0) return fmax(0.0, fmax(r1, r2)); // the later root: on its way down
  double first = fmin(r1, r2);
  return first >= 0.0 ? first : never;
}

// How far its lowest point lies below its centre after turning for t.
static double depth_below_center(const retired_piece* p, double t, const bk_vec3* points, uint32_t count) {
  bk_quat q = turn(p->spin, t);
  bk_vec3 arm = bk_v3_sub(p->start.position, p->center); // centre to the tree frame's origin
  double lowest = 0.0;
  for (uint32_t i = 0; i < count; ++i) {
    bk_vec3 offset = bk_quat_rotate(q, bk_v3_add(arm, bk_quat_rotate(p->start.rotation, points[i])));
    lowest = i == 0 ? offset.y : fmin(lowest, offset.y);
  }
  return -lowest;
}

void retired_pieces_add(app_retired_pieces* list, const bk_retired_body* body, uint32_t tree, int material,
                        const bk_vec3* points, uint32_t point_count) {
  if (list->count == BK_RETIRED_PIECES_MAX) { // the newest matter: the oldest has faded most
    list->first = (list->first + 1) % BK_RETIRED_PIECES_MAX;
    list->count--;
    list->pushed_out++;
  }
  retired_piece* p = &list->items[(list->first + list->count) % BK_RETIRED_PIECES_MAX];
  list->count++;
  *p = (retired_piece){.tree = tree,
                       .node = body->node,
                       .material = material,
                       .start = body->tree_to_world,
                       .center = body->center,
                       .velocity = body->linear_velocity,
                       .spin = body->angular_velocity,
                       .land_time = 0.0,
                       .age = 0.0};
  if (bk_v3_length(p->velocity) < still_speed && bk_v3_length(p->spin) < still_spin) return;
  // The height its centre rests at depends on how it has turned when it
  // lands, which depends on that height: two rounds settle it closely
  // enough for a piece that is gone within a second. A piece already
  // touching the ground (or in it a little) lands at once.
  double t = 0.0;
  for (int round = 0; round < 2; ++round) {
    double rest = points && point_count ? depth_below_center(p, t, points, point_count) : 0.0;
    t = time_to_height(list, p, fmin(p->center.y, rest));
  }
  p->land_time = t;
}

void retired_pieces_update(app_retired_pieces* list, double dt) {
  for (uint32_t i = 0; i < list->count; ++i)
    list->items[(list->first + i) % BK_RETIRED_PIECES_MAX].age += dt;
  // All age alike, so the faded ones are the oldest, at the front.
  while (list->count > 0 && list->items[list->first].age >= list->fade_seconds) {
    list->first = (list->first + 1) % BK_RETIRED_PIECES_MAX;
    list->count--;
  }
}

const retired_piece* retired_pieces_at(const app_retired_pieces* list, uint32_t index) {
  return index < list->count ? &list->items[(list->first + index) % BK_RETIRED_PIECES_MAX] : NULL;
}

double retired_piece_fade(const app_retired_pieces* list, double age) {
  double fade = age / list->fade_seconds;
  return fade > 0.0 ? fmin(fade, 1.0) : 0.0;
}

bk_transform retired_piece_pose(const app_retired_pieces* list, const retired_piece* p, double age) {
  double t = fmin(fmax(age, 0.0), p->land_time);
  bk_quat q = turn(p->spin, t);
  bk_vec3 arm = bk_quat_rotate(q, bk_v3_sub(p->start.position, p->center));
  return (bk_transform){bk_v3_add(center_at(list, p, t), arm),
                        bk_quat_normalize(bk_quat_mul(q, p->start.rotation))};
}
