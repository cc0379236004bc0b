// The studio's page: sends the view it wants over the WebSocket, draws the
// frames that come back and keeps each frame's region ids for picking.
'use strict';

const $ = (id) => document.getElementById(id);
const token = location.pathname.split('/')[2];
const canvas = $('view');
const context = canvas.getContext('2d', { willReadFrequently: true });

const studio = {
  model: null,
  version: 0,
  view: null, // target, az, el, distance, ortho, view_height, fov, up
  hidden: new Set(),
  ghost: new Set(),
  cuts: [], // {axis, sign, value}
  frame: null,
  filmCamera: true,
  seq: 0,
  ids: null,
  idsWidth: 0,
  idsHeight: 0,
  framesReceived: 0,
  lastFrame: null, // header of the last frame drawn
  picked: null,
  sent: new Map(), // seq -> time sent, for latency
  latency: [],
};
window.studio = studio;

const socket = new WebSocket(`ws://${location.host}/s/${token}/ws`);
socket.binaryType = 'arraybuffer';
socket.onopen = () => status('connected');
socket.onclose = () => status('disconnected: restart the studio and reload');
socket.onmessage = (event) => {
  if (typeof event.data === 'string') {
    answer(JSON.parse(event.data));
  } else {
    drawFrame(event.data);
  }
};

function status(text) { $('status').textContent = text; }
function send(message) {
  if (socket.readyState === WebSocket.OPEN) socket.send(JSON.stringify(message));
}

// ---- the camera -------------------------------------------------------

function azEl(az, el) {
  const a = az * Math.PI / 180, e = el * Math.PI / 180;
  return [Math.cos(e) * Math.cos(a), Math.cos(e) * Math.sin(a), Math.sin(e)];
}
function turnZUp(v, up) {
  if (up === 'y') return [v[1], v[2], v[0]];
  if (up === 'x') return [v[2], v[0], v[1]];
  return v;
}
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const scale = (a, s) => a.map((x) => x * s);
const add = (a, b) => a.map((x, i) => x + b[i]);
const norm = (a) => scale(a, 1 / Math.hypot(...a));

// Right and up unit vectors of the picture, as the engine makes them.
function basis(view) {
  const forward = scale(turnZUp(azEl(view.az, view.el), view.up), -1);
  let up = turnZUp([0, 0, 1], view.up);
  if (Math.abs(view.el) > 89) {
    const a = view.az * Math.PI / 180;
    up = turnZUp([-Math.cos(a), -Math.sin(a), 0], view.up);
  }
  const right = norm(cross(forward, up));
  return { right, up: cross(right, forward) };
}

// The model framed from azimuth 35°, elevation 25° (or from the scene's
// own camera, when it has one and `scene` is asked for).
function defaultView(scene) {
  const m = studio.model;
  const view = {
    target: m.target.slice(), az: 35, el: 25, distance: m.distance,
    ortho: $('ortho').checked, view_height: 2 * m.radius, fov: 30, up: $('up').value,
  };
  if (scene && m.camera && view.up === 'z') Object.assign(view, m.camera, { target: m.camera.target.slice() });
  return view;
}

let pendingMoving = null;
// Ask for the view; while moving, at most once a display frame.
function requestView(moving) {
  if (!studio.view) return;
  if (moving) {
    if (pendingMoving === null) {
      pendingMoving = requestAnimationFrame(() => { pendingMoving = null; sendView(true); });
    }
    return;
  }
  if (pendingMoving !== null) { cancelAnimationFrame(pendingMoving); pendingMoving = null; }
  sendView(false);
}

function sendView(moving) {
  const v = studio.view;
  studio.seq += 1;
  studio.sent.set(studio.seq, performance.now());
  send({
    type: 'view', seq: studio.seq, moving,
    target: v.target, az: v.az, el: v.el, distance: v.distance,
    ortho: v.ortho, view_height: v.view_height, fov: v.fov, up: v.up,
    width: canvas.width, height: canvas.height,
    hidden: [...studio.hidden], ghost: [...studio.ghost],
    cuts: studio.cuts.map(cutPlane),
    frame: studio.frame, film_camera: studio.frame !== null && studio.filmCamera,
  });
}

