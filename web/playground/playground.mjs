// The par2d playground: the examples in a menu, the scene's JSON in an editor (the validator's
// message shown under it and its line marked), lights and occluders dragged on the canvas with
// only the dirty rectangles redrawn, and the frame time. The page's state is exposed as
// window.par2dPlayground for the headless browser test (web/test/playground.mjs).
import { loadPar2d, Par2dError, translateShape } from '../par2d.mjs';

const canvas = document.getElementById('frame');
const ctx = canvas.getContext('2d');
const editor = document.getElementById('editor');
const gutter = document.getElementById('gutter');
const errorBox = document.getElementById('error');
const statusLine = document.getElementById('status');
const menu = document.getElementById('examples');

const par2d = await loadPar2d();
const renderer = par2d.createRenderer();

// What the test reads: frames drawn, what they uploaded, the last error.
const state = {
  ready: false,
  example: null,
  frames: 0,
  lastFrameMs: 0,
  lastDirtyRects: [],
  dirtyPixelsDrawn: 0, // pixels uploaded to the canvas by the last frame
  fullUploads: 0, // frames that uploaded the whole canvas (a new scene or size)
  error: '',
  errorLine: 0,
  isa: par2d.isa,
  par2d,
  renderer,
  /** The canvas's RGBA bytes as drawn. */
  canvasPixels: () => ctx.getImageData(0, 0, canvas.width, canvas.height).data,
  scene: null, // the scene as shown (drags move its shapes)
};
window.par2dPlayground = state;

let imageData = null;
let sceneName = 'scene.json';
let files = {};

function setError(message) {
  state.error = message;
  errorBox.textContent = message;
  errorBox.classList.toggle('shown', message !== '');
  state.errorLine = message ? errorLine(editor.value, message) : 0;
  drawGutter();
}

function drawGutter() {
  const lines = editor.value.split('\n').length;
  gutter.replaceChildren();
  for (let i = 1; i <= lines; ++i) {
    const span = document.createElement('span');
    span.textContent = `${i}\n`;
    if (i === state.errorLine) span.className = 'bad';
    gutter.append(span);
  }
  gutter.scrollTop = editor.scrollTop;
}

// Loads the editor's text as the scene. A refused one leaves the last good frame on the canvas.
function loadText() {
  try {
    renderer.loadScene(editor.value, { name: sceneName, files });
  } catch (e) {
    if (!(e instanceof Par2dError)) throw e;
    setError(e.message);
    return false;
  }
  state.scene = JSON.parse(editor.value);
  setError('');
  draw(true);
  return true;
}

// Renders and uploads: the whole canvas for a new scene, else only the dirty rectangles.
function draw(full = false) {
  const frame = renderer.render({ full });
  if (canvas.width !== frame.width || canvas.height !== frame.height || !imageData) {
    canvas.width = frame.width;
    canvas.height = frame.height;
    full = true;
  }
  imageData = new ImageData(frame.pixels, frame.width, frame.height);
  let uploaded = 0;
  if (full) {
    ctx.putImageData(imageData, 0, 0);
    uploaded = frame.width * frame.height;
    ++state.fullUploads;
  } else {
    for (const r of frame.dirtyRects) {
      ctx.putImageData(imageData, 0, 0, r.x0, r.y0, r.x1 - r.x0, r.y1 - r.y0);
      uploaded += (r.x1 - r.x0) * (r.y1 - r.y0);
    }
  }
  ++state.frames;
  state.lastFrameMs = frame.ms;
  state.lastDirtyRects = frame.dirtyRects;
  state.dirtyPixelsDrawn = uploaded;
  statusLine.textContent =
    `${frame.width}×${frame.height}  frame ${frame.ms.toFixed(1)} ms  ` +
    `${frame.dirtyRects.length} dirty rect${frame.dirtyRects.length === 1 ? '' : 's'}, ${uploaded} px  [${renderer.isa}]`;
}

