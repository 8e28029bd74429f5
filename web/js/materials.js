// One material for a fragment's outside and its cut faces. Software GL pays
// per draw call: a mesh with two materials is drawn twice, and the wall
// after three shots took 66 draw calls and ran at half the frame rate of
// the same meshes drawn once each (34 calls). So the cut faces are marked
// per vertex (the tree's `inside` flags) and take their own colour in the
// shader, in the same draw as the outside.
import * as THREE from 'three';

export function fragmentMaterial({ color, inside, map = null, glass = false }) {
  const material = new THREE.MeshLambertMaterial({
    color: map ? 0xffffff : color,
    map,
    ...(glass ? { transparent: true, opacity: 0.5, depthWrite: false } : {}),
  });
  const insideColor = new THREE.Color(inside); // converted to the working (linear) colour space
  material.onBeforeCompile = (shader) => {
    shader.uniforms.insideColor = { value: insideColor };
    shader.vertexShader = shader.vertexShader
      .replace('#include <common>', '#include <common>\nattribute float inside;\nvarying float vInside;')
      .replace('#include <begin_vertex>', '#include <begin_vertex>\nvInside = inside;');
    shader.fragmentShader = shader.fragmentShader
      .replace('#include <common>', '#include <common>\nuniform vec3 insideColor;\nvarying float vInside;')
      .replace('#include <map_fragment>', '#include <map_fragment>\ndiffuseColor.rgb = mix(diffuseColor.rgb, insideColor, vInside);');
  };
  material.customProgramCacheKey = () => 'breakables-fragment';
  return material;
}

// Per vertex: 1 where it belongs to a cut face (the tree marks triangles).
export function insideAttribute(indices, insideTriangles, vertexCount) {
  const flags = new Float32Array(vertexCount);
  for (let t = 0; t < insideTriangles.length; t++)
    if (insideTriangles[t]) flags[indices[3 * t]] = flags[indices[3 * t + 1]] = flags[indices[3 * t + 2]] = 1;
  return new THREE.BufferAttribute(flags, 1);
}
