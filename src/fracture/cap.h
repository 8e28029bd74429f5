// Internal: triangulation of the planar polygons that close a cut.
#pragma once

#include "bk_fracture.h"

/// Scratch state and the GLU tessellator; reused across caps.
typedef struct bk_cap bk_cap;

bk_cap* bk_cap_create(void);
void bk_cap_destroy(bk_cap* cap);

/// Triangulates the region bounded by closed loops given as directed edges
/// between local vertices 0..vertex_count-1 (2D coordinates in `xy`). Loops
/// may be nested (polygons, holes, islands in holes: ODD winding). The
/// triangles use only the given vertices and are oriented so that their
/// outer edges are exactly the input edges; this is verified. On success
/// *triangles points to 3 * *triangle_count local indices owned by `cap`,
/// valid until its next use.
bool bk_cap_triangulate(bk_cap* cap, const uint32_t* edges, uint32_t edge_count, const double* xy,
                        uint32_t vertex_count, const uint32_t** triangles, uint32_t* triangle_count,
                        bk_error* err);

/// Re-triangulates planar faces over their true corners (see simplify.c).
typedef struct bk_face_simplifier bk_face_simplifier;

bk_face_simplifier* bk_face_simplifier_create(void);
void bk_face_simplifier_destroy(bk_face_simplifier* fs);
/// Replaces the triangles of each planar face of a closed mesh by a
/// triangulation of its outline, dropping vertices inside faces and on straight
/// edges between two faces. Returns false, leaving the mesh untouched, when a
/// face cannot be re-triangulated.
bool bk_face_simplifier_run(bk_face_simplifier* fs, bk_mesh* mesh);

/// Tags of source-mesh faces start here, above any cut id (cut ids are node
/// index + 1), so a tag names either one cut or one planar source face.
#define BK_SOURCE_FACE_TAG 0x80000000u

/// Labels each planar region of a source mesh (adjacent coplanar triangles
/// sharing corners and material) with its own tag from BK_SOURCE_FACE_TAG.
void bk_label_planar_faces(bk_mesh* mesh);