async function openExample(name) {
  const base = new URL(`../examples/${name}`, import.meta.url);
  const text = await (await fetch(base)).text();
  const scene = JSON.parse(text);
  files = {};
  if (typeof scene.normal_map === 'string') {
    files[scene.normal_map] = new Uint8Array(await (await fetch(new URL(scene.normal_map, base))).arrayBuffer());
  }
  sceneName = name;
  state.example = name;
  editor.value = text;
  loadText();
}

// ---- Dragging: the light or occluder under the pointer, moved in world units ----

function worldPerPixel() {
  const s = state.scene;
  const view = s.view ?? [0, 0, s.width, s.height];
  return { view, sx: (view[2] - view[0]) / s.width, sy: (view[3] - view[1]) / s.height };
}

function canvasPoint(event) {
  const rect = canvas.getBoundingClientRect();
  return {
    x: ((event.clientX - rect.left) * canvas.width) / rect.width,
    y: ((event.clientY - rect.top) * canvas.height) / rect.height,
  };
}

function toWorld(p) {
  const { view, sx, sy } = worldPerPixel();
  return [view[0] + p.x * sx, view[1] + p.y * sy];
}

function shapeBounds(shape) {
  let points;
  if (shape.circle) {
    const [x, y] = shape.circle.center;
    const r = shape.circle.radius;
    points = [[x - r, y - r], [x + r, y + r]];
  } else points = shape.segment ?? shape.polygon;
  const xs = points.map((p) => p[0]);
  const ys = points.map((p) => p[1]);
  return [Math.min(...xs), Math.min(...ys), Math.max(...xs), Math.max(...ys)];
}

// The light nearest the point within its bounds grown by 8 pixels, else such an occluder.
function pick([x, y]) {
  const { sx } = worldPerPixel();
  const slack = 8 * Math.abs(sx);
  const hit = (list) => {
    let best = -1;
    let bestDistance = Infinity;
    (list ?? []).forEach((item, i) => {
      const [x0, y0, x1, y1] = shapeBounds(item);
      if (x < x0 - slack || x > x1 + slack || y < y0 - slack || y > y1 + slack) return;
      const d = Math.hypot(x - (x0 + x1) / 2, y - (y0 + y1) / 2);
      if (d < bestDistance) [best, bestDistance] = [i, d];
    });
    return best;
  };
  const light = hit(state.scene.lights);
  if (light >= 0) return { kind: 'lights', index: light };
  const occluder = hit(state.scene.occluders);
  return occluder >= 0 ? { kind: 'occluders', index: occluder } : null;
}

function shapeOf(item) {
  if (item.circle) return { circle: item.circle };
  if (item.segment) return { segment: item.segment };
  return item.holes ? { polygon: item.polygon, holes: item.holes } : { polygon: item.polygon };
}

let drag = null;
canvas.addEventListener('pointerdown', (event) => {
  if (!state.scene || state.error) return;
  const at = toWorld(canvasPoint(event));
  const target = pick(at);
  if (!target) return;
  // The renderer's handles follow the scene file's order (lights, then occluders).
  const handles = target.kind === 'lights' ? renderer.lights() : renderer.occluders();
  drag = { ...target, handle: handles[target.index], last: at };
  canvas.setPointerCapture(event.pointerId);
  canvas.classList.add('dragging');
});
canvas.addEventListener('pointermove', (event) => {
  if (!drag) return;
  const at = toWorld(canvasPoint(event));
  const dx = at[0] - drag.last[0];
  const dy = at[1] - drag.last[1];
  if (dx === 0 && dy === 0) return;
  drag.last = at;
  const item = state.scene[drag.kind][drag.index];
  const moved = translateShape(shapeOf(item), dx, dy);
  Object.assign(item, moved);
  if (drag.kind === 'lights') renderer.updateLight(drag.handle, { shape: moved });
  else renderer.updateOccluder(drag.handle, moved);
  draw();
});
const endDrag = () => {
  if (!drag) return;
  drag = null;
  canvas.classList.remove('dragging');
  editor.value = formatScene(state.scene);
  drawGutter();
};
canvas.addEventListener('pointerup', endDrag);
canvas.addEventListener('pointercancel', endDrag);

