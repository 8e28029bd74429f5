// The game's list of pieces the physics budget retired, without a window:
// each fades from 0 to 1 over the fade time and is dropped then, oldest
// first; a full list keeps the newest; a piece flies ballistically and stops
// on the ground without going through it; one at rest stays where it was.
#include <string.h>

#include "ensure.h"
#include "retired_pieces.h"

static const bk_vec3 gravity = {0.0, -9.81, 0.0};

static bk_retired_body body_at(bk_vec3 center, bk_vec3 velocity, bk_vec3 spin, uint32_t node) {
  bk_retired_body b = {0};
  b.node = node;
  b.center = center;
  b.linear_velocity = velocity;
  b.angular_velocity = spin;
  // The tree frame somewhere off the piece, turned, as a fragment's is.
  b.tree_to_world.position = bk_v3_add(center, bk_v3(-0.3, 0.2, 0.1));
  b.tree_to_world.rotation = bk_quat_axis_angle(bk_v3_normalize(bk_v3(1, 2, 3)), 0.7);
  return b;
}

// The corners of a cube of side `side` round the piece's centre, in the tree frame.
static void cube_points(const bk_retired_body* b, double side, bk_vec3 out[8]) {
  bk_transform inverse = bk_transform_inverse(b->tree_to_world);
  for (int i = 0; i < 8; ++i) {
    bk_vec3 corner =
        bk_v3((i & 1 ? 0.5 : -0.5) * side, (i & 2 ? 0.5 : -0.5) * side, (i & 4 ? 0.5 : -0.5) * side);
    out[i] = bk_transform_point(inverse, bk_v3_add(b->center, corner));
  }
}

static double lowest_y(bk_transform pose, const bk_vec3* points, int count) {
  double lowest = INFINITY;
  for (int i = 0; i < count; ++i)
    lowest = fmin(lowest, bk_transform_point(pose, points[i]).y);
  return lowest;
}

static void test_fade_and_drop(void) {
  static app_retired_pieces list;
  retired_pieces_init(&list, 1.0, gravity);
  bk_retired_body b = body_at(bk_v3(0, 1, 0), bk_v3(0, 0, 0), bk_v3(0, 0, 0), 5);
  retired_pieces_add(&list, &b, 2, 7, NULL, 0);
  ENSURE(list.count == 1);
  const retired_piece* p = retired_pieces_at(&list, 0);
  ENSURE(p->tree == 2 && p->node == 5 && p->material == 7);
  ENSURE_SMALL(retired_piece_fade(&list, p->age), 0.0, 0.0);
  double previous = 0.0, last_seen = 0.0;
  int steps = 0;
  while (list.count > 0 && steps < 1000) {
    retired_pieces_update(&list, 1.0 / 60.0);
    steps++;
    p = retired_pieces_at(&list, 0);
    if (!p) break;
    double fade = retired_piece_fade(&list, p->age);
    ENSURE(fade > previous && fade < 1.0); // it only fades further, and is dropped before it is gone
    ENSURE_SMALL(fade, steps / 60.0, 1e-9);
    previous = last_seen = fade;
  }
  ENSURE(list.count == 0);
  ENSURE(steps == 60);      // gone after the fade time: one second at 60 steps a second
  ENSURE(last_seen > 0.98); // nearly gone when it was last drawn
  ENSURE(retired_pieces_at(&list, 0) == NULL);
  ENSURE_SMALL(retired_piece_fade(&list, 0.5), 0.5, 1e-12);
  ENSURE_SMALL(retired_piece_fade(&list, 3.0), 1.0, 0.0);
  ENSURE_SMALL(retired_piece_fade(&list, -1.0), 0.0, 0.0);
  retired_pieces_init(&list, 0.25, gravity); // a shorter fade is as long as asked
  retired_pieces_add(&list, &b, 0, 0, NULL, 0);
  retired_pieces_update(&list, 0.125);
  ENSURE_SMALL(retired_piece_fade(&list, retired_pieces_at(&list, 0)->age), 0.5, 1e-12);
  retired_pieces_update(&list, 0.125);
  ENSURE(list.count == 0);
}

