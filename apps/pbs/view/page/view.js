// pbs view's page: sends the camera and the settings, shows the frames the server renders.
// While the camera moves, two frames are in flight at once (the server renders one while the other is
// encoded, sent and decoded); a camera that moves meanwhile sends only its latest state when one returns,
// and the server drops a request once a newer one of the same tab has arrived. While the camera rests,
// the view is refined in stages (the full surfel frame, then exact, then 16 samples), one at a time.
'use strict';

const $ = (id) => document.getElementById(id);
const params = new URLSearchParams(location.search);
const client = 'tab-' + Math.random().toString(36).slice(2, 10);

const view = {
  scene: null,
  camera: null,       // {tx, ty, tz, az, el, dist}: an orbit around the target, dist in scene radii
  show: params.get('show') || 'surfels',
  refine: params.get('refine') !== '0',
  lod: null,          // {threshold, overdraw, splat, point}
  budgetKind: '',
  budget: 0,
  size: params.get('size') || 'fit',
  movingScale: 1,     // the share of the overdraw moving frames draw, adapted to keep them fast
  node: null,         // the clicked node's description (/api/pick), or null
  prefix: 1,          // show=prefix: the node's first surfels drawn
  boxes: false,       // the overlay of node boxes
};

// What tests and scripts/view-fps.mjs read: the last frame shown (with when, in performance.now()
// milliseconds), whether the still view is fully refined, the moving frames shown so far and how long the
// last ones took from request to picture and to render on the server.
window.pbsView = { ready: false, shown: null, refined: false, movingShown: 0, deliveredMs: [], renderMs: [],
                   errors: [] };

let sequence = 0;
const kMovingInFlight = 2;
let movingInFlight = 0;     // moving frames asked for and not yet answered
let stillInFlight = null;   // the still stage's AbortController, while one is asked for
let movePending = false;    // the camera moved since the last moving frame was asked for
let lastShown = 0;          // the sequence number of the frame on screen: older answers are not shown
let stillStages = [];       // what the resting camera still has to show, in order
let stillTimer = 0;
const movingTimes = [];     // when each moving frame was shown, for the frame rate

function frameSize() {
  if (view.size !== 'fit') return view.size.split('x').map(Number);
  const stage = $('stage');
  return [Math.max(16, Math.min(3840, stage.clientWidth)), Math.max(16, Math.min(2160, stage.clientHeight))];
}

// The frame's query: the camera, what to show, the settings. `overrides` changes some of them.
function frameQuery(overrides) {
  const [w, h] = frameSize();
  const c = view.camera;
  const q = {
    client, seq: ++sequence, w, h,
    tx: c.tx, ty: c.ty, tz: c.tz, az: c.az, el: c.el, dist: c.dist,
    show: view.show, samples: 1, format: 'png',
    threshold: view.lod.threshold, overdraw: view.lod.overdraw, splat: view.lod.splat,
  };
  if (view.lod.splat === 'nearest') q.point = view.lod.point;
  if (view.show === 'prefix') Object.assign(q, { node: view.node.node, prefix: view.prefix });
  if (view.budgetKind && view.budget > 0) q[view.budgetKind] = view.budget;
  Object.assign(q, overrides);
  return new URLSearchParams(q).toString();
}

// The overdraw moving surfel frames draw: the setting scaled down while frames are slow, but not below the
// least the slider (and the server) takes.
function movingOverdraw() {
  return Math.max(2 ** Number($('overdraw').min), view.lod.overdraw * view.movingScale);
}

function movingQuery() {
  if (view.show === 'difference' || view.show === 'flip') {
    // Comparisons need a 16-sample reference: while moving, the frame they compare.
    return frameQuery({ show: view.scene.surfels ? 'surfels' : 'embree', format: 'jpeg', overdraw: movingOverdraw() });
  }
  const overdraw = view.show === 'surfels' || view.show === 'source' ? movingOverdraw() : view.lod.overdraw;
  return frameQuery({ format: 'jpeg', overdraw });
}

