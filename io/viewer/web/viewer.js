// saccade view's page: polls /api/state five times a second and draws the camera view, the 3D
// view (three.js, when the build fetched it) and the strips. Camera frame: x right, y down,
// z forward, metres. docs/VIEWER.md describes what is drawn.

const POLL_MS = 200;
// The instance marker's colour: nothing else on the camera view is drawn in it (the test finds
// the marker by it).
const MARKER = '#ff00ff';
const TRUTH = '#33ff66';
const INSTANCE_COLOURS = ['#00e5ff', '#ffd400', '#ff7a1a', '#7dff4d', '#4d7dff', '#ff4d6a'];
const LEVEL_COLOURS = ['#3b6ea5', '#4f9fd1', '#8fd14f', '#e8e04a', '#ffb347', '#ff6f3c'];
const MODE_NAMES = ['TRACKING', 'SEARCHING', 'FULL_SCAN'];

const camera = document.getElementById('camera');
const ctx = camera.getContext('2d');
let state = null;
let image = null;        // the newest preview's decoded JPEG
let points = null;       // {xyz: Int16Array (mm), tags: Uint8Array}
let previewSeq = -1;     // the preview image and points above belong to this frame
let loading = false;
let view3d = null;       // set once three.js has loaded

// --- helpers -------------------------------------------------------------------------------

function rotate(q, p) {  // q = [w, x, y, z]
  const [w, x, y, z] = q;
  const [px, py, pz] = p;
  const ix = w * px + y * pz - z * py, iy = w * py + z * px - x * pz;
  const iz = w * pz + x * py - y * px, iw = -x * px - y * py - z * pz;
  return [ix * w + iw * -x + iy * -z - iz * -y, iy * w + iw * -y + iz * -x - ix * -z,
          iz * w + iw * -z + ix * -y - iy * -x];
}

function boxCorners(preview, level) {  // camera frame
  const out = [];
  for (let i = 0; i < 8; ++i) {
    const p = [0, 1, 2].map(a => ((i >> a) & 1) ? level.max[a] : level.min[a]);
    const r = rotate(preview.box_quat, p);
    out.push([r[0] + preview.box_trans[0], r[1] + preview.box_trans[1],
              r[2] + preview.box_trans[2]]);
  }
  return out;
}
const BOX_EDGES = [[0, 1], [2, 3], [4, 5], [6, 7], [0, 2], [1, 3], [4, 6], [5, 7],
                   [0, 4], [1, 5], [2, 6], [3, 7]];

// The camera view's pixel of a camera-frame point: the preview image is stretched over the
// canvas, its pixel centres at (u + 0.5) * scale on each axis. No image (a loose cloud): none.
function project(preview, p) {
  if (p[2] <= 0.05 || !(preview.width > 0) || !(preview.height > 0)) return null;
  const sx = camera.width / preview.width, sy = camera.height / preview.height;
  return [(preview.fx * p[0] / p[2] + preview.cx + 0.5) * sx,
          (preview.fy * p[1] / p[2] + preview.cy + 0.5) * sy];
}

function fmt(v, digits = 2) { return v === null || v === undefined ? '-' : Number(v).toFixed(digits); }

// --- the camera view -----------------------------------------------------------------------

