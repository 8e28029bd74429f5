// The game's worker thread.
#pragma once

/// A thread that runs one job at a time (the game's physics steps, while the
/// driver draws the frame). Touch nothing the job uses until worker_wait.
typedef struct app_worker app_worker;
/// NULL if no thread can be started (the caller then runs jobs itself).
app_worker* worker_create(void);
/// Waits for the job in progress, then ends the thread.
void worker_destroy(app_worker* worker);
/// Runs job(argument) on the worker, after waiting for the previous job.
void worker_start(app_worker* worker, void (*job)(void*), void* argument);
/// Returns once no job is running.
void worker_wait(app_worker* worker);
