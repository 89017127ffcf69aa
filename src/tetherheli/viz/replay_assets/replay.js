// The viewer of a tetherheli replay (tetherheli.viz.replay): three.js from the inlined source,
// the runs' frames from the inlined data. N is drawn as it is, n3 up; lengths in metres.
const $ = (id) => document.getElementById(id);
const statusEl = $("status");
const data = JSON.parse($("replay-data").textContent);
const librarySource = JSON.parse($("three-source").textContent);
const libraryUrl = URL.createObjectURL(new Blob([librarySource], { type: "text/javascript" }));
const THREE = await import(libraryUrl);
URL.revokeObjectURL(libraryUrl);

THREE.Object3D.DEFAULT_UP.set(0, 0, 1);
const times = data.time;
const nFrames = times.length;
const t0 = times[0];
const tEnd = times[nFrames - 1];
const step = nFrames > 1 ? (tEnd - t0) / (nFrames - 1) : 1;
const runs = data.runs;

// --- renderer, scene, lights ---------------------------------------------------------------
const view = $("view");
const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(window.devicePixelRatio || 1);
view.appendChild(renderer.domElement);
const scene = new THREE.Scene();
scene.background = new THREE.Color(0xeef1f5);
scene.add(new THREE.HemisphereLight(0xffffff, 0x667788, 2.2));
const sun = new THREE.DirectionalLight(0xffffff, 1.6);
sun.position.set(5, -8, 12);
scene.add(sun);

const lo = new THREE.Vector3(...data.bounds.lo);
const hi = new THREE.Vector3(...data.bounds.hi);
// the camera looks a little above the middle: the helicopters, not the ground, fill the view
const centre = lo.clone().add(hi).multiplyScalar(0.5);
centre.z = lo.z + 0.58 * (hi.z - lo.z);
const radius = Math.max(hi.clone().sub(lo).length() / 2, 2);

// the ground z = 0 (a grid in the n1-n2 plane) and the axes n1, n2, n3 at NO (1 m)
const reach = Math.max(Math.abs(lo.x), Math.abs(hi.x), Math.abs(lo.y), Math.abs(hi.y), 3);
const gridSize = 2 * Math.ceil(reach + 1);
const grid = new THREE.GridHelper(gridSize, gridSize, 0x99a3b0, 0xc8ced6);
grid.rotation.x = Math.PI / 2;
scene.add(grid);
scene.add(new THREE.AxesHelper(1.0));

// --- shapes -------------------------------------------------------------------------------
const solid = (colour) =>
  new THREE.MeshStandardMaterial({ color: colour, roughness: 0.6, metalness: 0.1 });
const dark = solid(0x333a44);

function box(size, at, material) {
  const mesh = new THREE.Mesh(new THREE.BoxGeometry(...size), material);
  mesh.position.set(...at);
  return mesh;
}

function disc(radius, colour, opacity) {
  return new THREE.Mesh(
    new THREE.CircleGeometry(radius, 48),
    new THREE.MeshBasicMaterial({
      color: colour, transparent: true, opacity, side: THREE.DoubleSide, depthWrite: false,
    }),
  );
}

// A simple helicopter in F about O (the animation's wireframe, as solids): cabin and nose,
// tail boom and fin to the tail rotor, mast and rotor disc with two blades, skids, hook.
function helicopter(run) {
  const g = run.geometry;
  const hull = solid(run.colour);
  const body = new THREE.Group();
  body.add(box([0.7, 0.26, 0.28], [0.05, 0, -0.1], hull));
  body.add(box([0.22, 0.18, 0.16], [0.5, 0, -0.12], hull));
  const boom = Math.abs(g.tail + 0.3);
  body.add(box([boom, 0.05, 0.05], [(g.tail - 0.3) / 2, 0, 0], hull));
  body.add(box([0.08, 0.02, 0.22], [g.tail - 0.04, 0, 0.11], hull));
  body.add(box([0.04, 0.04, Math.max(g.mast - 0.04, 0.01)], [0, 0, (g.mast + 0.04) / 2], dark));
  const rotor = disc(g.rotor_radius, run.colour, 0.18);
  rotor.position.set(0, 0, g.mast);
  body.add(rotor);
  for (const angle of [Math.PI / 4, (3 * Math.PI) / 4]) {
    const blade = box([2 * g.rotor_radius, 0.05, 0.012], [0, 0, g.mast], dark);
    blade.rotation.z = angle;
    body.add(blade);
  }
  const tailRotor = disc(g.tail_radius, run.colour, 0.35);
  tailRotor.rotation.x = Math.PI / 2;
  tailRotor.position.set(g.tail, 0.04, 0);
  body.add(tailRotor);
  for (const side of [-0.2, 0.2]) {
    body.add(box([0.7, 0.03, 0.03], [0.01, side, -0.3], dark));
    for (const x of [-0.15, 0.22]) body.add(box([0.02, 0.02, 0.07], [x, 0.8 * side, -0.27], dark));
  }
  const hook = Math.min(g.hook, -0.24);
  body.add(box([0.015, 0.015, -0.24 - hook + 0.01], [0, 0, (hook - 0.24) / 2], dark));
  return body;
}