// ---- frames -----------------------------------------------------------

let framesThisSecond = 0, secondStarted = performance.now(), fps = 0;
async function drawFrame(buffer) {
  const headerLength = new DataView(buffer).getUint32(0, true);
  const header = JSON.parse(new TextDecoder().decode(new Uint8Array(buffer, 4, headerLength)));
  const jpegStart = 4 + headerLength;
  const jpeg = new Blob([new Uint8Array(buffer, jpegStart, header.jpeg_bytes)], { type: 'image/jpeg' });
  const ids = new Uint32Array(buffer.slice(jpegStart + header.jpeg_bytes));
  const picture = await createImageBitmap(jpeg);
  if (studio.lastFrame && header.seq < studio.lastFrame.seq) return; // stale
  context.imageSmoothingEnabled = header.kind === 'coarse';
  context.drawImage(picture, 0, 0, canvas.width, canvas.height);
  drawPickOutline(header, ids);
  studio.ids = ids;
  studio.idsWidth = header.width;
  studio.idsHeight = header.height;
  studio.lastFrame = header;
  studio.framesReceived += 1;
  canvas.dataset.frames = String(studio.framesReceived);
  canvas.dataset.kind = header.kind;
  const sentAt = studio.sent.get(header.seq);
  if (sentAt !== undefined) {
    studio.latency.push(performance.now() - sentAt);
    if (studio.latency.length > 50) studio.latency.shift();
  }
  for (const seq of studio.sent.keys()) if (seq <= header.seq) studio.sent.delete(seq);
  framesThisSecond += 1;
  const now = performance.now();
  if (now - secondStarted > 1000) {
    fps = framesThisSecond * 1000 / (now - secondStarted);
    framesThisSecond = 0;
    secondStarted = now;
  }
  status(`${header.kind} ${header.width}×${header.height} · ${header.render_ms.toFixed(0)} ms render · ${fps.toFixed(1)} frames/s`);
}

// The picked region's outline, from the region ids.
function drawPickOutline(header, ids) {
  if (studio.picked === null) return;
  const id = studio.picked + 1, w = header.width, h = header.height;
  const sx = canvas.width / w, sy = canvas.height / h;
  context.fillStyle = '#ffdd33';
  for (let y = 1; y < h - 1; y++) {
    for (let x = 1; x < w - 1; x++) {
      const i = y * w + x;
      if (ids[i] === id && (ids[i - 1] !== id || ids[i + 1] !== id || ids[i - w] !== id || ids[i + w] !== id)) {
        context.fillRect(x * sx, y * sy, Math.max(sx, 1.5), Math.max(sy, 1.5));
      }
    }
  }
}

// Region index under a point of the canvas (client coordinates), or -1.
function regionAt(event) {
  if (!studio.ids) return -1;
  const box = canvas.getBoundingClientRect();
  const x = Math.floor((event.clientX - box.left) / box.width * studio.idsWidth);
  const y = Math.floor((event.clientY - box.top) / box.height * studio.idsHeight);
  if (x < 0 || y < 0 || x >= studio.idsWidth || y >= studio.idsHeight) return -1;
  return studio.ids[y * studio.idsWidth + x] - 1;
}

// ---- the mouse and touch ------------------------------------------------

