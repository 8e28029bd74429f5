// setjmp and longjmp for GLU's tessellator in this build (web/src/tess/setjmp.h
// sends its calls here). It takes a setjmp only to leave when memory
// runs out; emscripten 3.1.6's own longjmp support sends every call made
// inside that function through a JavaScript trampoline, several times
// slower. Here setjmp returns once, and a longjmp, which only running out of
// memory makes, ends the module as bk_alloc would.
#include <stdio.h>
#include <stdlib.h>

#include "tess/setjmp.h"

int web_tess_setjmp(jmp_buf env) {
  (void)env;
  return 0;
}

void web_tess_longjmp(jmp_buf env, int value) {
  (void)env, (void)value;
  fputs("breakables: GLU's tessellator ran out of memory\n", stderr);
  abort();
}