// tension colours: the figures' colour map from 0 to tension_max; a slack tether grey
const tensionStops = data.tension_colours.map((c) => new THREE.Color(c));
const slackColour = new THREE.Color(0x9a9a9a);
function tensionColour(tension, out) {
  if (tension === null || !(tension > 1e-9)) return out.copy(slackColour);
  const x = Math.min(Math.max(tension / data.tension_max, 0), 1) * (tensionStops.length - 1);
  const i = Math.min(Math.floor(x), tensionStops.length - 2);
  return out.copy(tensionStops[i]).lerp(tensionStops[i + 1], x - i);
}

const yAxis = new THREE.Vector3(0, 1, 0);
const segmentGeometry = new THREE.CylinderGeometry(0.025, 0.025, 1, 8);
function placeSegment(mesh, a, b) {
  const d = b.clone().sub(a);
  const length = d.length();
  mesh.visible = length > 1e-6;
  if (!mesh.visible) return;
  mesh.position.copy(a).add(b).multiplyScalar(0.5);
  mesh.quaternion.setFromUnitVectors(yAxis, d.divideScalar(length));
  mesh.scale.set(1, length, 1);
}

const vec = (flat, k) => new THREE.Vector3(flat[3 * k], flat[3 * k + 1], flat[3 * k + 2]);
const finite = (flat, k, width = 3) => flat[width * k] !== null && flat[width * k] !== undefined;

// the deck and its pad, one per distinct base motion (runs over the same deck share it)
const decks = new Map();
for (const run of runs) {
  const key = JSON.stringify([run.frames.base, run.frames.deck_quaternion]);
  if (decks.has(key)) continue;
  const deck = new THREE.Group();
  deck.add(box([3, 3, 0.1], [0, 0, -0.05], solid(0x8d96a3)));
  const pad = new THREE.Mesh(
    new THREE.RingGeometry(0.45, 0.58, 48),
    new THREE.MeshBasicMaterial({ color: 0xf2c200, side: THREE.DoubleSide }),
  );
  pad.position.z = 0.003;
  deck.add(pad);
  deck.add(box([0.2, 0.2, 0.12], [0, 0, 0.06], dark));
  scene.add(deck);
  decks.set(key, { deck, base: run.frames.base, tilt: run.frames.deck_quaternion });
}

// --- per run: body, tether, wind arrow, path ----------------------------------------------
const drawn = runs.map((run) => {
  const f = run.frames;
  const body = helicopter(run);
  scene.add(body);
  const segments = [];
  const tetherMaterial = solid(0x888888);
  if (run.tethered) {
    const count = f.node_count > 1 ? f.node_count - 1 : 1;
    for (let i = 0; i < count; i++) {
      const mesh = new THREE.Mesh(segmentGeometry, tetherMaterial);
      scene.add(mesh);
      segments.push(mesh);
    }
  }
  const arrow = new THREE.ArrowHelper(new THREE.Vector3(1, 0, 0), new THREE.Vector3(), 1, 0xff8c00);
  scene.add(arrow);
  const path = [];
  for (let k = 0; k < nFrames; k++) if (finite(f.HO, k)) path.push(vec(f.HO, k));
  const line = new THREE.Line(
    new THREE.BufferGeometry().setFromPoints(path),
    new THREE.LineBasicMaterial({ color: run.colour, transparent: true, opacity: 0.45 }),
  );
  scene.add(line);
  return { run, body, segments, tetherMaterial, arrow };
});

