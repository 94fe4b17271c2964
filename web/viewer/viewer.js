// The page of `mbgen view` (generator/view/view_page.cpp inlines this file, three.js and the scene).
// Everything it draws comes from the scene JSON mbgen wrote: the body poses of every frame
// (computed by mbgen's kinematics, not here), the SSV compounds and meshes in their bodies'
// frames, the near pairs with their witness points, the closures and the contact forces. The page
// only places, colours and animates them. Its status (data-status on <body>: "ready" after the
// first frame is drawn, "error" otherwise) and #mbgen-errors are what the tests read.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

const scene = JSON.parse(document.getElementById('mbgen-scene').textContent);
const frames = scene.frames;
const numFrames = frames.t.length;
const bodies = scene.bodies.length;

const colours = {
  ssv: new THREE.Color(0x7f9cc4),   // a body in no near pair
  touching: new THREE.Color(0xd7191c),  // distance <= 0
  threshold: new THREE.Color(0xfdae61), // distance at the near threshold
  mesh: new THREE.Color(0xb9b9b9),
  closure: new THREE.Color(0xc51b7d),
  force: new THREE.Color(0x1a9641),
  witness: new THREE.Color(0xd7191c),
};

function decodeBase64(text, Type) {
  const bytes = Uint8Array.from(atob(text), (c) => c.charCodeAt(0));  // little-endian, as mbgen writes
  return new Type(bytes.buffer);
}

function vec(p) { return new THREE.Vector3(p[0], p[1], p[2]); }

// --- the world ------------------------------------------------------------------------------
const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(window.devicePixelRatio);
renderer.setSize(window.innerWidth, window.innerHeight);
renderer.setClearColor(0xffffff);
document.body.appendChild(renderer.domElement);
const world = new THREE.Scene();
world.add(new THREE.HemisphereLight(0xffffff, 0x667788, 2.2));
const sun = new THREE.DirectionalLight(0xffffff, 1.6);
sun.position.set(2, -3, 5);
world.add(sun);
const camera = new THREE.PerspectiveCamera(40, window.innerWidth / window.innerHeight, 0.01, 200);
camera.up.set(0, 0, 1);  // z up, as mbgen's world
// The ground: the scene's plane when it has contact (z = 0), else a grid under the robot's feet.
const grid = new THREE.GridHelper(10, 40, 0x999999, 0xdddddd);
grid.rotation.x = Math.PI / 2;  // the grid's plane is x-y
world.add(grid);

// --- the bodies: one group each, posed from the frame's X_WB --------------------------------
const groups = [];
const ssvMaterials = [];
const ssvGroups = [];
for (let b = 0; b < bodies; ++b) {
  const g = new THREE.Group();
  g.matrixAutoUpdate = false;
  g.name = scene.bodies[b];
  world.add(g);
  groups.push(g);
  const material = new THREE.MeshStandardMaterial({ color: colours.ssv.clone(), transparent: true, opacity: 0.6,
                                                    roughness: 0.6, depthWrite: false });
  ssvMaterials.push(material);
  const s = new THREE.Group();
  g.add(s);
  ssvGroups.push(s);
  const axes = new THREE.AxesHelper(0.08);
  axes.visible = false;
  axes.userData.isFrame = true;
  g.add(axes);
}
function bodyGroup(b) { return b >= 0 ? groups[b] : world; }

function sphere(parent, centre, radius, material) {
  const m = new THREE.Mesh(new THREE.SphereGeometry(radius, 24, 16), material);
  m.position.copy(centre);
  parent.add(m);
}

function capsule(parent, a, b, radius, material) {
  const axis = new THREE.Vector3().subVectors(b, a);
  const length = axis.length();
  if (length < 1e-9) return sphere(parent, a, radius, material);
  const m = new THREE.Mesh(new THREE.CapsuleGeometry(radius, length, 8, 20), material);
  m.position.addVectors(a, b).multiplyScalar(0.5);
  m.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), axis.normalize());
  parent.add(m);
}

// A triangle SSV: its edges' capsules and the triangle moved by +-radius along its normal.
function roundedTriangle(parent, p, radius, material) {
  for (let k = 0; k < 3; ++k) capsule(parent, p[k], p[(k + 1) % 3], radius, material);
  const n = new THREE.Vector3().crossVectors(new THREE.Vector3().subVectors(p[1], p[0]), new THREE.Vector3().subVectors(p[2], p[0]));
  if (n.lengthSq() < 1e-18) return;
  n.normalize().multiplyScalar(radius);
  const positions = [];
  for (const side of [1, -1])
    for (const q of p) positions.push(q.x + side * n.x, q.y + side * n.y, q.z + side * n.z);
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.Float32BufferAttribute(positions, 3));
  geometry.setIndex([0, 1, 2, 5, 4, 3]);
  geometry.computeVertexNormals();
  const face = material.clone();
  face.side = THREE.DoubleSide;
  material.userData.faces = (material.userData.faces || []).concat([face]);
  parent.add(new THREE.Mesh(geometry, face));
}