function stillQueries() {
  const stages = [{ label: view.show, query: frameQuery({}) }];
  if (!view.refine) return stages;
  if (view.show === 'surfels') {
    stages.push({ label: 'exact (rays)', query: frameQuery({ show: 'embree' }) });
    stages.push({ label: 'exact (rays), 16 samples', query: frameQuery({ show: 'embree', samples: 16 }) });
  } else if (view.show === 'exact' || view.show === 'embree') {
    stages.push({ label: view.show + ', 16 samples', query: frameQuery({ samples: 16 }) });
  }
  return stages;
}

async function send(query, still, label) {
  const controller = new AbortController();
  if (still) stillInFlight = controller;
  else movingInFlight++;
  const seq = Number(new URLSearchParams(query).get('seq'));
  const started = performance.now();
  try {
    const response = await fetch('/api/frame?' + query, { signal: controller.signal });
    if (response.status === 204) return;  // superseded on the server: a newer frame follows
    if (!response.ok) {
      const message = (await response.text()).trim();
      window.pbsView.errors.push(message);
      $('status').textContent = message;
      if (still) stillStages = [];
      return;
    }
    const stats = JSON.parse(response.headers.get('X-Pbs-Stats') || '{}');
    const blob = await response.blob();
    if (seq < lastShown) return;  // a newer frame came first
    lastShown = seq;
    const url = URL.createObjectURL(blob);
    const image = $('frame');
    const old = image.src;
    image.src = url;
    await image.decode().catch(() => {});
    if (old.startsWith('blob:')) URL.revokeObjectURL(old);
    const total = performance.now() - started;
    showFrame({ query, still, label, stats, total, url });
  } catch (error) {
    if (error.name !== 'AbortError') {
      window.pbsView.errors.push(String(error));
      $('status').textContent = 'lost the server: ' + error;
    }
  } finally {
    if (still) {
      if (stillInFlight === controller) stillInFlight = null;
    } else {
      movingInFlight--;
    }
    next();
  }
}

function showFrame(frame) {
  const now = performance.now();
  if (!frame.still) {
    movingTimes.push(now);
    while (movingTimes.length && movingTimes[0] < now - 1000) movingTimes.shift();
    // Moving surfel frames are kept to 30 ms of rendering (with two in flight and the browser's own
    // work beside them on the same cores, about 20 a second on two): fewer surfels when slower, more
    // when fast.
    if (view.show !== 'exact' && view.show !== 'embree') {
      if (frame.stats.render_ms > 30) view.movingScale = Math.max(1 / 16, view.movingScale / 2);
      else if (frame.stats.render_ms < 12) view.movingScale = Math.min(1, view.movingScale * 2);
    }
  }
  window.pbsView.shown = { query: frame.query, still: frame.still, label: frame.label, stats: frame.stats, at: now };
  if (!frame.still) {
    window.pbsView.movingShown++;
    window.pbsView.deliveredMs.push(frame.total);
    window.pbsView.renderMs.push(frame.stats.render_ms);
    if (window.pbsView.deliveredMs.length > 1000) window.pbsView.deliveredMs.shift();
    if (window.pbsView.renderMs.length > 1000) window.pbsView.renderMs.shift();
  }
  window.pbsView.refined = frame.still && stillStages.length === 0;
  if (frame.still && frame.label === view.show) drawBoxes(frame.query);
  else if (!frame.still) clearBoxes();
  const label = frame.still ? frame.label + (stillStages.length ? ' (refining…)' : '') : 'moving';
  $('status').textContent = label;
  const s = frame.stats;
  const rows = [
    ['shown', label],
    ['drawn by', s.drawn_by + (s.samples > 1 ? ', ' + s.samples + ' samples' : '')],
    ['render', s.render_ms.toFixed(1) + ' ms'],
    ['encode', s.encode_ms.toFixed(1) + ' ms'],
    ['delivered', frame.total.toFixed(1) + ' ms'],
    ['frames a second (moving)', String(movingTimes.length)],
    ['triangles', s.triangles.toLocaleString()],
    ['surfels', s.surfels.toLocaleString()],
    ['nodes as geometry', s.nodes_geometry.toLocaleString()],
    ['nodes as surfels', s.nodes_surfels.toLocaleString()],
    ['bytes', s.bytes.toLocaleString()],
  ];
  if (s.flip !== undefined) rows.push(['FLIP (foreground)', s.flip.toFixed(4)]);
  const body = $('stats').tBodies[0];
  body.replaceChildren(...rows.map(([name, value]) => {
    const row = document.createElement('tr');
    row.append(Object.assign(document.createElement('td'), { textContent: name }),
               Object.assign(document.createElement('td'), { textContent: value }));
    return row;
  }));
}