// --- the panel: one line per run, the tension scale --------------------------------------
const runsEl = $("runs");
const lines = runs.map((run) => {
  const el = document.createElement("div");
  el.className = "run";
  el.title = `${run.stem} (${run.configuration})`;
  runsEl.appendChild(el);
  return el;
});
$("bar").style.background = `linear-gradient(to right, ${data.tension_colours.join(", ")})`;
$("tension-range").textContent = `0 to ${data.tension_max.toFixed(1)} N; grey: slack`;
$("wind-label").textContent =
  data.wind_scale > 0 ? `wind force on HO (orange): 1 m = ${(1 / data.wind_scale).toPrecision(3)} N` : "no wind";
if (!runs.some((r) => r.tethered)) {
  for (const id of ["tension-label", "bar", "tension-range"]) $(id).hidden = true;
}

function fmt(x, digits, width) {
  return (x === null ? "n/a" : x.toFixed(digits)).padStart(width);
}

// --- one frame ------------------------------------------------------------------------------
const colour = new THREE.Color();
const quaternion = new THREE.Quaternion();
function update(k) {
  for (const { deck, base, tilt } of decks.values()) {
    deck.visible = finite(base, k);
    if (deck.visible) deck.position.copy(vec(base, k));
    if (deck.visible && tilt && finite(tilt, k, 4)) {  // over a ship: roll, pitch, yaw
      deck.quaternion.set(tilt[4 * k], tilt[4 * k + 1], tilt[4 * k + 2], tilt[4 * k + 3]);
    }
  }
  const t = times[k];
  drawn.forEach(({ run, body, segments, tetherMaterial, arrow }, i) => {
    const f = run.frames;
    const ok = finite(f.O, k) && finite(f.quaternion, k, 4);
    body.visible = ok;
    if (ok) {
      body.position.copy(vec(f.O, k));
      const q = f.quaternion;
      body.quaternion.copy(quaternion.set(q[4 * k], q[4 * k + 1], q[4 * k + 2], q[4 * k + 3]));
    }
    if (segments.length) {
      const tension = f.tension[k];
      tetherMaterial.color.copy(tensionColour(tension, colour));
      if (f.node_count > 1) {
        const base = 3 * f.node_count * k;
        const node = (i) => new THREE.Vector3(...f.nodes.slice(base + 3 * i, base + 3 * i + 3));
        segments.forEach((mesh, j) => placeSegment(mesh, node(j), node(j + 1)));
      } else if (finite(f.base, k) && finite(f.P, k)) {
        placeSegment(segments[0], vec(f.base, k), vec(f.P, k));
      }
    }
    const wind = finite(f.wind, k) ? vec(f.wind, k) : new THREE.Vector3();
    const length = wind.length() * data.wind_scale;
    arrow.visible = ok && length > 1e-6;
    if (arrow.visible) {
      arrow.position.copy(vec(f.HO, k));
      arrow.setDirection(wind.clone().normalize());
      arrow.setLength(length, Math.min(0.25, 0.4 * length), Math.min(0.12, 0.2 * length));
    }
    let text = `${run.name} (${run.configuration})  |Fw| = ${fmt(wind.length(), 1, 5)} N`;
    text += `  |HO - trim| = ${fmt(f.deviation[k], 2, 5)} m`;
    if (run.tethered) text += `  TC = ${fmt(f.tension[k], 1, 6)} N`;
    if (run.status !== 0 && t >= run.end_time) text += `  (stopped at ${run.end_time.toFixed(2)} s: ${run.message})`;
    lines[i].textContent = "";
    const swatch = document.createElement("span");
    swatch.className = "swatch";
    swatch.style.background = run.colour;
    lines[i].append(swatch, text);
  });
  $("clock").textContent = `t = ${t.toFixed(2)} s`;
}