// The scene as JSON with one line per light, occluder or other list entry, as the examples are written.
function formatScene(scene) {
  const lines = Object.entries(scene).map(([key, value]) => {
    if (Array.isArray(value) && value.some((v) => v && typeof v === 'object' && !Array.isArray(v))) {
      return `  ${JSON.stringify(key)}: [\n${value.map((v) => `    ${JSON.stringify(v)}`).join(',\n')}\n  ]`;
    }
    return `  ${JSON.stringify(key)}: ${JSON.stringify(value)}`;
  });
  return `{\n${lines.join(',\n')}\n}\n`;
}

// ---- Where an error is: "line L" from a JSON syntax error, or the place the validator names ----

function errorLine(text, message) {
  const syntax = /line (\d+), column \d+/.exec(message);
  if (syntax) return Number(syntax[1]);
  const place = /^[^:]+: ([A-Za-z_][\w.[\]]*): /.exec(message);
  if (!place) return 0;
  const offset = locate(text, place[1]);
  return offset < 0 ? 0 : text.slice(0, offset).split('\n').length;
}

// The text offset of the value at a validator place ("lights[1].color[2]"): the deepest part
// of it that the text has (an unknown key's place names its object).
function locate(text, place) {
  const path = [];
  for (const m of place.matchAll(/([A-Za-z_]\w*)|\[(\d+)\]/g)) path.push(m[1] ?? Number(m[2]));
  let i = 0;
  const ws = () => {
    while (i < text.length && /\s/.test(text[i])) ++i;
  };
  let best = -1;
  // Walks one value starting at i; `depth` parts of `path` matched so far.
  const value = (depth) => {
    ws();
    if (depth > 0) best = i;
    const c = text[i];
    if (c === '{') {
      ++i;
      for (;;) {
        ws();
        if (text[i] === '}') return ++i;
        const keyStart = i;
        const key = JSON.parse(text.slice(keyStart, (i = stringEnd(i))));
        ws();
        ++i; // ':'
        if (depth < path.length && path[depth] === key) {
          value(depth + 1);
          if (depth + 1 === path.length) best = keyStart;
        } else skip();
        ws();
        if (text[i] === ',') ++i;
      }
    } else if (c === '[') {
      ++i;
      for (let k = 0; ; ++k) {
        ws();
        if (text[i] === ']') return ++i;
        if (depth < path.length && path[depth] === k) value(depth + 1);
        else skip();
        ws();
        if (text[i] === ',') ++i;
      }
    }
    skip();
    return i;
  };
  const stringEnd = (start) => {
    let j = start + 1;
    while (j < text.length && text[j] !== '"') j += text[j] === '\\' ? 2 : 1;
    return j + 1;
  };
  const skip = () => {
    ws();
    const c = text[i];
    if (c === '"') i = stringEnd(i);
    else if (c === '{' || c === '[') {
      let level = 0;
      for (; i < text.length; ++i) {
        if (text[i] === '"') i = stringEnd(i) - 1;
        else if (text[i] === '{' || text[i] === '[') ++level;
        else if ((text[i] === '}' || text[i] === ']') && --level === 0) return ++i;
      }
    } else while (i < text.length && !/[,\]}\s]/.test(text[i])) ++i;
    return i;
  };
  try {
    value(0);
  } catch {
    return best;
  }
  return best;
}

// ---- Wiring ----

let pending = 0;
editor.addEventListener('input', () => {
  drawGutter();
  clearTimeout(pending);
  pending = setTimeout(loadText, 250);
});
editor.addEventListener('scroll', () => {
  gutter.scrollTop = editor.scrollTop;
});
menu.addEventListener('change', () => openExample(menu.value));

const examples = await (await fetch(new URL('../examples/index.json', import.meta.url))).json();
for (const name of examples) menu.append(new Option(name.replace(/\.json$/, ''), name));
const wanted = new URLSearchParams(location.search).get('example');
menu.value = examples.includes(wanted) ? wanted : examples.includes('paper.json') ? 'paper.json' : examples[0];
await openExample(menu.value);
state.loadText = loadText;
state.ready = true;
