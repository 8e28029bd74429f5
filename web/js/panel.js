// The panel: scene, material sliders (live), pieces and pattern (re-fracture
// in the worker), the progress bar, download; and the canvas's inputs:
// click to fire, drop a model.
const $ = (id) => document.getElementById(id);

export function wirePanel(app, view, status, bk) {
  const scene = $('scene'), frailty = $('frailty'), density = $('density');
  const pieces = $('pieces'), pattern = $('pattern');
  for (const name of bk.patterns) pattern.add(new Option(name, name));
  const run = (promise) => promise.then(() => status.clearError(), (e) => status.error(e));

  // Live: the runtime's values for the scene's object, at once.
  frailty.addEventListener('input', () => {
    app.world.rt.setFrailty(app.world.breakable, Number(frailty.value));
    $('frailty-value').textContent = Number(frailty.value).toFixed(1);
  });
  density.addEventListener('input', () => {
    app.world.rt.setDensity(app.world.breakable, Number(density.value));
    $('density-value').textContent = `${density.value} kg/m³`;
  });
  scene.addEventListener('change', () => run(app.switchScene(scene.value)));
  $('refracture').addEventListener('click', () => {
    const n = pieces.value === '' ? null : Number(pieces.value);
    if (n !== null && !(Number.isInteger(n) && n >= 2 && n <= 4096))
      return status.error(`pieces: expected a whole number from 2 to 4096 (got ${pieces.value})`);
    run(app.refractureCurrent(n, pattern.value || null));
  });
  $('download').addEventListener('click', () => {
    try {
      app.download();
    } catch (e) {
      status.error(e);
    }
  });

  // A click (not a drag of the orbit controls) fires along the mouse ray.
  const canvas = view.renderer.domElement;
  let down = null;
  canvas.addEventListener('pointerdown', (e) => (down = e.button === 0 ? [e.clientX, e.clientY] : null));
  canvas.addEventListener('pointerup', (e) => {
    if (!down || Math.hypot(e.clientX - down[0], e.clientY - down[1]) > 4) return;
    const { origin, direction } = view.ray(e.clientX, e.clientY);
    try {
      app.fire(origin, direction);
    } catch (err) {
      status.error(err);
    }
  });

  // Drop a model anywhere on the page.
  document.addEventListener('dragover', (e) => e.preventDefault());
  document.addEventListener('drop', (e) => {
    e.preventDefault();
    const file = e.dataTransfer?.files?.[0];
    if (!file) return;
    run(file.arrayBuffer().then((b) => app.dropFile(file.name, new Uint8Array(b))));
  });

  // The panel follows the scene built.
  return function update() {
    const rt = app.world.rt, b = app.world.breakable;
    scene.value = app.sceneName;
    frailty.value = rt.frailty(b);
    density.value = rt.density(b);
    $('frailty-value').textContent = rt.frailty(b).toFixed(1);
    $('density-value').textContent = `${Math.round(rt.density(b))} kg/m³`;
    pieces.placeholder = String(app.world.tree.leafCount);
  };
}

export function showProgress(fraction) {
  const bar = $('progress');
  bar.hidden = fraction === null;
  if (fraction !== null) {
    bar.querySelector('progress').value = fraction;
    bar.querySelector('span').textContent = `fracturing… ${Math.round(fraction * 100)}%`;
  }
}