// --- camera: turned about a target by dragging, zoomed by the wheel --------------------------
const camera = new THREE.PerspectiveCamera(40, 1, 0.05, 10000);
let azimuth = (-60 * Math.PI) / 180;
let elevation = (18 * Math.PI) / 180;
let distance = (1.05 * radius) / Math.sin((20 * Math.PI) / 180);
let frame = 0;
const follow = $("follow");
function placeCamera() {
  let target = centre;
  const f = runs[0].frames;
  if (follow.checked && finite(f.HO, frame)) target = vec(f.HO, frame);
  const c = Math.cos(elevation);
  camera.position.set(
    target.x + distance * c * Math.cos(azimuth),
    target.y + distance * c * Math.sin(azimuth),
    target.z + distance * Math.sin(elevation),
  );
  camera.lookAt(target);
}
function resize() {
  const w = Math.max(view.clientWidth, 1);
  const h = Math.max(view.clientHeight, 1);
  renderer.setSize(w, h);
  camera.aspect = w / h;
  camera.updateProjectionMatrix();
}
function render() {
  placeCamera();
  renderer.render(scene, camera);
}

let dragging = null;
renderer.domElement.addEventListener("pointerdown", (e) => {
  dragging = { x: e.clientX, y: e.clientY };
  renderer.domElement.setPointerCapture(e.pointerId);
});
renderer.domElement.addEventListener("pointerup", () => (dragging = null));
renderer.domElement.addEventListener("pointermove", (e) => {
  if (!dragging) return;
  azimuth -= 0.006 * (e.clientX - dragging.x);
  elevation = Math.min(Math.max(elevation + 0.006 * (e.clientY - dragging.y), -1.5), 1.5);
  dragging = { x: e.clientX, y: e.clientY };
  render();
});
renderer.domElement.addEventListener("wheel", (e) => {
  e.preventDefault();
  distance = Math.min(Math.max(distance * Math.exp(0.001 * e.deltaY), 0.5), 1e4);
  render();
}, { passive: false });
follow.addEventListener("change", render);
window.addEventListener("resize", () => { resize(); render(); });

// --- time: slider, play/pause, speed, #t=<seconds> ------------------------------------------
const slider = $("slider");
const playButton = $("play");
slider.max = String(nFrames - 1);
let playing = false;
let simTime = t0;
let lastTick = null;

function frameAt(t) {
  return Math.min(Math.max(Math.round((t - t0) / step), 0), nFrames - 1);
}
function show(k) {
  frame = k;
  slider.value = String(k);
  update(k);
  render();
}
function setPlaying(on) {
  playing = on && nFrames > 1;
  playButton.textContent = playing ? "Pause" : "Play";
  lastTick = null;
  if (playing) requestAnimationFrame(tick);
}
function tick(now) {
  if (!playing) return;
  if (lastTick !== null) {
    simTime += ((now - lastTick) / 1000) * Number($("speed").value);
    if (simTime > tEnd) simTime = t0;
  }
  lastTick = now;
  const k = frameAt(simTime);
  if (k !== frame) show(k);
  requestAnimationFrame(tick);
}
slider.addEventListener("input", () => {
  simTime = times[Number(slider.value)];
  show(Number(slider.value));
});
playButton.addEventListener("click", () => setPlaying(!playing));
window.addEventListener("keydown", (e) => {
  if (e.target.tagName === "INPUT" && e.target.type !== "range") return;
  if (e.code === "Space") { e.preventDefault(); setPlaying(!playing); }
  if (e.code === "ArrowRight") show(Math.min(frame + 1, nFrames - 1));
  if (e.code === "ArrowLeft") show(Math.max(frame - 1, 0));
});
function timeFromHash() {
  const found = /(?:^|[#&])t=([-+0-9.eE]+)/.exec(window.location.hash);
  const t = found ? Number(found[1]) : NaN;
  return Number.isFinite(t) ? t : null;
}
window.addEventListener("hashchange", () => {
  const t = timeFromHash();
  if (t !== null) { setPlaying(false); simTime = t; show(frameAt(t)); }
});

resize();
const start = timeFromHash();
simTime = start !== null ? start : t0;
show(frameAt(simTime));
if (statusEl.dataset.errors === "0") {
  statusEl.dataset.state = "ready";
  statusEl.dataset.frame = String(frame);
  statusEl.textContent = `${data.generator}: ${runs.length} run(s), ${nFrames} frames at ${data.fps} per s; frame ${frame} at t = ${times[frame].toFixed(2)} s`;
}
