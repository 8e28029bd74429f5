// The WebAssembly bridge's own declarations: what web_tree.c and
// web_runtime.c share. Only public headers of the libraries are used: the
// bridge is a program over them, like the game.
#ifndef BK_WEB_BRIDGE_H
#define BK_WEB_BRIDGE_H

#include <breakables/authoring.h>
#include <breakables/base.h>
#include <breakables/runtime.h>
#include <emscripten/emscripten.h>

/// A tree as the page holds it: the tree, and its meshes as the GPU and a
/// physics engine take them (float positions and normals per corner, 32-bit
/// indices per node), made once so JavaScript reads them in place.
typedef struct web_tree {
  bk_mesh_tree tree;
  double build_ms;
  float* positions;      // 3 per corner, all nodes
  float* normals;        // 3 per corner
  uint32_t* indices;     // 3 per triangle, each node's from 0
  uint8_t* inside;       // per triangle: 1 for a cut face
  uint32_t* ranges;      // per node: first corner, corners, first index, indices
  float* hull_points;    // per node: its distinct positions, 3 each
  uint32_t* hull_ranges; // per node: first point, points
} web_tree;

/// The last error's one line (what a failed call left), for JavaScript.
void web_set_error(const bk_error* err);
void web_set_error_text(const char* text);

#endif
