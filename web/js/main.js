// Boots the page: the library and Rapier, the first scene, the panel, and
// the frame loop (fixed 60 Hz physics steps; scripted runs step once a frame).
import { loadBreakables } from './breakables.js';
import { loadRapier, FIXED_DT } from './physics.js';
import { readParams } from './params.js';
import { View } from './render.js';
import { App } from './app.js';
import { Status, round } from './status.js';
import { wirePanel, showProgress } from './panel.js';

// Shots of ?autofire=N: the first after half a second, then one a second.
const AUTOFIRE_FIRST = 30, AUTOFIRE_EVERY = 60;
const MAX_STEPS_PER_FRAME = 3; // a slow frame falls behind rather than spiral
const STATS_EVERY = 5; // frames between writes of #stats

const status = new Status(document.getElementById('stats'), document.getElementById('banner'));
window.addEventListener('error', (e) => {
  e.preventDefault();
  status.error(e.error ?? e.message);
});
window.addEventListener('unhandledrejection', (e) => {
  e.preventDefault();
  status.error(e.reason);
});

async function boot() {
  const [bk] = await Promise.all([loadBreakables(), loadRapier()]);
  const params = readParams(new URLSearchParams(location.search), bk);
  const view = new View(document.getElementById('view'));
  let updatePanel = () => {};
  const app = new App(bk, view, params, {
    progress: showProgress,
    built: () => {
      frames = 0;
      updatePanel();
      // Everything about the new scene at once: a reader that waits for
      // ready (or a new tree_hash) reads this scene's numbers, not the last's.
      status.set({ ...sceneStats(), ready: true, done: false, scene: app.sceneName, tree_hash: app.treeHash });
      status.write();
    },
  });
  let frames = 0; // steps of the current world
  const sceneStats = () => ({
    ...roundAll(app.world.stats()),
    frames,
    shots: app.world.shots,
    fracture_ms: round(app.fractureMs),
    fracture_call_ms: round(app.fractureCallMs),
  });
  await app.start();
  updatePanel = wirePanel(app, view, status, bk);
  updatePanel();

  window.breakablesPage = {
    // Rejects with the one-line message the banner shows.
    dropFile: (name, bytes) =>
      app.dropFile(name, bytes).then(() => status.clearError(), (e) => {
        status.error(e);
        throw e;
      }),
    fire: (origin, direction) => app.fire(origin, direction),
  };

  // Scripted runs (autofire or frames) step once a frame: the same steps
  // and shots every time, whatever the frame rate. Otherwise real time.
  const scripted = params.autofire > 0 || params.frames !== null;
  let last = performance.now(), owed = 0, writes = 0;
  function frame(now) {
    requestAnimationFrame(frame);
    status.tick(now);
    const world = app.world;
    let steps = 1;
    if (!scripted) {
      owed = Math.min(owed + (now - last) / 1000, MAX_STEPS_PER_FRAME * FIXED_DT);
      steps = Math.floor(owed / FIXED_DT);
      owed -= steps * FIXED_DT;
    }
    last = now;
    const stepping = params.frames === null || frames < params.frames;
    try {
      for (let i = 0; stepping && i < steps; i++) {
        const k = (frames - AUTOFIRE_FIRST) / AUTOFIRE_EVERY;
        if (Number.isInteger(k) && k >= 0 && k < params.autofire) app.fireScripted(k);
        world.step();
        frames++;
      }
      view.sync(world.physics);
      view.render();
      status.set({ ...sceneStats(), draw_calls: view.renderer.info.render.calls });
      if (params.frames !== null && frames >= params.frames && !status.values.done) {
        status.set({ done: true });
        writes = 0;
      }
    } catch (e) {
      status.error(e);
    }
    // Every few frames: rewriting the element every frame costs a layout.
    if (writes++ % STATS_EVERY === 0) status.write();
  }
  requestAnimationFrame(frame);
}

function roundAll(values) {
  const out = {};
  for (const [k, v] of Object.entries(values)) out[k] = typeof v === 'number' ? round(v, 3) : v;
  return out;
}

boot().catch((e) => status.error(e));
