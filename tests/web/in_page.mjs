// Measurements made inside the page through its own copy of the WebAssembly
// module (js/breakables.js, as the page loads it): tree hashes of fractures,
// the bunny's fracture time, the split of the 1,024-fragment wall (what
// split_native.c does natively), and the rate of animation frames.

/// The tree hash of each fracture, built by the module in the page. `jobs`:
/// [{source: {shape} | {bunny: true}, options: {pieces, pattern, seed}}].
export function moduleTreeHashes(page, jobs) {
  return page.evaluate(async (jobs) => {
    const { loadBreakables } = await import('/js/breakables.js');
    const bk = await loadBreakables();
    const bunny = new Uint8Array(await (await fetch('/assets/bunny.obj')).arrayBuffer());
    return jobs.map(({ source, options }) => {
      const src = source.bunny ? { obj: bunny, name: 'bunny.obj', bunny: true } : source;
      const tree = bk.fracture(src, options);
      const out = { hash: tree.hash, leaves: tree.leafCount };
      tree.free();
      return out;
    });
  }, jobs);
}

/// The module's fracture of the built-in bunny: the median wall-clock time of `runs` runs (ms) and its hash.
export function moduleBunnyFracture(page, options, runs) {
  return page.evaluate(
    async (options, runs) => {
      const { loadBreakables } = await import('/js/breakables.js');
      const bk = await loadBreakables();
      const bytes = new Uint8Array(await (await fetch('/assets/bunny.obj')).arrayBuffer());
      const times = [];
      let hash = null;
      for (let i = 0; i < runs; ++i) {
        const t0 = performance.now();
        const tree = bk.fracture({ obj: bytes, name: 'bunny.obj', bunny: true }, options);
        times.push(performance.now() - t0);
        hash = tree.hash;
        tree.free();
      }
      times.sort((a, b) => a - b);
      return { ms: times[Math.floor(runs / 2)], hash };
    },
    options,
    runs,
  );
}

/// The wall split, as split_native.c measures it natively: the same tree, hit,
/// and loop; the mean over `runs` fresh runtimes.
export function moduleSplit(page, pieces, seed, runs) {
  return page.evaluate(
    async (pieces, seed, runs) => {
      const { loadBreakables } = await import('/js/breakables.js');
      const bk = await loadBreakables();
      const t0 = performance.now();
      const tree = bk.fracture({ shape: 'wall' }, { pieces, pattern: 'brick', seed });
      const fractureMs = performance.now() - t0;
      const box = tree.bounds();
      const middle = [0.5 * (box.min[0] + box.max[0]), 0.5 * (box.min[1] + box.max[1]), box.max[2]];
      let damage = 0;
      let split = 0;
      let calls = 0;
      let created = 0;
      let broken = 0;
      for (let r = 0; r < runs; ++r) {
        const rt = bk.createRuntime({ gravity: [0, -9.81, 0] });
        const bodies = new Map();
        rt.setBodyState((key) => bodies.get(key));
        const take = () => {
          for (const c of rt.events().created) bodies.set(c.cluster, c.body);
          rt.clearEvents();
        };
        rt.addBreakable(tree, { material: 'stone', anchored: true });
        take();
        const a = performance.now();
        rt.damageAt(middle, 320);
        const hit = performance.now();
        broken = rt.events().broken.length; // read outside the split's time, as split_native.c does
        const b = performance.now();
        calls = 0;
        created = 0;
        for (;;) {
          const made = rt.split();
          ++calls;
          created += made;
          if (made === 0 && !(rt.stats().pendingSplits > 0)) break;
        }
        const c = performance.now();
        take();
        damage += hit - a;
        split += c - b;
        rt.destroy();
      }
      const out = {
        fragments: tree.leafCount,
        bonds: tree.bondCount,
        tree_hash: tree.hash,
        fracture_ms: fractureMs,
        damage_ms: damage / runs,
        split_ms: split / runs,
        split_calls: calls,
        clusters_created: created,
        bonds_broken: broken,
        runs,
      };
      tree.free();
      return out;
    },
    pieces,
    seed,
    runs,
  );
}

/// Animation frames a second, counted over `ms` milliseconds.
export function frameRate(page, ms) {
  return page.evaluate(
    (ms) =>
      new Promise((resolve) => {
        let frames = 0;
        let first = 0;
        const tick = (t) => {
          if (!first) first = t;
          else ++frames;
          if (t - first >= ms) resolve((frames * 1000) / (t - first));
          else requestAnimationFrame(tick);
        };
        requestAnimationFrame(tick);
      }),
    ms,
  );
}

/// Stops the page's animation loop (it asks for each next frame with
/// requestAnimationFrame, which from now on schedules nothing) and waits for
/// the frame under way to end.
export function stopAnimation(page) {
  return page.evaluate(
    () =>
      new Promise((resolve) => {
        const request = window.requestAnimationFrame.bind(window);
        request(() => {
          window.requestAnimationFrame = () => 0;
          setTimeout(resolve, 100);
        });
      }),
  );
}
