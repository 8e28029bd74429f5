// Fractures off the main thread, so the scene keeps running: its own
// instance of the library, progress as it goes, the tree's bytes at the end
// (transferred, not copied).
import { loadBreakables } from './breakables.js';
import { fracture } from './fracture_plan.js';

const ready = loadBreakables();

self.onmessage = async ({ data }) => {
  const { id, source, options, aim } = data;
  try {
    const bk = await ready;
    let last = -1;
    const { tree, ms, callMs } = fracture(bk, source, {
      ...options,
      onProgress: (fraction) => {
        // A message a percent is plenty for a progress bar.
        const percent = Math.floor(fraction * 100);
        if (percent !== last) self.postMessage({ id, progress: fraction }), (last = percent);
      },
    }, aim);
    const bytes = tree.bytes();
    const hash = tree.hash;
    tree.free();
    self.postMessage({ id, bytes, hash, ms, callMs }, [bytes.buffer]);
  } catch (e) {
    self.postMessage({ id, error: e?.message ?? String(e) });
  }
};