function drawCamera() {
  ctx.fillStyle = '#000';
  ctx.fillRect(0, 0, camera.width, camera.height);
  const preview = state && state.preview;
  if (!preview) {
    ctx.fillStyle = '#9aa4ad';
    ctx.font = '16px sans-serif';
    ctx.fillText(state && state.connected
                     ? 'No preview: set preview.enabled: true in saccaded\'s config'
                     : 'No saccaded heard', 20, 40);
    return;
  }
  if (image && previewSeq === preview.seq) {
    ctx.imageSmoothingEnabled = false;
    ctx.drawImage(image, 0, 0, camera.width, camera.height);
  }
  // The fovea's boxes, outer level first.
  preview.levels.forEach((level, k) => {
    const c = boxCorners(preview, level);
    ctx.strokeStyle = LEVEL_COLOURS[Math.min(k, LEVEL_COLOURS.length - 1)];
    ctx.lineWidth = k === preview.levels.length - 1 ? 2 : 1;
    ctx.beginPath();
    for (const [a, b] of BOX_EDGES) {
      const pa = project(preview, c[a]), pb = project(preview, c[b]);
      if (!pa || !pb) continue;
      ctx.moveTo(pa[0], pa[1]);
      ctx.lineTo(pb[0], pb[1]);
    }
    ctx.stroke();
  });
  // The fixation trail (fixations in the camera frame only).
  if (state.fixation && state.fixation.frame === 'camera' && state.trail.length > 1) {
    ctx.strokeStyle = 'rgba(255, 160, 60, 0.8)';
    ctx.lineWidth = 1.5;
    ctx.beginPath();
    let first = true;
    for (const f of state.trail) {
      const p = project(preview, f);
      if (!p) continue;
      if (first) ctx.moveTo(p[0], p[1]); else ctx.lineTo(p[0], p[1]);
      first = false;
    }
    ctx.stroke();
  }
  // Each instance's model points at its pose.
  if (points && previewSeq === preview.seq) {
    for (let i = 0; i < points.tags.length; ++i) {
      const tag = points.tags[i];
      if (tag < 128) continue;
      const p = project(preview, [points.xyz[3 * i] / 1000, points.xyz[3 * i + 1] / 1000,
                                  points.xyz[3 * i + 2] / 1000]);
      if (!p) continue;
      ctx.fillStyle = INSTANCE_COLOURS[(tag - 128) % INSTANCE_COLOURS.length];
      ctx.fillRect(p[0] - 1, p[1] - 1, 2, 2);
    }
  }
  // Where the truth puts the target (recordings and the synthetic Kinect).
  if (preview.truth) {
    const t = project(preview, preview.truth);
    if (t) {
      ctx.strokeStyle = TRUTH;
      ctx.lineWidth = 2;
      ctx.strokeRect(t[0] - 16, t[1] - 16, 32, 32);
    }
  }
  // Each instance: a marker at its centroid, its id, state and confidence.
  ctx.font = '13px sans-serif';
  preview.instances.forEach(inst => {
    const p = project(preview, inst.centroid);
    if (!p) return;
    ctx.strokeStyle = MARKER;
    ctx.lineWidth = 2;
    ctx.beginPath();
    ctx.arc(p[0], p[1], 9, 0, 2 * Math.PI);
    ctx.moveTo(p[0] - 14, p[1]);
    ctx.lineTo(p[0] + 14, p[1]);
    ctx.moveTo(p[0], p[1] - 14);
    ctx.lineTo(p[0], p[1] + 14);
    ctx.stroke();
    const label = (inst.model_name || 'model') +
                  (inst.track_id !== undefined && inst.track_id >= 0 ? ' #' + inst.track_id : '') +
                  (inst.track_state ? ' ' + inst.track_state : '') +
                  (inst.confidence !== undefined && inst.confidence >= 0
                       ? ' ' + fmt(inst.confidence) : '');
    ctx.fillStyle = 'rgba(0, 0, 0, 0.6)';
    ctx.fillRect(p[0] + 18, p[1] - 26, ctx.measureText(label).width + 8, 18);
    ctx.fillStyle = '#ffffff';
    ctx.fillText(label, p[0] + 22, p[1] - 12);
  });
  // What attention is doing.
  if (state.fixation) {
    const text = state.fixation.mode + '  G ' + fmt(state.fixation.growth) + ' m  frame ' +
                 preview.seq;
    ctx.fillStyle = 'rgba(0, 0, 0, 0.6)';
    ctx.fillRect(6, 6, ctx.measureText(text).width + 10, 20);
    ctx.fillStyle = '#ffffff';
    ctx.fillText(text, 11, 21);
  }
}

// --- the strips ----------------------------------------------------------------------------

const STRIPS = [
  {key: 'fps', title: 'fps', unit: ''},
  {key: 'dropped', title: 'frames dropped / period', unit: ''},
  {key: 'recognize_ms', title: 'recognition p50', unit: ' ms'},
  {key: 'capture_to_publish_ms', title: 'capture to publish p50', unit: ' ms'},
  {key: 'growth_m', title: 'growth factor G', unit: ' m'},
  {key: 'mode', title: 'mode', unit: '', names: MODE_NAMES},
];
const stripCanvases = STRIPS.map(s => {
  const c = document.createElement('canvas');
  c.width = 210;
  c.height = 84;
  c.title = s.title + ' over the last minute';
  document.getElementById('strips').appendChild(c);
  return c;
});

