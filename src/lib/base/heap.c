// Binary min-heap of (key, value) pairs, shared by the builders that take
// the best of many candidates in turn (the largest leaf to split, the
// cheapest edge to collapse).
#include <stdlib.h>

#include "bk_base.h"

// Smaller key first; equal keys by smaller value, so the order never depends
// on how the heap happened to be laid out.
static bool heap_before(bk_heap_item a, bk_heap_item b) {
  return a.key < b.key || (a.key == b.key && a.value < b.value);
}

void bk_heap_push(bk_heap* heap, double key, uint32_t value) {
  if (heap->count == heap->capacity) {
    heap->capacity = bk_grow_capacity(heap->capacity, heap->count + 1);
    heap->items = bk_realloc(heap->items, sizeof(bk_heap_item) * heap->capacity);
  }
  bk_heap_item item = {key, value};
  uint32_t i = heap->count++;
  while (i > 0 && heap_before(item, heap->items[(i - 1) / 2])) {
    heap->items[i] = heap->items[(i - 1) / 2];
    i = (i - 1) / 2;
  }
  heap->items[i] = item;
}

bk_heap_item bk_heap_pop(bk_heap* heap) {
  bk_heap_item top = heap->items[0], last = heap->items[--heap->count];
  uint32_t i = 0;
  for (;;) {
    uint32_t child = 2 * i + 1;
    if (child >= heap->count) break;
    if (child + 1 < heap->count && heap_before(heap->items[child + 1], heap->items[child])) child++;
    if (!heap_before(heap->items[child], last)) break;
    heap->items[i] = heap->items[child];
    i = child;
  }
  if (heap->count) heap->items[i] = last;
  return top;
}

void bk_heap_free(bk_heap* heap) {
  bk_free(heap->items);
  *heap = (bk_heap){0};
}
