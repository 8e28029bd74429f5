// <setjmp.h> as GLU's tessellator sees it in the WebAssembly build (its
// include directory comes first): its setjmp and longjmp go to
// web/src/tess_jump.c, not to emscripten's longjmp support, which would send
// every call made inside the function taking the setjmp through a JavaScript
// trampoline.
#ifndef BK_WEB_TESS_SETJMP_H
#define BK_WEB_TESS_SETJMP_H

typedef unsigned long jmp_buf[8];

int web_tess_setjmp(jmp_buf env);
void web_tess_longjmp(jmp_buf env, int value);

#define setjmp(env) web_tess_setjmp(env)
#define longjmp(env, value) web_tess_longjmp(env, value)

#endif