function drawStrips() {
  STRIPS.forEach((strip, n) => {
    const c = stripCanvases[n], g = c.getContext('2d');
    g.fillStyle = '#0b0c0e';
    g.fillRect(0, 0, c.width, c.height);
    const samples = (state && state.history && state.history[strip.key]) || [];
    let lo = 0, hi = strip.names ? 2 : 1e-9;
    for (const [, v] of samples) hi = Math.max(hi, v), lo = Math.min(lo, v);
    const top = 22, bottom = c.height - 6, span = hi - lo || 1;
    const x = t => (t + 60) / 60 * (c.width - 8) + 4;
    const y = v => bottom - (v - lo) / span * (bottom - top);
    g.strokeStyle = '#2a2e33';
    g.beginPath();
    g.moveTo(4, bottom);
    g.lineTo(c.width - 4, bottom);
    g.stroke();
    g.strokeStyle = '#59b4ff';
    g.lineWidth = 1.5;
    g.beginPath();
    samples.forEach(([t, v], i) => {
      if (strip.names && i > 0) g.lineTo(x(t), y(samples[i - 1][1]));  // steps
      if (i === 0) g.moveTo(x(t), y(v)); else g.lineTo(x(t), y(v));
    });
    g.stroke();
    const last = samples.length ? samples[samples.length - 1][1] : null;
    const now = last === null ? '-' : strip.names ? strip.names[last] || last
                                                  : fmt(last, strip.key === 'fps' ? 1 : 2) + strip.unit;
    g.fillStyle = '#d8dde3';
    g.font = '12px sans-serif';
    g.fillText(strip.title + ': ' + now, 6, 15);
    g.fillStyle = '#6b747d';
    g.fillText(fmt(hi, 1), c.width - 34, 15);
  });
}

// --- the text beside -----------------------------------------------------------------------

function drawInfo() {
  const banner = document.getElementById('banner');
  if (!state) {
    banner.className = 'down';
    banner.textContent = 'The viewer itself does not answer (is saccade view still running?)';
  } else if (!state.connected) {
    banner.className = 'down';
    banner.textContent = 'No saccaded heard on ' + state.lcm_url + ' (channels ' +
                         state.channel_prefix + '_*)' +
                         (state.heard_s_ago >= 0 ? ' for ' + fmt(state.heard_s_ago, 0) + ' s'
                                                 : ' yet') +
                         ': is it running, on the same LCM network?';
  } else {
    banner.className = 'ok';
    const s = state.status;
    banner.textContent = 'saccaded: ' + (s ? s.source_state + ', ' + fmt(s.fps, 1) + ' fps, ' +
                                             s.frames_dropped + ' dropped' : 'heard') +
                         (state.rejected ? ', ' + state.rejected + ' malformed message(s)' : '');
  }
  const s = state && state.status;
  document.getElementById('status').textContent =
      s ? 'source ' + s.source + ' | processed ' + s.frames_processed + ' | up ' +
              fmt(s.uptime_s, 0) + ' s' : '';
  const body = document.querySelector('#instances tbody');
  body.textContent = '';
  for (const inst of (state && state.instances) || []) {
    const row = body.insertRow();
    for (const v of [inst.model_name, inst.track_id, inst.track_state, fmt(inst.confidence),
                     inst.centroid.map(c => fmt(c, 3)).join(', ')])
      row.insertCell().textContent = v;
  }
  document.getElementById('reason').textContent =
      state && state.fixation ? 'fixation: ' + state.fixation.reason : '';
}

// --- the 3D view (three.js) ----------------------------------------------------------------

