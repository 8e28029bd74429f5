// What the page draws: a three.js scene with the ground, one Group per
// cluster body (one Mesh per node of its node set, the node's geometry made
// once per tree and shared), and the projectiles in flight.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { inverse, mul } from './transform.js';
import { brickTexture, brickUvs } from './textures.js';
import { fragmentMaterial, insideAttribute } from './materials.js';

// A mesh handed over without normals (positions and indices from a glTF)
// has zero normals where the source had none: those vertices take the
// average of their triangles' instead.
function fillNormals(g) {
  const given = g.attributes.normal.array;
  let missing = false;
  for (let i = 0; i < given.length && !missing; i += 3) missing = given[i] === 0 && given[i + 1] === 0 && given[i + 2] === 0;
  if (!missing) return;
  const kept = given.slice();
  g.computeVertexNormals();
  const n = g.attributes.normal.array;
  for (let i = 0; i < n.length; i += 3)
    if (kept[i] !== 0 || kept[i + 1] !== 0 || kept[i + 2] !== 0) n.set(kept.subarray(i, i + 3), i);
}

export class View {
  constructor(container) {
    this.renderer = new THREE.WebGLRenderer({ antialias: false });
    this.renderer.setPixelRatio(Math.min(window.devicePixelRatio, 2));
    this.renderer.setSize(container.clientWidth, container.clientHeight);
    container.appendChild(this.renderer.domElement);
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(0xbfd4e6);
    this.camera = new THREE.PerspectiveCamera(50, container.clientWidth / container.clientHeight, 0.02, 500);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.enableDamping = false;
    this.scene.add(new THREE.HemisphereLight(0xeef4ff, 0x6b5a48, 1.4));
    const sun = new THREE.DirectionalLight(0xfff2dd, 2.2);
    sun.position.set(3, 6, 4);
    this.scene.add(sun);
    // Unlit: the ground fills half the picture, and lighting it cost software
    // GL a sixth of the frame rate (30 -> 35 fps, the wall after three shots).
    // No fog for the same reason; the plane reaches the horizon instead.
    const ground = new THREE.Mesh(new THREE.PlaneGeometry(400, 400),
      new THREE.MeshBasicMaterial({ color: 0x7d8c6c }));
    ground.rotation.x = -Math.PI / 2;
    this.scene.add(ground);
    const grid = new THREE.GridHelper(20, 40, 0x5d6b50, 0x74836a);
    grid.position.y = 0.001;
    this.scene.add(grid);
    this.objects = new THREE.Group(); // the clusters' groups
    this.scene.add(this.objects);
    this.groups = new Map(); // cluster key -> {group, fromPrincipal}
    this.geometries = new Map(); // tree -> Map(node -> BufferGeometry)
    this.projectileMeshes = new Map(); // projectile -> Mesh
    this.projectileMaterial = new THREE.MeshLambertMaterial({ color: 0x4a4f57 });
    this.sphere = new THREE.SphereGeometry(1, 16, 12);
    this.material = null;
    this.resize(container);
    window.addEventListener('resize', () => this.resize(container));
  }

  resize(container) {
    const w = container.clientWidth, h = container.clientHeight;
    this.renderer.setSize(w, h);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
  }

  // The scene's look and camera: the outside faces take the object's
  // colour (or the wall's bricks), the cut faces (a fracture's caps) another.
  setLook(look, eye, target) {
    this.clear();
    this.look = look;
    this.material = fragmentMaterial({
      color: look.color, inside: look.inside, glass: look.glass, map: look.brick ? brickTexture(look.color) : null,
    });
    this.camera.position.set(...eye);
    this.controls.target.set(...target);
    this.controls.update();
  }

  // A node's geometry: made from the tree's mesh once and shared by every
  // body the node is part of.
  geometry(tree, node) {
    let perTree = this.geometries.get(tree);
    if (!perTree) this.geometries.set(tree, (perTree = new Map()));
    let g = perTree.get(node);
    if (g) return g;
    const m = tree.nodeMesh(node); // views into wasm memory: copied right away
    const vertices = m.positions.length / 3;
    g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(new Float32Array(m.positions), 3));
    g.setAttribute('normal', new THREE.BufferAttribute(new Float32Array(m.normals), 3));
    g.setAttribute('inside', insideAttribute(m.indices, m.inside, vertices));
    g.setIndex(new THREE.BufferAttribute(new Uint32Array(m.indices), 1));
    if (this.look.brick) g.setAttribute('uv', new THREE.BufferAttribute(brickUvs(m.positions, m.normals), 2));
    fillNormals(g);
    g.computeBoundingSphere();
    perTree.set(node, g);
    return g;
  }

  addCluster(info, tree) {
    const group = new THREE.Group();
    group.matrixAutoUpdate = false;
    for (const node of info.nodes) group.add(new THREE.Mesh(this.geometry(tree, node), this.material));
    this.objects.add(group);
    this.groups.set(info.key, { group, fromPrincipal: inverse(info.principal), info });
  }

  removeCluster(info) {
    const entry = this.groups.get(info.key);
    if (!entry) return;
    this.objects.remove(entry.group);
    this.groups.delete(info.key);
  }

  // Each group placed by its body's transform after the inverse of the
  // cluster's principal frame (the tree frame in the world).
  sync(physics) {
    const position = new THREE.Vector3(), rotation = new THREE.Quaternion(), one = new THREE.Vector3(1, 1, 1);
    for (const { group, fromPrincipal, info } of this.groups.values()) {
      if (info.isStatic && group.userData.placed) continue;
      const p = info.body.translation(), q = info.body.rotation();
      const t = mul({ p: [p.x, p.y, p.z], q: [q.x, q.y, q.z, q.w] }, fromPrincipal);
      group.matrix.compose(position.set(...t.p), rotation.set(...t.q), one);
      group.matrixWorldNeedsUpdate = true;
      group.userData.placed = true;
    }
    for (const [projectile, mesh] of this.projectileMeshes)
      if (projectile.removed) {
        this.scene.remove(mesh);
        this.projectileMeshes.delete(projectile);
      }
    for (const projectile of physics.projectiles) {
      let mesh = this.projectileMeshes.get(projectile);
      if (!mesh) {
        mesh = new THREE.Mesh(this.sphere, this.projectileMaterial);
        mesh.scale.setScalar(projectile.radius);
        this.scene.add(mesh);
        this.projectileMeshes.set(projectile, mesh);
      }
      const p = projectile.body.translation();
      mesh.position.set(p.x, p.y, p.z);
    }
  }

  render() {
    this.renderer.render(this.scene, this.camera);
  }

  // The ray under a point of the canvas, for a shot.
  ray(clientX, clientY) {
    const rect = this.renderer.domElement.getBoundingClientRect();
    const ndc = new THREE.Vector2(((clientX - rect.left) / rect.width) * 2 - 1, -((clientY - rect.top) / rect.height) * 2 + 1);
    const raycaster = new THREE.Raycaster();
    raycaster.setFromCamera(ndc, this.camera);
    const { origin, direction } = raycaster.ray;
    return { origin: origin.toArray(), direction: direction.toArray() };
  }

  // Drops every body's drawing and the trees' geometries (a new scene).
  clear() {
    for (const { group } of this.groups.values()) this.objects.remove(group);
    this.groups.clear();
    for (const perTree of this.geometries.values()) for (const g of perTree.values()) g.dispose();
    this.geometries.clear();
    for (const mesh of this.projectileMeshes.values()) this.scene.remove(mesh);
    this.projectileMeshes.clear();
    this.material?.map?.dispose();
    this.material?.dispose();
  }
}