let drag = null;
canvas.addEventListener('contextmenu', (e) => e.preventDefault());
canvas.addEventListener('pointerdown', (e) => {
  canvas.setPointerCapture(e.pointerId);
  const pan = e.button === 2 || e.button === 1 || e.ctrlKey;
  drag = { x: e.clientX, y: e.clientY, startX: e.clientX, startY: e.clientY, pan, moved: false, shift: e.shiftKey };
});
canvas.addEventListener('pointermove', (e) => {
  if (!drag || !studio.view) return;
  const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
  drag.x = e.clientX; drag.y = e.clientY;
  if (Math.abs(e.clientX - drag.startX) + Math.abs(e.clientY - drag.startY) > 3) drag.moved = true;
  if (!drag.moved) return;
  const v = studio.view;
  if (drag.pan) {
    const box = canvas.getBoundingClientRect();
    const height = v.ortho ? v.view_height : 2 * v.distance * Math.tan(v.fov * Math.PI / 360);
    const perPixel = height / box.height;
    const { right, up } = basis(v);
    v.target = add(v.target, add(scale(right, -dx * perPixel), scale(up, dy * perPixel)));
  } else {
    v.az -= dx * 0.4;
    v.el = Math.max(-90, Math.min(90, v.el + dy * 0.4));
  }
  requestView(true);
});
canvas.addEventListener('pointerup', (e) => {
  if (!drag) return;
  const wasDrag = drag.moved, shift = drag.shift;
  drag = null;
  if (wasDrag) { requestView(false); return; }
  if (shift) { shoot(e); return; }
  pick(regionAt(e));
});
let wheelTimer = null;
canvas.addEventListener('wheel', (e) => {
  e.preventDefault();
  if (!studio.view) return;
  const factor = Math.pow(1.0015, e.deltaY);
  studio.view.distance *= factor;
  studio.view.view_height *= factor;
  requestView(true);
  clearTimeout(wheelTimer);
  wheelTimer = setTimeout(() => requestView(false), 180);
}, { passive: false });

// Two fingers pinch to zoom (one finger turns, as the mouse).
let pinch = null;
canvas.addEventListener('touchstart', (e) => {
  if (e.touches.length === 2) {
    pinch = Math.hypot(e.touches[0].clientX - e.touches[1].clientX, e.touches[0].clientY - e.touches[1].clientY);
  }
});
canvas.addEventListener('touchmove', (e) => {
  if (e.touches.length !== 2 || !pinch || !studio.view) return;
  const now = Math.hypot(e.touches[0].clientX - e.touches[1].clientX, e.touches[0].clientY - e.touches[1].clientY);
  studio.view.distance *= pinch / now;
  studio.view.view_height *= pinch / now;
  pinch = now;
  requestView(true);
});
canvas.addEventListener('touchend', () => { if (pinch) { pinch = null; requestView(false); } });

function shoot(event) {
  const box = canvas.getBoundingClientRect();
  send({
    type: 'shoot',
    x: (event.clientX - box.left) / box.width * canvas.width,
    y: (event.clientY - box.top) / box.height * canvas.height,
  });
}

// ---- the view buttons ---------------------------------------------------

const standard = { scene: [35, 25], default: [35, 25], front: [0, 0], side: [90, 0], top: [0, 90] };
for (const button of document.querySelectorAll('[data-view]')) {
  button.addEventListener('click', () => {
    if (!studio.model) return;
    const [az, el] = standard[button.dataset.view];
    const name = button.dataset.view;
    studio.view = name === 'scene' ? defaultView(true) : Object.assign(defaultView(false), { az, el });
    requestView(false);
  });
}
$('ortho').addEventListener('change', () => {
  if (!studio.view) return;
  studio.view.ortho = $('ortho').checked;
  requestView(false);
});
$('up').addEventListener('change', () => {
  if (!studio.view) return;
  studio.view.up = $('up').value;
  requestView(false);
});

// ---- answers ------------------------------------------------------------

function answer(message) {
  switch (message.type) {
    case 'model': return loadModel(message);
    case 'problems': return showProblems(message.problems);
    case 'pick': return showPick(message);
    case 'volume': return showVolume(message);
    case 'check': return showOverlaps(message);
    case 'slice': return showSection(message);
    case 'shoot': return showShoot(message);
    case 'written': return showWritten(message);
    case 'error': return status(`error: ${message.message}`);
    default: return undefined;
  }
}

function loadModel(model) {
  const first = studio.model === null;
  studio.model = model;
  studio.version = model.version;
  $('problems').hidden = true;
  $('title').textContent = `${model.title || ''} — ${model.file} (${model.regions.length} regions, ${model.units})`;
  $('notes').textContent = model.notes.join(' · ');
  if (first) {
    studio.view = defaultView(true);
    for (const region of model.regions) if (region.hidden) studio.hidden.add(region.index);
  }
  // A reload keeps the camera; regions that went away are forgotten.
  for (const set of [studio.hidden, studio.ghost]) {
    for (const index of [...set]) if (index >= model.regions.length) set.delete(index);
  }
  setupFilm(model);
  listRegions();
  if (studio.picked !== null && studio.picked < model.regions.length) send({ type: 'pick', region: studio.picked });
  requestView(false);
}

