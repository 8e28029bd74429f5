// Internal to the executable: pieces the physics budget retired, kept by the
// game for a moment so that they fade out where they were going instead of
// vanishing. No window or renderer: the game draws them (game_budget.c).
#pragma once

#include <stdbool.h>
#include <stdint.h>

#include <breakables/bullet.h>

/// At most this many fade at once; a newer piece pushes out the oldest.
enum { BK_RETIRED_PIECES_MAX = 512 };

/// One retired piece: where it left the world, and how it moved then.
typedef struct retired_piece {
  uint32_t tree;      ///< the scene's tree it belongs to (bk_breakable_id.index)
  uint32_t node;      ///< its one mesh-tree node
  int material;       ///< the renderer's material it is drawn with
  bk_transform start; ///< the tree frame's placement when it retired
  bk_vec3 center;     ///< its centre of mass then
  bk_vec3 velocity;   ///< of the centre of mass
  bk_vec3 spin;       ///< angular velocity, rad/s
  double land_time;   ///< s after retiring when it lies on the ground and stops (0: it never moves)
  double age;         ///< s since it retired
} retired_piece;

/// A fixed-capacity ring of retired pieces, oldest first.
typedef struct app_retired_pieces {
  retired_piece items[BK_RETIRED_PIECES_MAX];
  uint32_t first, count;
  double fade_seconds; ///< from retired (fade 0) to gone (fade 1)
  bk_vec3 gravity;     ///< what pulls them while they fly
  uint32_t pushed_out; ///< pieces dropped to make room before they had faded
} app_retired_pieces;

/// Empties the list and sets how long a piece takes to fade (> 0 s) and the gravity it falls by.
void retired_pieces_init(app_retired_pieces* list, double fade_seconds, bk_vec3 gravity);
/// Adds a piece the world retired, drawn as `material` from the scene's tree
/// `tree`. `points` (tree frame, may be NULL) are its mesh's vertices: they
/// decide the height at which it rests on the ground (y = 0), where it then
/// stays; a piece that barely moved stays where it is.
void retired_pieces_add(app_retired_pieces* list, const bk_retired_body* body, uint32_t tree, int material,
                        const bk_vec3* points, uint32_t point_count);
/// Ages every piece by dt (s) and drops those that have faded out.
void retired_pieces_update(app_retired_pieces* list, double dt);
/// The piece at index (0 = the oldest), NULL past the end.
const retired_piece* retired_pieces_at(const app_retired_pieces* list, uint32_t index);
/// How far a piece has faded at `age` s (0 = opaque, 1 = gone).
double retired_piece_fade(const app_retired_pieces* list, double age);
/// The tree frame's placement of a piece at `age` s after it retired:
/// ballistic (its centre falls under gravity and it keeps turning) until it
/// lands, then still.
bk_transform retired_piece_pose(const app_retired_pieces* list, const retired_piece* piece, double age);
