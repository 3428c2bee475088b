// The playground in headless Chromium, driven over the DevTools protocol (a WebSocket client
// of its own, cdp_socket.mjs: no npm package): the page loads and renders an example; its
// canvas holds the native SSE4.2 kernel's bytes and its frame is within docs/contract.md
// section 5 of the native scalar reference; a drag moves a light and redraws only dirty rectangles, after which the canvas
// equals a fresh render of the moved scene; a refused scene shows the validator's message,
// the native CLI's for the same text, with its line marked; the menu opens a normal-mapped
// example.
//
// Usage: node web/test/playground.mjs SITE NATIVE_BUILD [--screenshot PNG]
import { execFileSync, spawn, spawnSync } from 'node:child_process';
import fs from 'node:fs';
import http from 'node:http';
import os from 'node:os';
import path from 'node:path';
import zlib from 'node:zlib';
import { fileURLToPath } from 'node:url';
import { openSocket } from './cdp_socket.mjs';
import { emissionMax, writePfm } from './scene_tools.mjs';

const args = process.argv.slice(2);
const shotAt = args.indexOf('--screenshot');
const screenshot = shotAt >= 0 ? args.splice(shotAt, 2)[1] : null;
const [site, native] = args;
if (!site || !native) {
  console.error('usage: node web/test/playground.mjs SITE NATIVE_BUILD [--screenshot PNG]');
  process.exit(2);
}
const repo = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..');
const cli = path.resolve(native, 'tools/par2d');
const EXAMPLE = 'lighting_range.json';
const work = fs.mkdtempSync(path.join(os.tmpdir(), 'par2d-playground-'));
let failures = 0;
const check = (ok, message) => {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${message}`);
  if (!ok) ++failures;
};

// ---- A static server for the site (ES modules need http, not file://) ----
const types = { '.html': 'text/html', '.mjs': 'text/javascript', '.json': 'application/json', '.png': 'image/png', '.ts': 'text/plain' };
const server = http.createServer((req, res) => {
  const file = path.join(path.resolve(site), decodeURIComponent(new URL(req.url, 'http://x').pathname));
  if (!file.startsWith(path.resolve(site)) || !fs.existsSync(file) || fs.statSync(file).isDirectory()) {
    res.writeHead(404).end();
    return;
  }
  res.writeHead(200, { 'content-type': types[path.extname(file)] ?? 'application/octet-stream' });
  fs.createReadStream(file).pipe(res);
});
await new Promise((resolve) => server.listen(0, '127.0.0.1', resolve));
const origin = `http://127.0.0.1:${server.address().port}`;

// ---- Chromium and a DevTools connection to its page ----
const browser = spawn('chromium', [
  '--headless=new', '--no-sandbox', '--disable-gpu', '--no-first-run', '--no-default-browser-check',
  '--remote-debugging-port=0', `--user-data-dir=${path.join(work, 'profile')}`, '--window-size=1400,900', 'about:blank',
], { stdio: ['ignore', 'ignore', 'pipe'] });
const finish = async (code) => {
  const exited = new Promise((resolve) => browser.once('exit', resolve));
  browser.kill();
  await exited;
  server.close();
  // Chromium's helper processes may still be writing its profile for a moment after it exits.
  fs.rmSync(work, { recursive: true, force: true, maxRetries: 20, retryDelay: 100 });
  process.exit(code);
};
const timer = setTimeout(() => {
  console.log('FAIL timed out');
  finish(1);
}, 120000);
timer.unref();
const devtools = await new Promise((resolve, reject) => {
  let text = '';
  browser.stderr.on('data', (chunk) => {
    text += chunk;
    const m = /DevTools listening on (ws:\/\/\S+)/.exec(text);
    if (m) resolve(m[1]);
  });
  browser.on('exit', (code) => reject(new Error(`chromium exited (${code}): ${text}`)));
});
const port = new URL(devtools).port;
const targets = await (await fetch(`http://127.0.0.1:${port}/json/list`)).json();
const page = targets.find((t) => t.type === 'page');
const socket = await openSocket(page.webSocketDebuggerUrl);
let nextId = 0;
const pending = new Map();
const consoleLines = [];
socket.onmessage = (event) => {
  const msg = JSON.parse(event.data);
  if (msg.id && pending.has(msg.id)) {
    pending.get(msg.id)(msg);
    pending.delete(msg.id);
  } else if (msg.method === 'Runtime.exceptionThrown') consoleLines.push(JSON.stringify(msg.params.exceptionDetails));
  else if (msg.method === 'Runtime.consoleAPICalled') consoleLines.push(msg.params.args.map((a) => a.value).join(' '));
};
const send = (method, params = {}) =>
  new Promise((resolve, reject) => {
    const id = ++nextId;
    pending.set(id, (msg) => (msg.error ? reject(new Error(`${method}: ${msg.error.message}`)) : resolve(msg.result)));
    socket.send(JSON.stringify({ id, method, params }));
  });
// Evaluates an expression in the page (awaiting a promise) and returns its JSON value.
const evaluate = async (expression) => {
  const r = await send('Runtime.evaluate', { expression, awaitPromise: true, returnByValue: true });
  if (r.exceptionDetails) throw new Error(`page: ${expression}: ${JSON.stringify(r.exceptionDetails)}`);
  return r.result.value;
};
// A typed array of the page as bytes: base64 in the page, decoded here (a JSON array of a
// frame's numbers is slow to pass).
const bytesOf = async (expression) =>
  Buffer.from(await evaluate(`(() => { const a = ${expression}; const u = new Uint8Array(a.buffer, a.byteOffset, a.byteLength);
    let s = ''; for (let i = 0; i < u.length; i += 32768) s += String.fromCharCode.apply(null, u.subarray(i, i + 32768));
    return btoa(s); })()`), 'base64');
const waitFor = async (expression, what) => {
  for (let k = 0; k < 600; ++k) {
    if (await evaluate(expression)) return;
    await new Promise((r) => setTimeout(r, 100));
  }
  throw new Error(`page: waited 60 s for ${what}; console: ${consoleLines.join(' | ')}`);
};

try {
  await send('Runtime.enable');
  await send('Page.enable');
  await send('Page.navigate', { url: `${origin}/playground/index.html?example=${EXAMPLE}` });
  await waitFor('window.par2dPlayground?.ready === true', 'the playground to load');
  const P = 'window.par2dPlayground';

  // 1. The page rendered the example.
  const first = await evaluate(`({example: ${P}.example, error: ${P}.error, frames: ${P}.frames, isa: ${P}.isa,
    w: document.getElementById('frame').width, h: document.getElementById('frame').height,
    status: document.getElementById('status').textContent})`);
  console.log(`page: ${JSON.stringify(first)}`);
  check(first.example === EXAMPLE && first.error === '' && first.frames >= 1, `the page loaded and rendered ${EXAMPLE}`);
  check(first.isa === 'sse4', 'the page runs the SIMD128 kernel');
  check(/frame \d+\.\d ms/.test(first.status), 'the frame time is shown');

  // 2. Its pixels: the canvas holds the native SSE4.2 kernel's PNG bytes; its linear frame is
  // within the section 5 SIMD bound of the native scalar reference.
  const scenePath = path.join(repo, 'examples', EXAMPLE);
  const scene = JSON.parse(fs.readFileSync(scenePath, 'utf8'));
  execFileSync(cli, ['render', scenePath, '--isa', 'sse4', '--backend', 'simd', '-o', path.join(work, 'sse4.png')]);
  execFileSync(cli, ['render', scenePath, '--backend', 'scalar', '--pfm', path.join(work, 'scalar.pfm')]);
  const canvasBytes = await bytesOf(`${P}.canvasPixels()`);
  const nativeBytes = readPngRgba(path.join(work, 'sse4.png'));
  check(canvasBytes.equals(nativeBytes.data), `the canvas (${first.w}x${first.h}) holds the native SSE4.2 kernel's bytes`);
  const linear = await bytesOf(`${P}.renderer.renderLinear()`);
  writePfm(path.join(work, 'page.pfm'), first.w, first.h, new Float32Array(linear.buffer, linear.byteOffset, linear.length / 4));
  const bound = 1e-4 * emissionMax(scene);
  const diff = spawnSync(path.resolve(native, 'tools/par2d_image_diff'),
    [path.join(work, 'page.pfm'), path.join(work, 'scalar.pfm'), '--tolerance', String(bound), '--json'], { encoding: 'utf8' });
  check(diff.status === 0, `the page's frame is within ${bound.toExponential(1)} of native scalar: ${diff.stdout.trim()}`);

  // 3. A drag moves a light; only dirty rectangles are computed and uploaded.
  const light = scene.lights[0].circle.center;
  const layout = await evaluate(`(() => { const r = document.getElementById('frame').getBoundingClientRect();
    const c = document.getElementById('frame'); return {left: r.left, top: r.top, sx: r.width / c.width, sy: r.height / c.height}; })()`);
  const view = scene.view ?? [0, 0, scene.width, scene.height];
  const toClient = ([x, y]) => ({
    x: layout.left + ((x - view[0]) / (view[2] - view[0])) * scene.width * layout.sx,
    y: layout.top + ((y - view[1]) / (view[3] - view[1])) * scene.height * layout.sy,
  });
  const before = await evaluate(`({frames: ${P}.frames, full: ${P}.fullUploads,
    center: ${P}.renderer.light(${P}.renderer.lights()[0]).shape.circle.center})`);
  const from = toClient(light);
  const mouse = (type, p, buttons) =>
    send('Input.dispatchMouseEvent', { type, x: p.x, y: p.y, button: 'left', buttons, clickCount: 1 });
  await mouse('mouseMoved', from, 0);
  await mouse('mousePressed', from, 1);
  for (let k = 1; k <= 4; ++k) await mouse('mouseMoved', { x: from.x + 10 * k * layout.sx, y: from.y + 5 * k * layout.sy }, 1);
  await mouse('mouseReleased', { x: from.x + 40 * layout.sx, y: from.y + 20 * layout.sy }, 0);
  const after = await evaluate(`({frames: ${P}.frames, full: ${P}.fullUploads, rects: ${P}.lastDirtyRects,
    drawn: ${P}.dirtyPixelsDrawn, center: ${P}.renderer.light(${P}.renderer.lights()[0]).shape.circle.center,
    editor: document.getElementById('editor').value})`);
  const moved = [after.center[0] - before.center[0], after.center[1] - before.center[1]];
  console.log(`drag: light 0 moved by ${moved.map((v) => v.toFixed(2))}, ${after.frames - before.frames} frames, ` +
    `last frame ${after.rects.length} dirty rects, ${after.drawn} of ${first.w * first.h} pixels uploaded`);
  check(Math.abs(moved[0] - 40) < 1e-6 && Math.abs(moved[1] - 20) < 1e-6, 'the drag moved the light by (40, 20)');
  check(after.frames - before.frames === 4 && after.full === before.full, 'the drag drew 4 frames, none of them whole');
  const rectArea = after.rects.reduce((s, r) => s + (r.x1 - r.x0) * (r.y1 - r.y0), 0);
  check(after.rects.length > 0 && after.drawn === rectArea && after.drawn < first.w * first.h,
    'the last frame uploaded its dirty rectangles only, less than the frame');
  check(JSON.parse(after.editor).lights[0].circle.center.every((v, i) => v === after.center[i]), 'the editor shows the moved light');
  const fresh = await bytesOf(`(() => { const r = ${P}.par2d.createRenderer(); r.loadScene(${P}.renderer.snapshotJson());
    const px = r.render().pixels.slice(); r.dispose(); return px; })()`);
  const shown = await bytesOf(`${P}.canvasPixels()`);
  check(fresh.equals(shown),
    'after the drag the canvas equals a fresh render of the moved scene');

  // 4. A refused scene: the validator's message, as the native CLI prints it, its line marked.
  const badText = fs.readFileSync(scenePath, 'utf8').replace(/("intensity":\s*)(\d+(\.\d+)?)/g, (m, key, v, _f, offset, all) =>
    all.slice(0, offset).split('"intensity"').length - 1 === 1 ? `${key}-3` : m);
  check(JSON.parse(badText).lights[1].intensity === -3, 'the bad scene text sets lights[1].intensity to -3');
  fs.writeFileSync(path.join(work, EXAMPLE), badText);
  const nativeRun = spawnSync(cli, ['render', EXAMPLE, '--pfm', 'never.pfm'], { cwd: work, encoding: 'utf8' });
  const nativeMessage = nativeRun.stderr.trim().replace(/^par2d: /, '');
  await evaluate(`(() => { const e = document.getElementById('editor'); e.value = ${JSON.stringify(badText)};
    e.dispatchEvent(new Event('input')); })()`);
  await waitFor(`${P}.error !== ''`, 'the error');
  const shownError = await evaluate(`({box: document.getElementById('error').textContent, line: ${P}.errorLine,
    marked: document.querySelector('#gutter .bad')?.textContent.trim()})`);
  const expectedLine = badText.split('\n').findIndex((l) => l.includes('-3')) + 1;
  console.log(`bad scene: shown '${shownError.box}' at line ${shownError.line}; native '${nativeMessage}'`);
  check(nativeRun.status !== 0 && shownError.box === nativeMessage, "the page shows the validator's message (the native CLI's)");
  check(shownError.line === expectedLine && shownError.marked === String(expectedLine), `the error's line ${expectedLine} is marked`);

  // 5. The menu opens another example, one with a normal map the page fetches beside it.
  await evaluate(`(() => { const m = document.getElementById('examples'); m.value = 'lighting_game.json';
    m.dispatchEvent(new Event('change')); })()`);
  await waitFor(`${P}.example === 'lighting_game.json' && ${P}.error === ''`, 'lighting_game.json from the menu');
  const game = await evaluate(`({w: document.getElementById('frame').width, h: document.getElementById('frame').height,
    drawn: ${P}.dirtyPixelsDrawn})`);
  check(game.w === 960 && game.h === 540 && game.drawn === 960 * 540, 'the menu opened lighting_game.json (normal-mapped) whole');

  if (screenshot) {
    await evaluate(`(() => { const m = document.getElementById('examples'); m.value = '${EXAMPLE}';
      m.dispatchEvent(new Event('change')); })()`);
    await waitFor(`${P}.example === '${EXAMPLE}' && ${P}.error === ''`, 'the example again');
    await evaluate(`(() => { const e = document.getElementById('editor'); e.value = ${JSON.stringify(badText)};
      e.dispatchEvent(new Event('input')); })()`);
    await waitFor(`${P}.error !== ''`, 'the error again');
    const shot = await send('Page.captureScreenshot', { format: 'png' });
    fs.writeFileSync(screenshot, Buffer.from(shot.data, 'base64'));
    console.log(`screenshot: ${screenshot}`);
  }
} catch (e) {
  console.log(`FAIL ${e.stack}`);
  ++failures;
}
clearTimeout(timer);
console.log(failures ? `${failures} check(s) failed` : 'the playground passes');
finish(failures ? 1 : 0);

// An 8-bit RGB or RGBA PNG as RGBA bytes (what par2d's CLI writes: non-interlaced).
function readPngRgba(file) {
  const png = fs.readFileSync(file);
  let offset = 8;
  let width = 0;
  let height = 0;
  let channels = 0;
  const idat = [];
  while (offset < png.length) {
    const length = png.readUInt32BE(offset);
    const type = png.toString('ascii', offset + 4, offset + 8);
    const data = png.subarray(offset + 8, offset + 8 + length);
    if (type === 'IHDR') {
      width = data.readUInt32BE(0);
      height = data.readUInt32BE(4);
      if (data[8] !== 8 || (data[9] !== 2 && data[9] !== 6) || data[12] !== 0) throw new Error(`${file}: unsupported PNG`);
      channels = data[9] === 6 ? 4 : 3;
    } else if (type === 'IDAT') idat.push(data);
    offset += 12 + length;
  }
  const raw = zlib.inflateSync(Buffer.concat(idat));
  const stride = width * channels;
  const rows = Buffer.alloc(height * stride);
  for (let y = 0; y < height; ++y) {
    const filter = raw[y * (stride + 1)];
    const line = raw.subarray(y * (stride + 1) + 1, (y + 1) * (stride + 1));
    for (let x = 0; x < stride; ++x) {
      const a = x >= channels ? rows[y * stride + x - channels] : 0;
      const b = y > 0 ? rows[(y - 1) * stride + x] : 0;
      const c = x >= channels && y > 0 ? rows[(y - 1) * stride + x - channels] : 0;
      let v = line[x];
      if (filter === 1) v += a;
      else if (filter === 2) v += b;
      else if (filter === 3) v += (a + b) >> 1;
      else if (filter === 4) {
        const p = a + b - c;
        const pa = Math.abs(p - a);
        const pb = Math.abs(p - b);
        const pc = Math.abs(p - c);
        v += pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
      }
      rows[y * stride + x] = v & 255;
    }
  }
  const data = Buffer.alloc(width * height * 4, 255);
  for (let i = 0; i < width * height; ++i) for (let k = 0; k < channels; ++k) data[i * 4 + k] = rows[i * channels + k];
  return { width, height, data };
}