// After a frame (or on a change): the camera's latest state if it moved, else the next still stage once
// no frame is in flight.
function next() {
  if (movePending) {
    if (movingInFlight >= kMovingInFlight) return;
    movePending = false;
    send(movingQuery(), false, 'moving');
  } else if (stillStages.length && !movingInFlight && !stillInFlight) {
    const stage = stillStages.shift();
    send(stage.query, true, stage.label);
  }
}

function changed() {
  window.pbsView.refined = false;
  stillStages = [];
  movePending = true;
  if (stillInFlight) stillInFlight.abort();
  clearTimeout(stillTimer);
  stillTimer = setTimeout(() => { stillStages = stillQueries(); next(); }, 150);
  next();
}

// The settings changed while still: refine again from the first stage.
function settingsChanged() {
  window.pbsView.refined = false;
  if (stillInFlight) stillInFlight.abort();
  clearTimeout(stillTimer);
  movePending = false;
  stillStages = stillQueries();
  next();
}

function clearBoxes() {
  const canvas = $('overlay');
  canvas.getContext('2d').clearRect(0, 0, canvas.width, canvas.height);
}

// The nodes the still frame draws, as their projected boxes' rectangles in the overlay, coloured by what
// they draw, with their projected size (the threshold's measure) where there is room.
async function drawBoxes(query) {
  const canvas = $('overlay');
  const [w, h] = frameSize();
  canvas.width = w;
  canvas.height = h;
  if (!view.boxes || !view.scene.surfels || view.show === 'prefix') return;
  const response = await fetch('/api/draws?' + query.replace(/(^|&)(show|format|samples|node|prefix)=[^&]*/g, ''));
  if (!response.ok) return;
  const nodes = await response.json();
  const context = canvas.getContext('2d');
  const colors = { geometry: '#3378f5', surfels: '#f58c1f', band: '#cc29cc' };
  context.font = '10px system-ui, sans-serif';
  for (const node of nodes) {
    const [x0, y0, x1, y1] = node.rect;
    context.strokeStyle = colors[node.kind];
    context.strokeRect(x0 + 0.5, y0 + 0.5, Math.max(0, x1 - x0 - 1), Math.max(0, y1 - y0 - 1));
    if (x1 - x0 > 30 && y1 - y0 > 14) {
      context.fillStyle = colors[node.kind];
      context.fillText(Math.round(node.size) + ' px', x0 + 2, y0 + 11);
    }
  }
}

// The prefix slider runs on a log scale from 1 surfel to the whole array.
function prefixFromSlider() {
  const length = view.node.array.surfels;
  return Math.max(1, Math.round(Math.pow(length, Number($('prefix').value))));
}

