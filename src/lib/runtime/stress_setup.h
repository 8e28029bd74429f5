// runtime (private): the stress system of one cluster, its data and how it
// is made (stress_setup.c): fragments as rigid nodes, bonds as elastic
// beams, and the multigrid's coarse levels over them. Solving it is
// stress_system.h's.
#pragma once

#include <stdbool.h>
#include <stdint.h>

#include "bk_base.h"

enum { RT_STRESS_DOF = 6 }; ///< unknowns per node: displacement and rotation

static inline void rt_stress_cross(const double a[3], const double b[3], double out[3]) {
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}

static inline double rt_stress_dot3(const double a[3], const double b[3]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/// A node of the system: a fragment.
typedef struct rt_stress_node {
  bk_vec3 centroid; ///< tree frame
  double mass;      ///< kg
  bool fixed;       ///< a support: anchored, or where the cluster rests
} rt_stress_node;

/// A bond of the system, between nodes a and b (indices into the nodes).
typedef struct rt_stress_bond {
  uint32_t a, b;
  bk_vec3 centroid, normal; ///< tree frame; normal from a to b
  double area;
  uint32_t tree_bond; ///< the tree's index of the bond
} rt_stress_bond;

/// One level of the multigrid: level 0 is the fragments, each coarser level
/// groups the nodes of the one before (see stress_system.c).
typedef struct rt_stress_level {
  uint32_t node_count, bond_count;
  uint8_t* fixed;
  double* centroid;  // 3 per node
  uint32_t* ends;    // 2 per bond
  double* frame;     // 9 per bond: normal, lever arm from a, lever arm from b
  double* stiffness; // 4 per bond: axial, shear, bend, twist
  double* inverse;   // 36 per node: the damped inverse of its stiffness block
  double* work;      // 4 x 6 per node
  // Levels between the finest and the coarsest: the matrix assembled, the
  // bonds between one pair of nodes merged into one block (coarse nodes
  // share many bonds): each node's own block, and per pair (first < second)
  // the block coupling the first's rows to the second's motion.
  double* diagonal; // 36 per node
  uint32_t pair_count;
  uint32_t* pair_ends; // 2 per pair
  double* pair_block;  // 36 per pair
  // Coarse levels: the node of each node of the level before, and its
  // centroid's offset from that node's (3 per node of the level before).
  uint32_t* coarse_of;
  double* offset;
  // The coarsest level: its matrix over its free nodes, factored.
  double* dense;
  uint32_t* dense_index; // per node: its place in the dense matrix (UINT32_MAX: fixed)
  uint32_t dense_size;
} rt_stress_level;

#define RT_STRESS_LEVELS_MAX 8

/// The system and its conjugate-gradient state.
typedef struct rt_stress {
  rt_stress_level levels[RT_STRESS_LEVELS_MAX];
  uint32_t level_count;
  uint32_t node_count, bond_count;
  double* mass;                  // per node
  double* area;                  // per bond
  uint32_t* tree_bond;           // per bond
  double *x, *b, *r, *z, *p, *q; // 6 per node each (x: displacement and rotation)
  double rz, load_norm, residual;
  bk_vec3 gravity; ///< the load's gravity (tree frame)
  bool loaded;     ///< rt_stress_load was called (and the residual is its)
  // The setup, made a level per step (rt_stress_setup_step) so that no
  // call pays for all of a big system's: ready once the coarsest is
  // factored. Until then: the groups (group_levels x node_count), the next
  // to try, and for the newest level a fragment of each node and the
  // nodes' masses.
  bool ready;
  uint32_t* group_keys;
  uint32_t group_levels, next_group;
  uint32_t* member;
  double* level_mass;
} rt_stress;

/// A system over these nodes and bonds, with x = 0 (set x to warm-start),
/// not yet ready: run rt_stress_setup_step until it is, then load.
/// group_keys[g][node] groups the nodes for coarse level g + 1 (nodes with
/// one key move as one; each level's groups must nest in the next's), for
/// up to group_levels levels.
rt_stress* rt_stress_create(const rt_stress_node* nodes, uint32_t node_count, const rt_stress_bond* bonds,
                            uint32_t bond_count, const uint32_t* const* group_keys, uint32_t group_levels);
void rt_stress_destroy(rt_stress* system);
/// What making the system cost (and gathering its bonds), in the unit of
/// rt_stress_iteration_cost.
uint64_t rt_stress_create_cost(const rt_stress* system);
/// One step of the setup (the next coarse level, or the coarsest's
/// factor); returns its cost in the unit of rt_stress_iteration_cost.
uint64_t rt_stress_setup_step(rt_stress* system);