for (const s of scene.ssv) {
  const parent = ssvGroups[s.body];
  const material = ssvMaterials[s.body];
  const p = s.points.map(vec);
  if (s.kind === 'point') sphere(parent, p[0], s.radius, material);
  else if (s.kind === 'line') capsule(parent, p[0], p[1], s.radius, material);
  else roundedTriangle(parent, p, s.radius, material);
}

const meshMaterial = new THREE.MeshStandardMaterial({ color: colours.mesh, roughness: 0.8, metalness: 0.1 });
const meshObjects = [];
for (const m of scene.meshes) {
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(decodeBase64(m.positions, Float32Array), 3));
  geometry.setIndex(new THREE.BufferAttribute(decodeBase64(m.indices, Uint32Array), 1));
  geometry.computeVertexNormals();
  const object = new THREE.Mesh(geometry, meshMaterial);
  groups[m.body].add(object);
  meshObjects.push(object);
}

// Each closure's two frames: they coincide (up to the closure's free motion) when the loop is closed.
const closureMaterial = new THREE.MeshStandardMaterial({ color: colours.closure });
const closureObjects = [];
for (const c of scene.closures) {
  for (const [b, p] of [[c.body_a, c.point_a], [c.body_b, c.point_b]]) {
    const m = new THREE.Mesh(new THREE.SphereGeometry(0.012, 16, 12), closureMaterial);
    m.position.copy(vec(p));
    bodyGroup(b).add(m);
    closureObjects.push(m);
  }
}

// Witness segments of the near pairs, world coordinates, rewritten each frame.
const witnessPositions = new Float32Array(Math.max(1, scene.pairs.length) * 6);
const witnessGeometry = new THREE.BufferGeometry();
witnessGeometry.setAttribute('position', new THREE.BufferAttribute(witnessPositions, 3));
const witnesses = new THREE.LineSegments(witnessGeometry, new THREE.LineBasicMaterial({ color: colours.witness }));
witnesses.frustumCulled = false;
world.add(witnesses);

// Contact forces: one arrow per contact sphere, from its lowest point; the largest force of the
// trajectory is a quarter of a metre long.
let largestForce = 0;
for (const row of frames.forces || []) for (const f of row) largestForce = Math.max(largestForce, f);
const metresPerNewton = largestForce > 0 ? 0.25 / largestForce : 0;
const arrows = scene.contacts.map(() => {
  const a = new THREE.ArrowHelper(new THREE.Vector3(0, 0, 1), new THREE.Vector3(), 0.1, colours.force, 0.03, 0.02);
  a.visible = false;
  world.add(a);
  return a;
});

// --- one frame ------------------------------------------------------------------------------
const info = document.getElementById('info');
const pose = new THREE.Matrix4();
const contactWorld = new THREE.Vector3();
let current = -1;

function showFrame(k) {
  current = k;
  const X = frames.X_WB[k];
  for (let b = 0; b < bodies; ++b) {
    const o = 12 * b;  // [R | p] row-major
    pose.set(X[o], X[o + 1], X[o + 2], X[o + 3], X[o + 4], X[o + 5], X[o + 6], X[o + 7], X[o + 8], X[o + 9], X[o + 10], X[o + 11],
             0, 0, 0, 1);
    groups[b].matrix.copy(pose);
    groups[b].matrixWorldNeedsUpdate = true;
  }
  // Near pairs: each body coloured by its closest near pair, red at contact to orange at the threshold.
  const closest = new Array(bodies).fill(Infinity);
  let lines = 0, best = null;
  for (const [pair, d, ...w] of frames.near[k]) {
    const [a, b] = scene.pairs[pair];
    closest[a] = Math.min(closest[a], d);
    closest[b] = Math.min(closest[b], d);
    witnessPositions.set(w, 6 * lines++);
    if (!best || d < best.d) best = { a, b, d };
  }
  witnessGeometry.setDrawRange(0, 2 * lines);
  witnessGeometry.attributes.position.needsUpdate = true;
  for (let b = 0; b < bodies; ++b) {
    const m = ssvMaterials[b];
    if (closest[b] === Infinity) m.color.copy(colours.ssv);
    else m.color.lerpColors(colours.touching, colours.threshold, Math.min(1, Math.max(0, closest[b] / scene.near_threshold)));
    for (const f of m.userData.faces || []) f.color.copy(m.color);
  }
  const forces = frames.forces ? frames.forces[k] : null;
  scene.contacts.forEach((c, i) => {
    const f = forces ? forces[i] : 0;
    arrows[i].visible = f > 0 && document.getElementById('show-forces').checked;
    if (!arrows[i].visible) return;
    contactWorld.copy(vec(c.center)).applyMatrix4(groups[c.body].matrix);
    contactWorld.z -= c.radius;
    arrows[i].position.copy(contactWorld);
    arrows[i].setLength(Math.max(0.02, metresPerNewton * f), 0.03, 0.02);
  });
  slider.value = k;
  const near = best ? `closest near pair: ${scene.bodies[best.a]} – ${scene.bodies[best.b]} at ${(1e3 * best.d).toFixed(1)} mm`
                    : `no pair within ${(1e3 * scene.near_threshold).toFixed(0)} mm`;
  info.textContent = `${scene.robot}  t = ${frames.t[k].toFixed(3)} s  (frame ${k + 1} of ${numFrames})  ${near}`;
}