async function start3d() {
  const host = document.getElementById('scene');
  let THREE, OrbitControls;
  try {
    THREE = await import('three');
    ({OrbitControls} = await import('/vendor/OrbitControls.js'));
  } catch (e) {
    host.textContent = 'No 3D view: three.js is not installed (the build fetches it with npm).';
    return;
  }
  const renderer = new THREE.WebGLRenderer({antialias: true, preserveDrawingBuffer: true});
  renderer.setSize(640, 480);
  renderer.setClearColor(0x0b0c0e);
  host.appendChild(renderer.domElement);
  const scene = new THREE.Scene();
  const eye = new THREE.PerspectiveCamera(50, 640 / 480, 0.01, 50);
  eye.up.set(0, -1, 0);  // the camera frame's y points down
  eye.position.set(0.9, -0.8, -0.6);
  const controls = new OrbitControls(eye, renderer.domElement);
  controls.target.set(0, 0, 1);
  controls.update();
  scene.add(new THREE.AxesHelper(0.2));  // the camera at the origin
  const cloud = new THREE.Points(new THREE.BufferGeometry(),
                                 new THREE.PointsMaterial({size: 0.008, vertexColors: true}));
  scene.add(cloud);
  const boxes = new THREE.Group();
  scene.add(boxes);
  let aimed = false;
  const levelColours = LEVEL_COLOURS.map(c => new THREE.Color(c));
  const instanceColours = INSTANCE_COLOURS.map(c => new THREE.Color(c));
  view3d = {
    update(preview, pts) {
      const n = pts.tags.length, position = new Float32Array(3 * n), colour = new Float32Array(3 * n);
      const levels = preview.levels.length;
      for (let i = 0; i < n; ++i) {
        for (let a = 0; a < 3; ++a) position[3 * i + a] = pts.xyz[3 * i + a] / 1000;
        const tag = pts.tags[i];
        // Levels in shades of grey, coarse dark; instances in their colour.
        const c = tag >= 128 ? instanceColours[(tag - 128) % instanceColours.length]
                             : new THREE.Color().setScalar(0.3 + 0.7 * (tag + 1) / Math.max(levels, 1));
        colour.set([c.r, c.g, c.b], 3 * i);
      }
      cloud.geometry.dispose();
      cloud.geometry = new THREE.BufferGeometry();
      cloud.geometry.setAttribute('position', new THREE.BufferAttribute(position, 3));
      cloud.geometry.setAttribute('color', new THREE.BufferAttribute(colour, 3));
      boxes.clear();
      preview.levels.forEach((level, k) => {
        const c = boxCorners(preview, level), line = [];
        for (const [a, b] of BOX_EDGES) line.push(...c[a], ...c[b]);
        const g = new THREE.BufferGeometry();
        g.setAttribute('position', new THREE.BufferAttribute(new Float32Array(line), 3));
        boxes.add(new THREE.LineSegments(
            g, new THREE.LineBasicMaterial({color: levelColours[Math.min(k, levelColours.length - 1)]})));
      });
      if (!aimed) {  // look at the fovea once; the user orbits from there
        controls.target.set(...preview.fovea);
        eye.position.set(preview.fovea[0] + 0.9, preview.fovea[1] - 0.8, preview.fovea[2] - 1.2);
        controls.update();
        aimed = true;
      }
    },
  };
  const render = () => {
    renderer.render(scene, eye);
    requestAnimationFrame(render);
  };
  render();
  if (state && state.preview && points) view3d.update(state.preview, points);
}

// --- polling -------------------------------------------------------------------------------

async function loadPreview(preview) {
  loading = true;
  try {
    const [img, bin] = await Promise.all([
      fetch('/api/preview.jpg?seq=' + preview.seq).then(r => r.ok ? r.blob() : null),
      fetch('/api/points.bin?seq=' + preview.seq).then(r => r.ok ? r.arrayBuffer() : null),
    ]);
    if (bin) {  // the image may be missing (a frame that is not an image): points alone
      image = img ? await createImageBitmap(img) : null;
      const n = preview.num_points, view = new DataView(bin);
      const xyz = new Int16Array(3 * n);
      for (let i = 0; i < 3 * n; ++i) xyz[i] = view.getInt16(2 * i, true);
      points = {xyz, tags: new Uint8Array(bin, 6 * n, n)};
      previewSeq = preview.seq;
      if (view3d) view3d.update(preview, points);
    }
  } catch (e) {
    // A newer preview replaced this one meanwhile: the next poll fetches that.
  } finally {
    loading = false;
  }
}

async function poll() {
  try {
    const r = await fetch('/api/state', {cache: 'no-store'});
    state = await r.json();
  } catch (e) {
    state = null;
  }
  if (state && state.preview && state.preview.seq !== previewSeq && !loading)
    await loadPreview(state.preview);
  drawCamera();
  drawStrips();
  drawInfo();
  // Tests read the frame drawn from here (document.body.dataset).
  document.body.dataset.previewSeq = previewSeq;
  setTimeout(poll, POLL_MS);
}

poll();
start3d();
