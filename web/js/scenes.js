// The scenes of the native game the page shows (src/scenes/scenes.c): what
// stands where, made of what, how it is fractured, and where shots aim.
// Colours stand in for the game's textures.

export const SCENES = {
  wall: {
    description: 'a brick wall anchored to the ground',
    // One piece per brick of the wall's 0.25 x 0.125 m bricks: the brick
    // pattern cuts along the mortar, so a hole opens brick by brick.
    object: { mesh: 'wall', material: 'stone', anchored: true, pattern: 'brick', pieces: 85, aspectBias: 1.5 },
    eye: [1.3, 1.2, 3.1],
    target: [0.0, 0.6, 0.0],
    camera: [0.5, 1.0, 2.3],
    // 40 kg stone balls: three of them knock a hole of several bricks through it.
    projectile: { speed: 40.0, radius: 0.14, mass: 40.0 },
    look: { color: 0x9c4a32, inside: 0xb9a48c, roughness: 0.9, brick: true },
  },
  eggshell: {
    description: 'a porcelain eggshell resting on the ground',
    object: { mesh: 'eggshell', material: 'porcelain', anchored: false, pattern: 'voronoi', pieces: 128 },
    eye: [0.0, 0.5, 1.8],
    target: [0.0, 0.3, 0.0],
    camera: [0.45, 0.6, 1.1],
    projectile: { speed: 15.0, radius: 0.04, mass: 0.3 },
    look: { color: 0xf4f1ea, inside: 0xe2dccf, roughness: 0.25 },
  },
  bunny: {
    description: 'a glass Stanford bunny',
    // Radial: finest round where the shots land (the impact point is where
    // the line from the eye to the target meets the bunny's surface).
    object: { mesh: 'bunny', material: 'glass', anchored: false, pattern: 'radial', pieces: 128 },
    eye: [0.0, 0.6, 2.2],
    target: [0.0, 0.45, 0.0],
    camera: null,
    projectile: { speed: 25.0, radius: 0.06, mass: 1.0 },
    look: { color: 0x8fdcb4, inside: 0xc8f0dc, roughness: 0.05, glass: true },
  },
};

// A user's model, or a built-in mesh in place of the scene's object: the
// scene's camera and shots, the object's material, the library's default
// fracture (as `breakables fracture --mesh NAME` makes it).
export function objectFor(scene, mesh) {
  const own = SCENES[scene].object;
  if (!mesh) return { ...own };
  // Stood on the ground where the scene's object stands (placed once its tree is known).
  return { mesh, material: own.material, anchored: own.anchored, pattern: null, pieces: null, aspectBias: null, standOnGround: true };
}

// Shot k of a volley (as scene_shot in src/scenes/scene_setup.c): later
// shots land round the target on a golden-angle spiral, 0.12 m apart, so a
// volley spreads its damage.
export function sceneShot(scene, k) {
  const { eye, target } = scene;
  const forward = normalize(sub(target, eye));
  const [right, up] = planeBasis(forward);
  const radius = 0.12 * Math.sqrt(k), angle = 2.39996322972865332 * k;
  const aim = add(target, add(scale(right, radius * Math.cos(angle)), scale(up, radius * Math.sin(angle))));
  return { origin: [...eye], direction: normalize(sub(aim, eye)) };
}

const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const add = (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
const scale = (a, s) => [a[0] * s, a[1] * s, a[2] * s];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
function normalize(a) {
  const l = Math.hypot(a[0], a[1], a[2]);
  return l > 0 ? scale(a, 1 / l) : [0, 0, 0];
}
// bk_plane_basis (include/breakables/types.h): two unit vectors perpendicular
// to n and to each other, from the axis least aligned with n.
function planeBasis(n) {
  const other = Math.abs(n[0]) < 0.57735 ? [1, 0, 0] : Math.abs(n[1]) < 0.57735 ? [0, 1, 0] : [0, 0, 1];
  const right = normalize(cross(other, n));
  return [right, cross(n, right)];
}