static void test_oldest_dropped_first(void) {
  static app_retired_pieces list;
  retired_pieces_init(&list, 1.0, gravity);
  bk_retired_body a = body_at(bk_v3(0, 1, 0), bk_v3(0, 0, 0), bk_v3(0, 0, 0), 1);
  bk_retired_body b = body_at(bk_v3(0, 1, 0), bk_v3(0, 0, 0), bk_v3(0, 0, 0), 2);
  retired_pieces_add(&list, &a, 0, 0, NULL, 0);
  retired_pieces_update(&list, 0.6);
  retired_pieces_add(&list, &b, 0, 0, NULL, 0);
  ENSURE(list.count == 2 && retired_pieces_at(&list, 0)->node == 1);
  retired_pieces_update(&list, 0.5); // a is 1.1 s old: gone; b 0.5 s
  ENSURE(list.count == 1 && retired_pieces_at(&list, 0)->node == 2);
  ENSURE_SMALL(retired_pieces_at(&list, 0)->age, 0.5, 1e-12);
  retired_pieces_update(&list, 0.5);
  ENSURE(list.count == 0);
  ENSURE(list.pushed_out == 0);
}

static void test_capacity_keeps_newest(void) {
  static app_retired_pieces list;
  retired_pieces_init(&list, 1.0, gravity);
  const uint32_t extra = 37, total = BK_RETIRED_PIECES_MAX + extra;
  for (uint32_t i = 0; i < total; ++i) {
    bk_retired_body b = body_at(bk_v3(0, 1, 0), bk_v3(0, 0, 0), bk_v3(0, 0, 0), i);
    retired_pieces_add(&list, &b, 0, 0, NULL, 0);
    if (i % 100 == 99) retired_pieces_update(&list, 0.001); // older pieces are older
  }
  ENSURE(list.count == BK_RETIRED_PIECES_MAX);
  ENSURE(list.pushed_out == extra);
  for (uint32_t i = 0; i < BK_RETIRED_PIECES_MAX; ++i)
    ENSURE_MSG(retired_pieces_at(&list, i)->node == extra + i, "piece %u is node %u", i,
               retired_pieces_at(&list, i)->node);
  ENSURE(retired_pieces_at(&list, BK_RETIRED_PIECES_MAX) == NULL);
  // Dropped in turn after the fade, the oldest first, and the ring empties.
  retired_pieces_update(&list, 1.0 - 0.0045);
  ENSURE(list.count < BK_RETIRED_PIECES_MAX && list.count > 0);
  ENSURE(retired_pieces_at(&list, 0)->node > extra);
  retired_pieces_update(&list, 0.01);
  ENSURE(list.count == 0);
}

// A point piece: its centre follows c + v t + g t^2 / 2, the tree frame with
// it, until the centre is on the ground; it stays there.
static void test_ballistic_until_ground(void) {
  static app_retired_pieces list;
  retired_pieces_init(&list, 1.0, gravity);
  bk_vec3 c = bk_v3(0.5, 2.0, -1.0), v = bk_v3(2.0, 3.0, 1.0);
  bk_retired_body b = body_at(c, v, bk_v3(0, 0, 0), 0);
  retired_pieces_add(&list, &b, 0, 0, NULL, 0);
  const retired_piece* p = retired_pieces_at(&list, 0);
  double land = (3.0 + sqrt(9.0 + 2.0 * 9.81 * 2.0)) / 9.81; // y(t) = 2 + 3t - 4.905 t^2 = 0
  ENSURE_SMALL(p->land_time, land, 1e-9);
  for (double t = 0.0; t < land; t += 0.1) {
    bk_transform pose = retired_piece_pose(&list, p, t);
    bk_vec3 expected =
        bk_v3_add(b.tree_to_world.position, bk_v3_add(bk_v3_scale(v, t), bk_v3(0, -4.905 * t * t, 0)));
    ENSURE_SMALL(bk_v3_length(bk_v3_sub(pose.position, expected)), 0.0, 1e-9);
    bk_quat q = pose.rotation, r = b.tree_to_world.rotation;
    ENSURE_SMALL(fabs(q.x * r.x + q.y * r.y + q.z * r.z + q.w * r.w), 1.0, 1e-12); // no spin, no turn
  }
  bk_transform landed = retired_piece_pose(&list, p, land), later = retired_piece_pose(&list, p, 5.0);
  bk_vec3 centre = bk_transform_point(later, bk_transform_point(bk_transform_inverse(b.tree_to_world), c));
  ENSURE_SMALL(centre.y, 0.0, 1e-9);
  ENSURE_SMALL(bk_v3_length(bk_v3_sub(landed.position, later.position)), 0.0, 1e-12);
}