function drawRho(curve) {
  const svg = $('rho');
  const length = view.node.array.surfels;
  const x = (k) => 8 + 264 * Math.log(k) / Math.log(length);
  const y = (rho) => 110 - 100 * Math.max(0, Math.min(1, rho));
  const points = curve.k.map((k, i) => x(k).toFixed(1) + ',' + y(curve.rho[i]).toFixed(1)).join(' ');
  const marker = x(view.prefix).toFixed(1);
  svg.innerHTML =
    `<line x1="8" y1="110" x2="272" y2="110" stroke="#999"/><line x1="8" y1="10" x2="8" y2="110" stroke="#999"/>` +
    `<polyline points="${points}" fill="none" stroke="#333"/>` +
    `<line x1="${marker}" y1="10" x2="${marker}" y2="110" stroke="#f58c1f"/>` +
    `<text x="12" y="20" font-size="10">ρ(k), min ${curve.rho_min.toFixed(3)}, mean ${curve.rho_mean.toFixed(3)}</text>` +
    `<text x="12" y="106" font-size="9">k = 1</text><text x="236" y="106" font-size="9">${length}</text>`;
  view.rhoCurve = curve;
}

async function pick(x, y) {
  const query = frameQuery({ x, y }).replace(/(^|&)(show|format|samples|node|prefix)=[^&]*/g, '');
  const response = await fetch('/api/pick?' + query);
  if (!response.ok) { $('status').textContent = (await response.text()).trim(); return; }
  const node = await response.json();
  if (!node) return;
  view.node = node;
  window.pbsView.node = node;
  $('node-panel').hidden = false;
  const facts = [node.path.join(' / ') || '(unnamed)', node.subtree_triangles.toLocaleString() + ' triangles below'];
  const prefixRadio = document.querySelector('input[name=show][value=prefix]');
  prefixRadio.disabled = !node.array;
  $('prefix').disabled = !node.array;
  $('rho').innerHTML = '';
  if (node.array) {
    facts.push(`array ${node.array.index}: ${node.array.surfels.toLocaleString()} surfels, coverage ` +
               node.array.coverage.toFixed(3));
    view.prefix = node.array.surfels;
    $('prefix').value = 1;
    $('prefix-value').textContent = view.prefix;
    fetch('/api/node/rho?node=' + node.node).then((r) => r.json()).then(drawRho);
  }
  $('node-facts').replaceChildren(...facts.map((fact) => Object.assign(document.createElement('div'), { textContent: fact })));
  $('node-views').src = '/api/node/views?node=' + node.node;
}

function orbitDirection(c) {
  const az = c.az * Math.PI / 180, el = Math.max(-89.9, Math.min(89.9, c.el)) * Math.PI / 180;
  return [Math.cos(el) * Math.cos(az), Math.sin(el), Math.cos(el) * Math.sin(az)];
}

function fly(forward, right, up) {
  const c = view.camera, r = view.scene.radius;
  const back = orbitDirection(c);
  const ahead = back.map((v) => -v);
  const side = [-ahead[2], 0, ahead[0]];
  const length = Math.hypot(side[0], side[2]) || 1;
  const step = 0.04 * c.dist * r;
  c.tx += step * (forward * ahead[0] + right * side[0] / length);
  c.ty += step * (forward * ahead[1] + up);
  c.tz += step * (forward * ahead[2] + right * side[2] / length);
  changed();
}

function resetCamera() {
  const s = view.scene;
  view.camera = { tx: s.center[0], ty: s.center[1], tz: s.center[2], az: s.orbit[0], el: s.orbit[1], dist: s.orbit[2] };
}

function goToPathFrame() {
  const stops = view.scene.paths[$('path').value];
  view.camera = Object.assign({}, stops[Number($('path-frame').value) % stops.length]);
  changed();
}

