// runtime (private): the journal's entry kinds, shared by its writer
// (journal.c) and its reader (journal_apply.c); the layout is described at
// the top of journal.c.
#pragma once

enum {
  ENTRY_HIT = 1,
  ENTRY_BREAK,
  ENTRY_SPLIT,
  ENTRY_REMOVE,
  ENTRY_REFINE,
  ENTRY_MATERIAL,
  ENTRY_BREAKABLE_REMOVED,
  ENTRY_BREAKABLE_ADDED,
  MATERIAL_DOUBLES = 9,
};