// A spinning cube of 20 cm thrown up and sideways: never more than a little
// in the ground on its way, resting on it at the end.
static void test_cube_rests_on_ground(void) {
  static app_retired_pieces list;
  retired_pieces_init(&list, 1.0, gravity);
  const double side = 0.2;
  bk_retired_body b = body_at(bk_v3(0, 0.6, 0), bk_v3(1.5, 1.0, 0), bk_v3(0, 0, 0), 0);
  bk_vec3 points[8];
  cube_points(&b, side, points);
  retired_pieces_add(&list, &b, 0, 0, points, 8);
  const retired_piece* p = retired_pieces_at(&list, 0);
  // Not turning, it lands exactly when its lowest face meets the ground.
  ENSURE_SMALL(lowest_y(retired_piece_pose(&list, p, 3.0), points, 8), 0.0, 1e-9);
  ENSURE_SMALL(p->land_time, (1.0 + sqrt(1.0 + 2.0 * 9.81 * 0.5)) / 9.81, 1e-9);
  bk_retired_body spun = body_at(bk_v3(0, 0.6, 0), bk_v3(1.5, 1.0, 0), bk_v3(3.0, -2.0, 4.0), 0);
  cube_points(&spun, side, points);
  retired_pieces_add(&list, &spun, 0, 0, points, 8);
  p = retired_pieces_at(&list, 1);
  ENSURE(p->land_time > 0.3 && p->land_time < 1.0);
  for (double t = 0.0; t <= 2.0; t += 1.0 / 120.0)
    ENSURE_MSG(lowest_y(retired_piece_pose(&list, p, t), points, 8) > -0.1 * side, "at %g s", t);
  ENSURE_SMALL(lowest_y(retired_piece_pose(&list, p, 2.0), points, 8), 0.0, 0.1 * side);
}

// A piece at rest, or one sliding along the ground, stays where it was.
static void test_still_pieces_stay(void) {
  static app_retired_pieces list;
  retired_pieces_init(&list, 1.0, gravity);
  bk_retired_body rest = body_at(bk_v3(0, 0.8, 0), bk_v3(0.01, 0.0, 0.02), bk_v3(0.1, 0, 0), 0);
  bk_vec3 points[8];
  cube_points(&rest, 0.2, points);
  retired_pieces_add(&list, &rest, 0, 0, points, 8);
  bk_retired_body sliding = body_at(bk_v3(0, 0.1, 0), bk_v3(1.0, 0.0, 0.5), bk_v3(0, 0, 0), 1);
  cube_points(&sliding, 0.2, points);
  retired_pieces_add(&list, &sliding, 0, 0, points, 8);
  for (uint32_t i = 0; i < 2; ++i) {
    const retired_piece* p = retired_pieces_at(&list, i);
    ENSURE_SMALL(p->land_time, 0.0, 1e-6);
    bk_transform pose = retired_piece_pose(&list, p, 0.7);
    ENSURE_SMALL(bk_v3_length(bk_v3_sub(pose.position, p->start.position)), 0.0, 1e-6);
  }
}

int main(void) {
  RUN(test_fade_and_drop);
  RUN(test_oldest_dropped_first);
  RUN(test_capacity_keeps_newest);
  RUN(test_ballistic_until_ground);
  RUN(test_cube_rests_on_ground);
  RUN(test_still_pieces_stay);
  return 0;
}