function bindControls() {
  const stage = $('stage');
  let drag = null;
  stage.addEventListener('pointerdown', (e) => {
    drag = { x: e.clientX, y: e.clientY, startX: e.clientX, startY: e.clientY };
    stage.setPointerCapture(e.pointerId);
    stage.focus();
  });
  stage.addEventListener('pointermove', (e) => {
    if (!drag) return;
    const c = view.camera;
    c.az += (e.clientX - drag.x) * 0.4;
    c.el = Math.max(-89, Math.min(89, c.el + (e.clientY - drag.y) * 0.4));
    drag = { x: e.clientX, y: e.clientY, startX: drag.startX, startY: drag.startY };
    if (Math.abs(e.clientX - drag.startX) + Math.abs(e.clientY - drag.startY) >= 3) changed();
  });
  stage.addEventListener('pointerup', (e) => {
    // A click (no drag): the node under it.
    if (drag && Math.abs(e.clientX - drag.startX) + Math.abs(e.clientY - drag.startY) < 3) {
      const box = $('frame').getBoundingClientRect();
      const [w, h] = frameSize();
      const x = Math.floor(e.clientX - box.left), y = Math.floor(e.clientY - box.top);
      if (x >= 0 && y >= 0 && x < w && y < h && view.scene.surfels) pick(x, y);
    }
    drag = null;
  });
  stage.addEventListener('wheel', (e) => {
    e.preventDefault();
    const c = view.camera;
    c.dist = Math.max(1e-4, Math.min(1e4, c.dist * Math.exp(e.deltaY * 0.001)));
    changed();
  }, { passive: false });
  document.addEventListener('keydown', (e) => {
    if (e.target.tagName === 'INPUT' || e.target.tagName === 'SELECT') return;
    const moves = { w: [1, 0, 0], s: [-1, 0, 0], a: [0, -1, 0], d: [0, 1, 0], q: [0, 0, -1], e: [0, 0, 1] };
    const key = e.key.toLowerCase();
    if (moves[key]) fly(...moves[key]);
    else if (key === 'r') { resetCamera(); changed(); }
  });

  for (const input of document.querySelectorAll('input[name=show]')) {
    input.checked = input.value === view.show;
    input.disabled = input.value === 'surfels' && !view.scene.surfels;
    input.addEventListener('change', () => { view.show = input.value; settingsChanged(); });
  }
  $('boxes').checked = view.boxes;
  $('boxes').addEventListener('change', () => { view.boxes = $('boxes').checked; settingsChanged(); });
  $('node-close').addEventListener('click', () => {
    $('node-panel').hidden = true;
    if (view.show === 'prefix') { view.show = 'surfels'; document.querySelector('input[value=surfels]').checked = true; }
    document.querySelector('input[name=show][value=prefix]').disabled = true;
    view.node = null;
    settingsChanged();
  });
  $('prefix').addEventListener('input', () => {
    view.prefix = prefixFromSlider();
    $('prefix-value').textContent = view.prefix;
    if (view.rhoCurve) drawRho(view.rhoCurve);
    view.show = 'prefix';
    document.querySelector('input[name=show][value=prefix]').checked = true;
    settingsChanged();
  });
  $('node-look').addEventListener('click', () => {
    const node = view.node;
    if (!node || !node.center) return;
    Object.assign(view.camera, { tx: node.center[0], ty: node.center[1], tz: node.center[2],
                                 dist: Math.max(1e-4, 2.5 * node.radius / view.scene.radius) });
    changed();
  });
  $('refine').checked = view.refine;
  $('refine').addEventListener('change', () => { view.refine = $('refine').checked; settingsChanged(); });

  // Sliders on a log2 scale where the values span orders of magnitude.
  const logSlider = (id, key) => {
    const input = $(id);
    input.value = Math.log2(view.lod[key]);
    const update = () => { $(id + '-value').textContent = +view.lod[key].toPrecision(3); };
    update();
    input.addEventListener('input', () => { view.lod[key] = 2 ** Number(input.value); update(); settingsChanged(); });
  };
  logSlider('threshold', 'threshold');
  logSlider('overdraw', 'overdraw');
  $('splat').value = view.lod.splat;
  const point = $('point');
  point.value = view.lod.point;
  const pointState = () => {
    point.disabled = view.lod.splat !== 'nearest';
    $('point-value').textContent = view.lod.point > 0 ? view.lod.point : 'from the prefix';
  };
  pointState();
  $('splat').addEventListener('change', () => {
    view.lod.splat = $('splat').value;
    if (view.lod.splat !== 'nearest') { view.lod.point = 0; point.value = 0; }
    pointState();
    settingsChanged();
  });
  point.addEventListener('input', () => { view.lod.point = Number(point.value); pointState(); settingsChanged(); });
  const budgetChanged = () => {
    view.budgetKind = $('budget-kind').value;
    view.budget = Math.max(0, Number($('budget').value) || 0);
    settingsChanged();
  };
  $('budget-kind').addEventListener('change', budgetChanged);
  $('budget').addEventListener('change', budgetChanged);

  $('path').addEventListener('change', goToPathFrame);
  $('path-frame').addEventListener('input', goToPathFrame);
  let playing = 0;
  $('play').addEventListener('click', () => {
    if (playing) { clearInterval(playing); playing = 0; $('play').textContent = 'play'; return; }
    $('play').textContent = 'stop';
    playing = setInterval(() => {
      const frame = $('path-frame');
      frame.value = (Number(frame.value) + 1) % (Number(frame.max) + 1);
      goToPathFrame();
    }, 100);
  });
  if (![...$('size').options].some((option) => option.value === view.size))
    $('size').append(Object.assign(document.createElement('option'), { value: view.size, textContent: view.size }));
  $('size').value = view.size;
  $('size').addEventListener('change', () => { view.size = $('size').value; settingsChanged(); });
  window.addEventListener('resize', () => { if (view.size === 'fit') settingsChanged(); });
}