function showProblems(problems) {
  const box = $('problems');
  box.hidden = false;
  box.replaceChildren();
  const head = document.createElement('div');
  head.textContent = 'The file has errors; the last good model is shown.';
  box.append(head);
  for (const problem of problems) {
    const where = document.createElement('div');
    where.className = 'problem';
    where.textContent = `${problem.file}:${problem.line}:${problem.column}: ${problem.message}`;
    const text = document.createElement('pre');
    text.textContent = problem.text;
    box.append(where, text);
  }
}

function escapeText(text) {
  const span = document.createElement('span');
  span.textContent = text;
  return span.innerHTML;
}
const writtenAt = (w) => (w ? `<pre>${escapeText(`${w.file}:${w.line}\n${w.text}`)}</pre>` : '');

function showPick(region) {
  studio.picked = region.index;
  $('pick-name').textContent = `${region.name} (#${region.number})`;
  const bodies = region.bodies.map((b) =>
    `<tr><td>${escapeText(b.name)}</td><td>${escapeText(b.type)}</td><td>${b.params.map((p) => +p.toPrecision(6)).join(' ')}</td></tr>`).join('');
  $('pick-details').innerHTML =
    `<div>${escapeText(region.description || '')}</div>` +
    `<div>material ${escapeText(region.material)}${region.density ? `, ${region.density} g/cm³` : ''}</div>` +
    `<div>expression</div><pre>${escapeText(region.expression)}</pre>` + writtenAt(region.written) +
    `<div>bodies</div><table>${bodies}</table>`;
  $('pick-buttons').hidden = false;
  $('pick-volume-result').textContent = '';
  requestView(false);
}

function showVolume(v) {
  const centroid = v.centroid ? ` centroid (${v.centroid.map((c) => c.toPrecision(5)).join(', ')})` : '';
  const mass = v.mass_g ? `, ${v.mass_g.toPrecision(4)} g` : '';
  $('pick-volume-result').textContent = `volume ${v.volume.toPrecision(5)} ± ${v.error.toPrecision(2)} ${v.unit}³${mass}${centroid}`;
}

function pick(index) {
  if (index < 0) {
    studio.picked = null;
    $('pick-name').textContent = 'Click a region.';
    $('pick-details').textContent = '';
    $('pick-buttons').hidden = true;
    requestView(false);
    return;
  }
  send({ type: 'pick', region: index });
}

function toggle(set, index) {
  if (set.has(index)) set.delete(index); else set.add(index);
}
$('pick-ghost').onclick = () => { toggle(studio.ghost, studio.picked); changedLooks(); };
$('pick-hide').onclick = () => { studio.hidden.add(studio.picked); changedLooks(); };
$('pick-isolate').onclick = () => {
  studio.hidden = new Set(studio.model.regions.map((r) => r.index).filter((i) => i !== studio.picked));
  changedLooks();
};
$('pick-material').onclick = () => {
  const material = studio.model.regions[studio.picked].material;
  for (const r of studio.model.regions) if (r.material === material) toggle(studio.ghost, r.index);
  changedLooks();
};
$('pick-volume').onclick = () => {
  $('pick-volume-result').textContent = 'measuring…';
  send({ type: 'volume', region: studio.picked });
};
$('show-all').onclick = () => {
  studio.hidden = new Set(studio.model.regions.filter((r) => r.hidden).map((r) => r.index));
  studio.ghost.clear();
  changedLooks();
};

function changedLooks() {
  listRegions();
  requestView(false);
}

// ---- the region list and materials -------------------------------------

