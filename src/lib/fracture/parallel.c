// Static parallel jobs for the fracture's passes whose work is split up
// front (each job's result is written where its inputs say, so the result
// does not depend on which thread ran it).
#include <pthread.h>
#include <stdlib.h>

#include "bk_fracture.h"

void bk_fracture_run_jobs(void* (*work)(void*), void* jobs, size_t job_size, uint32_t count) {
  if (count == 0) return;
  pthread_t* ids = bk_calloc(count, sizeof(pthread_t));
  bool* started = bk_calloc(count, sizeof(bool));
  for (uint32_t j = 1; j < count; ++j)
    started[j] = pthread_create(&ids[j], NULL, work, (char*)jobs + j * job_size) == 0;
  work(jobs);
  for (uint32_t j = 1; j < count; ++j)
    if (started[j])
      pthread_join(ids[j], NULL);
    else
      work((char*)jobs + j * job_size); // no thread: done here
  bk_free(ids);
  bk_free(started);
}
