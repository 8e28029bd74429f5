// runtime (private): the saved state's format, shared by state_save.c and
// state_load.c (written and read with base's bk_bytes.h, as the world's
// state in world_state.c is).
//
// Layout: a fixed 32-byte header, then the payload.
//   header:  "BKSTATE\0" | u32 version | u32 0x01020304 | u64 payload size | u64 XXH3-64 of the payload
//   payload: u32 breakable_count, per slot { u32 alive | u32 generation | when alive:
//              u64 source_hash | u32 node_count, leaf_count, bond_count (the caller's tree)
//              material { u32 name length | name | f64 density, frailty, bond_strength | u32 accumulate
//                         f64 friction, restitution, compression, tension, shear, refine_strength }
//              u64 grown tree bytes (0: not refined) | .mtree bytes
//              bond_count x { u8 broken | f64 hit points } | leaf_count x u8 (1 anchored, 2 refining) }
//            u32 cluster_count, per slot { u32 alive | u32 generation | when alive:
//              u32 breakable | u32 flags (1 queued, 2 dirty) | u32 leaf_count | leaves (ascending) }
//            u32 free slots, in order | u32 split queue entries
//            u32 jobs, each { u32 breakable, node, due_call | f64 bounds[6]
//              u32 neighbours { u32 node | f64 area } | u32 hits { u64 sequence | f64 local[3], impulse,
//              frailty } }
//            u32 refine_calls, refine_marked, bonds_broken, splits, stress_bonds_broken,
//                stress_clusters_solved, stress_iterations, stress_cursor, refined_leaves, refine_failed
//            u64 hit_sequence
// Every field little endian, a double by its bits: never a struct's bytes.
#pragma once

#include <stdint.h>
#include <string.h>

#include "bk_base.h"
#include "bk_bytes.h"

#define RT_STATE_VERSION 1u
#define RT_STATE_HEADER_BYTES 32u
#define RT_STATE_ENDIAN_MARKER 0x01020304u
static const uint8_t rt_state_magic[8] = {'B', 'K', 'S', 'T', 'A', 'T', 'E', '\0'};