$('search').addEventListener('input', listRegions);
function listRegions() {
  const model = studio.model;
  if (!model) return;
  const wanted = $('search').value.toLowerCase();
  const rows = [];
  for (const r of model.regions) {
    if (rows.length >= 500) break;
    const text = `${r.name} ${r.description} ${r.material}`.toLowerCase();
    if (wanted && !text.includes(wanted)) continue;
    const row = document.createElement('div');
    const shown = document.createElement('input');
    shown.type = 'checkbox';
    shown.checked = !studio.hidden.has(r.index);
    shown.title = 'shown';
    shown.onchange = () => { toggle(studio.hidden, r.index); requestView(false); };
    const ghost = document.createElement('button');
    ghost.textContent = 'T';
    ghost.title = 'transparent';
    ghost.className = studio.ghost.has(r.index) ? 'on' : '';
    ghost.onclick = () => { toggle(studio.ghost, r.index); changedLooks(); };
    const swatch = document.createElement('span');
    swatch.className = 'swatch';
    swatch.style.background = r.colour;
    const name = document.createElement('span');
    name.className = 'name';
    name.textContent = r.name;
    name.onclick = () => send({ type: 'pick', region: r.index });
    const desc = document.createElement('span');
    desc.className = 'desc';
    desc.textContent = r.description;
    row.append(shown, ghost, swatch, name, desc);
    rows.push(row);
  }
  $('regions').replaceChildren(...rows);
  listMaterials();
}

function listMaterials() {
  const groups = new Map();
  for (const r of studio.model.regions) {
    if (!groups.has(r.material)) groups.set(r.material, []);
    groups.get(r.material).push(r.index);
  }
  const rows = [];
  for (const [material, members] of groups) {
    const row = document.createElement('div');
    const shown = document.createElement('input');
    shown.type = 'checkbox';
    shown.checked = members.some((i) => !studio.hidden.has(i));
    shown.onchange = () => {
      for (const i of members) { if (shown.checked) studio.hidden.delete(i); else studio.hidden.add(i); }
      changedLooks();
    };
    const ghost = document.createElement('button');
    ghost.textContent = 'T';
    ghost.className = members.every((i) => studio.ghost.has(i)) ? 'on' : '';
    ghost.onclick = () => {
      const all = members.every((i) => studio.ghost.has(i));
      for (const i of members) { if (all) studio.ghost.delete(i); else studio.ghost.add(i); }
      changedLooks();
    };
    const label = document.createElement('span');
    label.textContent = `material ${material} (${members.length})`;
    row.append(shown, ghost, label);
    rows.push(row);
  }
  $('materials').replaceChildren(...rows);
}

// ---- cut planes and the section view -----------------------------------

const axisIndex = { x: 0, y: 1, z: 2 };
function cutPlane(cut) {
  const normal = [0, 0, 0], point = [0, 0, 0];
  normal[axisIndex[cut.axis]] = cut.sign;
  point[axisIndex[cut.axis]] = cut.value;
  return [...normal, ...point];
}

$('cut-add').onclick = () => {
  if (!studio.model) return;
  const axis = $('cut-axis').value;
  studio.cuts.push({ axis, sign: 1, value: studio.model.target[axisIndex[axis]] });
  listCuts();
  requestView(false);
  section(studio.cuts[studio.cuts.length - 1]);
};

let sectionWaiting = false;
function section(cut) {
  if (sectionWaiting) return;
  sectionWaiting = true;
  const plane = cutPlane(cut);
  send({ type: 'slice', normal: plane.slice(0, 3), point: plane.slice(3), width: 320, height: 240 });
}
function showSection(message) {
  sectionWaiting = false;
  const img = $('section');
  img.src = message.png;
  img.style.display = 'block';
  $('section-legend').textContent = message.legend.slice(0, 12).map((l) => l.label).join(', ');
}