// Surfels made on the server in the background: started here, polled until written, then drawn.
async function makeSurfels() {
  $('make-surfels-button').disabled = true;
  let status = await (await fetch('/api/surfelize', { method: 'POST' })).json();
  while (status.state === 'running') {
    $('make-surfels-progress').textContent = `${(100 * status.fraction).toFixed(0)} % ` +
      `(${status.arrays_done} of ${status.arrays_total || '?'} arrays, ${status.seconds.toFixed(0)} s)`;
    await new Promise((resolve) => setTimeout(resolve, 500));
    status = await (await fetch('/api/surfelize')).json();
  }
  if (status.state !== 'done') {
    $('make-surfels-progress').textContent = 'failed: ' + (status.error || status.state);
    $('make-surfels-button').disabled = false;
    return;
  }
  $('make-surfels-progress').textContent = `made in ${status.seconds.toFixed(1)} s`;
  view.scene.surfels = true;
  window.pbsView.surfelsMade = true;
  for (const input of document.querySelectorAll('input[name=show][value=surfels]')) {
    input.disabled = false;
    input.checked = true;
  }
  view.show = 'surfels';
  settingsChanged();
}

async function start() {
  const response = await fetch('/api/scene');
  view.scene = await response.json();
  $('scene-name').textContent = view.scene.name + ', ' + view.scene.triangles.toLocaleString() + ' triangles';
  view.lod = Object.assign({}, view.scene.lod);
  if (!view.scene.surfels && view.show === 'surfels') view.show = 'embree';
  resetCamera();
  $('path-frame').max = view.scene.paths.orbit.length - 1;
  bindControls();
  if (!view.scene.surfels && view.scene.can_make_surfels) {
    $('make-surfels').hidden = false;
    $('make-surfels-button').addEventListener('click', makeSurfels);
  }
  window.pbsView.ready = true;
  settingsChanged();
}

// For tests and scripts: set the camera as the page's own controls would.
window.pbsView.setCamera = (camera) => { Object.assign(view.camera, camera); changed(); };
window.pbsView.camera = () => Object.assign({}, view.camera);
window.pbsView.shownPrefix = () => view.prefix;

start().catch((error) => { $('status').textContent = 'cannot reach the server: ' + error; });
