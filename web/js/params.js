// URL parameters for scripted runs (?scene=wall&autofire=3&frames=600):
// read once, checked here, so that a bad value is reported in one line
// instead of surfacing later as a strange scene.

const SCENES = ['wall', 'eggshell', 'bunny'];

function integer(search, name, min, max) {
  const text = search.get(name);
  if (text === null || text === '') return null;
  const value = Number(text);
  if (!Number.isInteger(value) || value < min || value > max)
    throw new Error(`URL parameter ${name}=${text}: expected a whole number from ${min} to ${max}`);
  return value;
}

// `bk` gives the lists of shapes and patterns the library knows.
export function readParams(search, bk) {
  const params = {
    scene: search.get('scene') || 'wall',
    mesh: search.get('mesh') || null,
    pieces: integer(search, 'pieces', 1, 4096),
    pattern: search.get('pattern') || null,
    seed: integer(search, 'seed', 0, 0xffffffff),
    autofire: integer(search, 'autofire', 0, 1000) ?? 0,
    frames: integer(search, 'frames', 1, 1e9),
  };
  if (!SCENES.includes(params.scene))
    throw new Error(`URL parameter scene=${params.scene}: expected one of ${SCENES.join(', ')}`);
  const meshes = ['bunny', ...bk.shapes];
  if (params.mesh !== null && !meshes.includes(params.mesh))
    throw new Error(`URL parameter mesh=${params.mesh}: expected one of ${meshes.join(', ')}`);
  if (params.pattern !== null && !bk.patterns.includes(params.pattern))
    throw new Error(`URL parameter pattern=${params.pattern}: expected one of ${bk.patterns.join(', ')}`);
  return params;
}

export { SCENES };