// --- controls -------------------------------------------------------------------------------
const slider = document.getElementById('frame');
slider.max = numFrames - 1;
slider.addEventListener('input', () => { playing = false; showFrame(Number(slider.value)); });
const playButton = document.getElementById('play');
let playing = false, playTime = 0, lastClock = 0;
playButton.addEventListener('click', () => {
  playing = !playing;
  if (playing && current === numFrames - 1) showFrame(0);
  playTime = frames.t[current];
  lastClock = performance.now();
});
const speed = document.getElementById('speed');
function bindToggle(id, objects) {
  const box = document.getElementById(id);
  const apply = () => objects().forEach((o) => { o.visible = box.checked; });
  box.addEventListener('change', apply);
  apply();
}
bindToggle('show-ssv', () => ssvGroups);
bindToggle('show-meshes', () => meshObjects);
bindToggle('show-frames', () => groups.map((g) => g.children.find((c) => c.userData.isFrame)));
bindToggle('show-closures', () => closureObjects);
bindToggle('show-witnesses', () => [witnesses]);
document.getElementById('show-forces').addEventListener('change', () => showFrame(current));
if (!scene.meshes.length) document.getElementById('show-meshes').parentElement.style.display = 'none';
if (!frames.forces) document.getElementById('show-forces').parentElement.style.display = 'none';
if (numFrames < 2) document.getElementById('timeline').style.display = 'none';

const hash = new URLSearchParams(window.location.hash.slice(1));
showFrame(Math.min(numFrames - 1, Math.max(0, Number(hash.get('frame') || 0))));

// The camera frames the robot at the first frame shown, from the front-left, a little above.
world.updateMatrixWorld(true);
const box = new THREE.Box3();
for (const g of groups) box.expandByObject(g);
if (box.isEmpty()) box.setFromCenterAndSize(new THREE.Vector3(0, 0, 0.5), new THREE.Vector3(1, 1, 1));
if (scene.ground) {  // the plane n . x = offset
  grid.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), vec(scene.ground.normal));
  grid.position.copy(vec(scene.ground.normal).multiplyScalar(scene.ground.offset));
} else {
  grid.position.z = box.min.z;
}
const centre = box.getCenter(new THREE.Vector3());
const size = Math.max(0.2, box.getSize(new THREE.Vector3()).length());
camera.position.copy(centre).add(new THREE.Vector3(1.25, 0.9, 0.4).multiplyScalar(size));
const controls = new OrbitControls(camera, renderer.domElement);
controls.target.copy(centre);
controls.update();

window.addEventListener('resize', () => {
  camera.aspect = window.innerWidth / window.innerHeight;
  camera.updateProjectionMatrix();
  renderer.setSize(window.innerWidth, window.innerHeight);
});

let drawn = false;
renderer.setAnimationLoop((clock) => {
  if (playing) {
    playTime += (clock - lastClock) / 1000 * Number(speed.value);
    let k = current;
    while (k + 1 < numFrames && frames.t[k + 1] <= playTime) ++k;
    if (k !== current) showFrame(k);
    if (k === numFrames - 1) playing = false;
  }
  lastClock = clock;
  playButton.textContent = playing ? 'pause' : 'play';
  renderer.render(world, camera);
  if (!drawn) {
    drawn = true;
    if (document.body.dataset.status !== 'error') document.body.dataset.status = 'ready';
  }
});
