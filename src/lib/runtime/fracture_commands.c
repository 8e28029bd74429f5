// Fracture commands: bonds to break, named by the cluster they are inside.
// The stress stage (stress.c) reports the bonds its solve finds past their
// limits this way and leaves the breaking to the core, as Blast's stress
// extension emits bond fracture commands for its core to apply; a caller
// may also filter, defer or make its own.
#include "runtime_internal.h"

// The command's bond, when it is intact and inside the live cluster it names.
static bool command_valid(const bk_runtime* rt, const bk_fracture_command* command) {
  if (command->cause != BK_BREAK_DAMAGE && command->cause != BK_BREAK_STRESS) return false;
  const rt_cluster* c = rt_find_cluster(rt, command->cluster);
  if (!c) return false;
  const rt_breakable* b = &rt->breakables[c->breakable];
  if (command->bond >= b->tree->bond_count || b->bond_broken[command->bond]) return false;
  const bk_bond* bd = &b->tree->bonds[command->bond];
  uint32_t slot = command->cluster.index;
  return b->leaf_cluster[bd->leaf_a] == slot && b->leaf_cluster[bd->leaf_b] == slot;
}

uint32_t bk_runtime_apply_fracture_commands(bk_runtime* rt, const bk_fracture_command* commands,
                                            uint32_t count) {
  if (!rt || !commands) return 0;
  uint32_t broken = 0;
  for (uint32_t i = 0; i < count; ++i) {
    const bk_fracture_command* command = &commands[i];
    if (!command_valid(rt, command)) continue;
    uint32_t slot = command->cluster.index;
    rt_journal_break(rt, slot, command->bond, command->cause);
    rt_break_bond(rt, slot, command->bond, command->position, command->velocity, command->cause);
    if (command->cause == BK_BREAK_STRESS) rt->stress_bonds_broken++;
    rt_queue_split(rt, slot); // once per cluster: the queue keeps its first place
    broken++;
  }
  return broken;
}
