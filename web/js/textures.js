// The wall's bricks, drawn on a canvas: two bricks by two courses of the
// library's default brick bond (0.25 x 0.125 m, every other course shifted
// half a brick), mapped by position so that the mortar lines lie where the
// brick pattern cuts (src/lib/fracture/brick_bond.c).
import * as THREE from 'three';

export const BRICK = { length: 0.25, height: 0.125 };
const PX = 512; // pixels a metre

export function brickTexture(color) {
  const w = 2 * BRICK.length * PX, h = 2 * BRICK.height * PX, mortar = 3;
  const canvas = document.createElement('canvas');
  canvas.width = w, canvas.height = h;
  const g = canvas.getContext('2d');
  g.fillStyle = '#b9ad9c';
  g.fillRect(0, 0, w, h);
  const base = new THREE.Color(color);
  const tones = [0.92, 1.04, 0.97, 1.08, 0.9, 1.0];
  const brickW = BRICK.length * PX, brickH = BRICK.height * PX;
  // The canvas's top row is the texture's top: course 1 (shifted) is drawn first.
  for (const [course, top] of [[1, 0], [0, brickH]]) {
    const shift = course % 2 ? brickW / 2 : 0;
    for (let k = -1; k < 2; k++) {
      const tone = tones[(course * 3 + k + 1) % tones.length];
      g.fillStyle = `#${base.clone().multiplyScalar(tone).getHexString()}`;
      g.fillRect(shift + k * brickW + mortar, top + mortar, brickW - 2 * mortar, brickH - 2 * mortar);
    }
  }
  const texture = new THREE.CanvasTexture(canvas);
  texture.wrapS = texture.wrapT = THREE.RepeatWrapping;
  texture.colorSpace = THREE.SRGBColorSpace;
  texture.anisotropy = 4;
  return texture;
}

// Texture coordinates by position, projected along each vertex's main
// normal axis: one texture repeat is two bricks by two courses.
export function brickUvs(positions, normals) {
  const uv = new Float32Array((positions.length / 3) * 2);
  const su = 1 / (2 * BRICK.length), sv = 1 / (2 * BRICK.height);
  for (let i = 0, j = 0; i < positions.length; i += 3, j += 2) {
    const ax = Math.abs(normals[i]), ay = Math.abs(normals[i + 1]), az = Math.abs(normals[i + 2]);
    const x = positions[i], y = positions[i + 1], z = positions[i + 2];
    if (ay >= ax && ay >= az) (uv[j] = x * su), (uv[j + 1] = z * sv);
    else if (ax >= az) (uv[j] = z * su), (uv[j + 1] = y * sv);
    else (uv[j] = x * su), (uv[j + 1] = y * sv);
  }
  return uv;
}
