// runtime (private): the stress system of one cluster (stress_system.c):
// fragments as rigid nodes, bonds as elastic beams, solved for the forces
// that hold the cluster's weight up on its supports.
#pragma once

#include <stdbool.h>
#include <stdint.h>

#include "bk_geom.h"

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
  double* block;     // 36 per node: its Cholesky-factored stiffness block
  double* work;      // 4 x 6 per node
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
} rt_stress;

/// A system over these nodes and bonds, with x = 0 (set x to warm-start,
/// then load). group_keys[g][node] groups the nodes for coarse level g + 1
/// (nodes with one key move as one; each level's groups must nest in the
/// next's), for up to group_levels levels.
rt_stress* rt_stress_create(const rt_stress_node* nodes, uint32_t node_count, const rt_stress_bond* bonds,
                            uint32_t bond_count, const uint32_t* const* group_keys, uint32_t group_levels);
void rt_stress_destroy(rt_stress* system);
/// Loads the free nodes with their weight under gravity (tree frame) and
/// restarts the iteration from the current x.
void rt_stress_load(rt_stress* system, bk_vec3 gravity);
/// Runs at most max_iterations conjugate-gradient steps, stopping once the
/// unbalanced force is at most tolerance x the load; returns those run.
uint32_t rt_stress_iterate(rt_stress* system, uint32_t max_iterations, double tolerance);
bool rt_stress_converged(const rt_stress* system, double tolerance);
/// Bond evaluations one iteration costs (the unit of the runtime's budget).
uint64_t rt_stress_iteration_cost(const rt_stress* system);
/// Bond k's stress (Pa) at the current x: compression, tension, shear.
void rt_stress_bond_stress(const rt_stress* system, uint32_t k, double out[3]);