function listCuts() {
  const rows = studio.cuts.map((cut, n) => {
    const row = document.createElement('div');
    row.className = 'buttons';
    const label = document.createElement('span');
    label.textContent = `${cut.sign > 0 ? '' : '−'}${cut.axis} =`;
    const slider = document.createElement('input');
    slider.type = 'range';
    const centre = studio.model.target[axisIndex[cut.axis]], radius = studio.model.radius;
    slider.min = centre - radius;
    slider.max = centre + radius;
    slider.step = radius / 500;
    slider.value = cut.value;
    const value = document.createElement('span');
    value.textContent = (+cut.value).toPrecision(4);
    slider.oninput = () => { cut.value = +slider.value; value.textContent = cut.value.toPrecision(4); requestView(true); section(cut); };
    slider.onchange = () => { requestView(false); section(cut); };
    const flip = document.createElement('button');
    flip.textContent = '⇄';
    flip.title = 'keep the other side';
    flip.onclick = () => { cut.sign = -cut.sign; listCuts(); requestView(false); };
    const remove = document.createElement('button');
    remove.textContent = '×';
    remove.onclick = () => { studio.cuts.splice(n, 1); listCuts(); requestView(false); };
    row.append(label, slider, value, flip, remove);
    return row;
  });
  $('cuts').replaceChildren(...rows);
}

// ---- overlaps and rays ---------------------------------------------------

$('check').onclick = () => {
  $('overlaps').textContent = 'checking…';
  send({ type: 'check' });
};
function showOverlaps(report) {
  const list = $('overlaps');
  list.replaceChildren();
  if (report.overlaps.length === 0) {
    list.textContent = `no overlaps (${report.rays} rays, ${report.seconds.toFixed(1)} s)`;
    return;
  }
  for (const overlap of report.overlaps.slice(0, 100)) {
    const item = document.createElement('li');
    item.textContent = `${overlap.regions[0]} × ${overlap.regions[1]} (${overlap.max_length.toPrecision(3)} deep)`;
    item.onclick = () => flyTo(overlap);
    list.append(item);
  }
}
// Look at the overlap: the pair drawn, every other region transparent.
function flyTo(overlap) {
  const v = studio.view;
  v.target = overlap.point.slice();
  v.distance = Math.max(studio.model.distance * 0.3, overlap.max_length * 10);
  v.view_height = Math.max(2 * studio.model.radius * 0.3, overlap.max_length * 6);
  studio.ghost = new Set(studio.model.regions.map((r) => r.index).filter((i) => !overlap.indices.includes(i)));
  changedLooks();
}

function showShoot(ray) {
  const rows = ray.steps.map((s) =>
    `<tr><td>${s.t.toPrecision(6)}</td><td>${s.entering ? 'enters' : 'leaves'}</td><td>${escapeText(s.body)}</td><td>${escapeText(s.kind)}</td><td>${escapeText(s.after.join(' + ') || '(outside)')}${s.after.length > 1 ? ' (overlap)' : ''}</td></tr>`).join('');
  const from = ray.from.map((c) => c.toPrecision(5)).join(', ');
  $('shoot').innerHTML = `<div>from (${from})</div><table>${rows}</table>`;
}

// ---- the film -----------------------------------------------------------

function setupFilm(model) {
  $('film').hidden = model.frames === 0;
  if (model.frames === 0) { studio.frame = null; return; }
  if (studio.frame === null || studio.frame >= model.frames) studio.frame = 0;
  $('frame').max = model.frames - 1;
  $('frame').value = studio.frame;
  $('frame-count').textContent = model.frames;
  $('frame-number').textContent = studio.frame;
  $('range-last').value = model.frames - 1;
}
function showFrame(n) {
  studio.frame = n;
  $('frame').value = n;
  $('frame-number').textContent = n;
  requestView(false);
}
$('frame').oninput = () => showFrame(+$('frame').value);
$('film-camera').onchange = () => { studio.filmCamera = $('film-camera').checked; requestView(false); };
let playing = null;
$('play').onclick = () => {
  if (playing) { clearInterval(playing); playing = null; $('play').textContent = 'Play'; return; }
  $('play').textContent = 'Stop';
  playing = setInterval(() => showFrame((studio.frame + 1) % studio.model.frames), 1000 / (studio.model.fps || 24));
};
$('render-frame').onclick = () => send({ type: 'render_file', first: studio.frame, last: studio.frame });
$('render-range').onclick = () => send({ type: 'render_file', first: +$('range-first').value, last: +$('range-last').value });
$('render-view').onclick = () => send({ type: 'render_file' });
function showWritten(message) {
  $('written').textContent = `written: ${message.files.slice(0, 3).join(', ')}${message.files.length > 3 ? ` and ${message.files.length - 3} more` : ''}`;
}
