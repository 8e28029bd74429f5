// A thread that runs one job at a time: the game steps its world on it
// while the driver rasterizes the frame just submitted.
#include <pthread.h>

#include <stdbool.h>

#include <breakables/base.h>

#include "worker.h"

struct app_worker {
  pthread_t thread;
  pthread_mutex_t lock;
  pthread_cond_t changed;
  void (*job)(void*);
  void* argument;
  bool busy, quit;
};

static void* worker_main(void* self) {
  app_worker* w = self;
  pthread_mutex_lock(&w->lock);
  for (;;) {
    while (!w->busy && !w->quit)
      pthread_cond_wait(&w->changed, &w->lock);
    if (w->quit) break;
    pthread_mutex_unlock(&w->lock);
    w->job(w->argument);
    pthread_mutex_lock(&w->lock);
    w->busy = false;
    pthread_cond_broadcast(&w->changed);
  }
  pthread_mutex_unlock(&w->lock);
  return NULL;
}

app_worker* worker_create(void) {
  app_worker* w = bk_calloc(1, sizeof *w);
  pthread_mutex_init(&w->lock, NULL);
  pthread_cond_init(&w->changed, NULL);
  if (pthread_create(&w->thread, NULL, worker_main, w) != 0) {
    pthread_cond_destroy(&w->changed);
    pthread_mutex_destroy(&w->lock);
    bk_free(w);
    return NULL;
  }
  return w;
}

void worker_destroy(app_worker* w) {
  if (!w) return;
  worker_wait(w);
  pthread_mutex_lock(&w->lock);
  w->quit = true;
  pthread_cond_broadcast(&w->changed);
  pthread_mutex_unlock(&w->lock);
  pthread_join(w->thread, NULL);
  pthread_cond_destroy(&w->changed);
  pthread_mutex_destroy(&w->lock);
  bk_free(w);
}

void worker_start(app_worker* w, void (*job)(void*), void* argument) {
  worker_wait(w); // one job at a time
  pthread_mutex_lock(&w->lock);
  w->job = job;
  w->argument = argument;
  w->busy = true;
  pthread_cond_broadcast(&w->changed);
  pthread_mutex_unlock(&w->lock);
}

void worker_wait(app_worker* w) {
  pthread_mutex_lock(&w->lock);
  while (w->busy)
    pthread_cond_wait(&w->changed, &w->lock);
  pthread_mutex_unlock(&w->lock);
}
