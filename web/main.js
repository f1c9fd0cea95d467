// The page's glue to microray.wasm (built by build.sh from src/exports.rs): the scene's text
// goes into the module's memory, the pixels come out of it, one frame of the orbit a tick.
//
// Query string: scene=URL (default scene.toml), frames=N (36), orbit=DEGREES (360), frame=K
// (where to start), still (render frame K once, then set body[data-rendered] = "1"; a
// failure sets body[data-error]).

const params = new URLSearchParams(location.search);
const still = params.has('still');
const el = (id) => document.getElementById(id);
const canvas = el('view');
const status = el('status');
const errorBox = el('error');
const textarea = el('scene');
const framesInput = el('frames');
const orbitInput = el('orbit');
const pauseButton = el('pause');

// An 8-bit sRGB canvas: putImageData and getImageData then pass the bytes through unchanged,
// which the pixel test relies on.
const ctx = canvas.getContext('2d', { colorSpace: 'srgb', willReadFrequently: true });

const number = (name, fallback) => {
  const v = Number(params.get(name));
  return params.has(name) && Number.isFinite(v) ? v : fallback;
};
let frames = Math.max(1, Math.floor(number('frames', 36)));
let degrees = number('orbit', 360);
let frame = Math.max(0, Math.floor(number('frame', 0))) % frames;
framesInput.value = frames;
orbitInput.value = degrees;

const times = []; // the last few frames' render times, in ms
const KEPT = 15;
let drawn = 0; // frames drawn since the page loaded
let playing = !still;
let wasm; // the module's exports, once instantiated
let running = false; // whether a scene has loaded and frames are being drawn
let raf = 0; // the pending animation frame, cancelled on pause so that one loop runs

function fail(message) {
  errorBox.textContent = message;
  document.body.dataset.error = message;
}

function ok(response) {
  if (!response.ok) throw new Error(`${response.url}: ${response.status} ${response.statusText}`);
  return response;
}

function bytes(ptr, len) {
  // Fresh on every read: the module's memory may have grown (a new buffer) in the last call.
  return new Uint8Array(wasm.memory.buffer, ptr, len);
}

function lastError() {
  return new TextDecoder().decode(bytes(wasm.error_ptr(), wasm.error_len()));
}

// Loads a scene; null on success (it replaces the scene), else the message (the old one stays).
function load(text) {
  const utf8 = new TextEncoder().encode(text);
  bytes(wasm.text_buffer(utf8.length), utf8.length).set(utf8);
  return wasm.load(utf8.length) === 0 ? null : lastError();
}

// Renders frame k and draws it; null on success, else the message.
function draw(k) {
  const t0 = performance.now();
  const ptr = wasm.render(k, frames, degrees);
  const ms = performance.now() - t0;
  if (ptr === 0) return lastError();
  const width = wasm.width();
  const height = wasm.height();
  if (canvas.width !== width || canvas.height !== height) {
    canvas.width = width;
    canvas.height = height;
  }
  const rgba = new Uint8ClampedArray(wasm.memory.buffer, ptr, width * height * 4);
  ctx.putImageData(new ImageData(rgba, width, height), 0, 0);
  times.push(ms);
  if (times.length > KEPT) times.shift();
  const median = [...times].sort((a, b) => a - b)[times.length >> 1];
  // For the test: the median, and how many frames have been drawn.
  document.body.dataset.medianMs = median.toFixed(2);
  document.body.dataset.drawn = String(++drawn);
  status.textContent =
    `${width}×${height}, frame ${k} of ${frames}: ` +
    `${median.toFixed(1)} ms a frame (median of the last ${times.length})`;
  return null;
}

function tick() {
  if (!playing) return;
  const error = draw(frame);
  // A frame that fails (a keyframe's camera looking along `up`) is skipped, and said why.
  if (error) errorBox.textContent = error;
  frame = (frame + 1) % frames;
  raf = requestAnimationFrame(tick);
}

// Starts drawing once the first scene has loaded.
function start() {
  running = true;
  if (still) {
    const error = draw(frame);
    if (error) fail(error);
    else document.body.dataset.rendered = '1';
    pauseButton.textContent = 'Play';
  } else {
    raf = requestAnimationFrame(tick);
  }
}

// Checked as the user types, a moment after the last key: a valid scene replaces the one
// turning, an invalid one leaves it and shows why.
let pending;
textarea.addEventListener('input', () => {
  clearTimeout(pending);
  pending = setTimeout(() => {
    if (!wasm) return;
    const error = load(textarea.value);
    errorBox.textContent = error ?? '';
    if (error) return;
    delete document.body.dataset.error;
    times.length = 0;
    if (!running) start();
    else if (!playing) draw(frame);
  }, 300);
});

pauseButton.addEventListener('click', () => {
  if (!running) return;
  playing = !playing;
  pauseButton.textContent = playing ? 'Pause' : 'Play';
  cancelAnimationFrame(raf);
  if (playing) raf = requestAnimationFrame(tick);
});

framesInput.addEventListener('change', () => {
  const n = Math.floor(Number(framesInput.value));
  if (n >= 1) {
    frames = n;
    frame %= frames;
    if (running && !playing) draw(frame);
  }
});

orbitInput.addEventListener('change', () => {
  const d = Number(orbitInput.value);
  if (Number.isFinite(d)) {
    degrees = d;
    if (running && !playing) draw(frame);
  }
});

try {
  const [module, text] = await Promise.all([
    fetch('microray.wasm').then(ok).then((r) => r.arrayBuffer()),
    fetch(params.get('scene') ?? 'scene.toml').then(ok).then((r) => r.text()),
  ]);
  // instantiate, not instantiateStreaming: any server's content type for .wasm will do.
  wasm = (await WebAssembly.instantiate(module, {})).instance.exports;
  textarea.value = text;
  const error = load(text);
  if (error) {
    // Shown like an edit's error: the page starts once the text is fixed.
    status.textContent = 'no scene yet';
    fail(error);
  } else {
    start();
  }
} catch (e) {
  status.textContent = 'not running';
  fail(String(e.message ?? e));
}
