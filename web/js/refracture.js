// The main thread's side of the fracture worker: one job at a time, a
// promise for its tree bytes, progress reported as it comes.
let worker = null, nextId = 1;
const jobs = new Map();

function start() {
  worker = new Worker(new URL('./fracture_worker.js', import.meta.url), { type: 'module' });
  worker.onmessage = ({ data }) => {
    const job = jobs.get(data.id);
    if (!job) return;
    if (data.progress !== undefined) return job.onProgress(data.progress);
    jobs.delete(data.id);
    if (data.error) job.reject(new Error(data.error));
    else job.resolve({ bytes: data.bytes, hash: data.hash, ms: data.ms, callMs: data.callMs });
  };
  worker.onerror = (e) => {
    e.preventDefault();
    const error = new Error(`fracture worker: ${e.message || 'failed to start'}`);
    for (const job of jobs.values()) job.reject(error);
    jobs.clear();
    worker.terminate();
    worker = null;
  };
}

// source, options: as bk.fracture takes them, aim: as fracture_plan.js's (copied to the worker: the caller keeps its bytes).
export function fractureInWorker(source, options, aim, onProgress = () => {}) {
  if (!worker) start();
  const id = nextId++;
  return new Promise((resolve, reject) => {
    jobs.set(id, { resolve, reject, onProgress });
    worker.postMessage({ id, source, options, aim });
  });
}
