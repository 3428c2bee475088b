// Every example scene rendered by the WebAssembly module through par2d.mjs, against the native
// build's renders of the same file (docs/platforms.md, "WebAssembly and the playground"):
//
// - the SIMD128 frame (the SSE4.2 kernel) against the native SSE4.2 kernel: the same bytes;
// - the SIMD128 frame against the native scalar reference: within docs/contract.md section 5's
//   SIMD bound, 1e-4 * e_max per channel;
// - the module's scalar reference against the native one: each within 1e-6 * e_max of the
//   exact value, so within 2e-6 * e_max of each other;
// - refused scenes (a bad value, a JSON syntax error): the Par2dError's message is the native
//   CLI's message for the same file.
//
// Usage: node web/test/examples.mjs SITE NATIVE_BUILD   (SITE: build-wasm/web/site)
// Exit status 0 when every check holds; each failure is printed with the example and numbers.
import { execFileSync, spawnSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';

const [site, native] = process.argv.slice(2);
if (!site || !native) {
  console.error('usage: node web/test/examples.mjs SITE NATIVE_BUILD');
  process.exit(2);
}
const repo = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..');
const cli = path.resolve(native, 'tools/par2d');
const diffTool = path.resolve(native, 'tools/par2d_image_diff');
const { loadPar2d, Par2dError } = await import(pathToFileURL(path.resolve(site, 'par2d.mjs')).href);
const { emissionMax, writePfm, sceneFiles } = await import('./scene_tools.mjs');

const par2d = await loadPar2d();
if (par2d.isa !== 'sse4') throw new Error(`the module's SIMD level is ${par2d.isa}, expected sse4 (SIMD128)`);
const work = fs.mkdtempSync(path.join(os.tmpdir(), 'par2d-wasm-'));
let failures = 0;
const fail = (message) => {
  ++failures;
  console.log(`FAIL ${message}`);
};

// par2d_image_diff's numbers for two PFMs, and whether every channel is within `tolerance`.
function imageDiff(a, b, tolerance) {
  const run = spawnSync(diffTool, [a, b, '--tolerance', String(tolerance), '--json'], { encoding: 'utf8' });
  if (run.status !== 0 && run.status !== 1) throw new Error(`par2d_image_diff ${a} ${b}: ${run.stderr}`);
  return { ...JSON.parse(run.stdout), within: run.status === 0 };
}

function sameBytes(a, b) {
  return Buffer.compare(fs.readFileSync(a), fs.readFileSync(b)) === 0;
}

const examples = fs.readdirSync(path.join(repo, 'examples')).filter((f) => f.endsWith('.json')).sort();
if (examples.length < 10) throw new Error(`only ${examples.length} examples found`);
console.log('example                  size        e_max   simd=sse4  simd-vs-scalar (bound)     scalar-vs-scalar (bound)');
// The scalar reference of a frame past this many pixels takes minutes on one thread here
// (dungeon.json: 2 minutes in the module, 1 natively on two cores): such an example is
// compared whole SIMD128 against native SSE4.2, then every comparison is made on its middle
// quarter of width and height (a sixteenth of its pixels), a scene file of its own: the same
// shapes, the view cut at pixel boundaries, so its pixels are pixels of the whole frame.
const CROP_ABOVE_PIXELS = 1 << 20;
const cases = [];
for (const name of examples) {
  const file = path.join(repo, 'examples', name);
  const scene = JSON.parse(fs.readFileSync(file, 'utf8'));
  if (scene.width * scene.height <= CROP_ABOVE_PIXELS) {
    cases.push({ name, file, full: true });
    continue;
  }
  const wholeWasm = par2d.createRenderer();
  wholeWasm.loadScene(fs.readFileSync(file, 'utf8'), { name, files: sceneFiles(scene, path.dirname(file)) });
  const whole = path.join(work, `${path.basename(name, '.json')}_whole`);
  writePfm(`${whole}_wasm.pfm`, wholeWasm.width, wholeWasm.height, wholeWasm.renderLinear());
  wholeWasm.dispose();
  execFileSync(cli, ['render', file, '--isa', 'sse4', '--backend', 'simd', '--threads', '1', '--pfm', `${whole}_native.pfm`]);
  const same = sameBytes(`${whole}_wasm.pfm`, `${whole}_native.pfm`);
  console.log(`${name} whole ${scene.width}x${scene.height}: SIMD128 ${same ? 'identical to' : 'DIFFERS from'} native SSE4.2`);
  if (!same) fail(`${name}: the whole SIMD128 frame differs from the native SSE4.2 kernel's`);
  const view = scene.view ?? [0, 0, scene.width, scene.height];
  const [w, h] = [Math.floor(scene.width / 4), Math.floor(scene.height / 4)];
  const [i0, j0] = [Math.floor((scene.width - w) / 2), Math.floor((scene.height - h) / 2)];
  const [sx, sy] = [(view[2] - view[0]) / scene.width, (view[3] - view[1]) / scene.height];
  const crop = { ...scene, width: w, height: h,
    view: [view[0] + i0 * sx, view[1] + j0 * sy, view[0] + (i0 + w) * sx, view[1] + (j0 + h) * sy] };
  const cropName = `${path.basename(name, '.json')}_middle.json`;
  fs.writeFileSync(path.join(work, cropName), JSON.stringify(crop));
  cases.push({ name: cropName, file: path.join(work, cropName), full: false });
}

for (const { name, file } of cases) {
  const json = fs.readFileSync(file, 'utf8');
  const scene = JSON.parse(json);
  const files = sceneFiles(scene, path.dirname(file));
  const out = (tag) => path.join(work, `${path.basename(name, '.json')}_${tag}.pfm`);

  const simd = par2d.createRenderer();
  simd.loadScene(json, { name, files });
  if (simd.isa !== 'sse4') fail(`${name}: the SIMD renderer runs at ${simd.isa}`);
  writePfm(out('wasm_simd'), simd.width, simd.height, simd.renderLinear());
  simd.dispose();
  const scalar = par2d.createRenderer({ backend: 'scalar' });
  scalar.loadScene(json, { name, files });
  writePfm(out('wasm_scalar'), scalar.width, scalar.height, scalar.renderLinear());
  scalar.dispose();

  // The native CLI on the same file: the SSE4.2 kernel, and the scalar reference (any thread
  // count gives the same bytes; the reference takes all of them).
  execFileSync(cli, ['render', file, '--isa', 'sse4', '--backend', 'simd', '--threads', '1', '--pfm', out('native_sse4')]);
  execFileSync(cli, ['render', file, '--backend', 'scalar', '--pfm', out('native_scalar')]);

  const eMax = emissionMax(scene);
  const identical = sameBytes(out('wasm_simd'), out('native_sse4'));
  const simdBound = 1e-4 * eMax;
  const simdDiff = imageDiff(out('wasm_simd'), out('native_scalar'), simdBound);
  const scalarBound = 2e-6 * eMax;
  const scalarDiff = imageDiff(out('wasm_scalar'), out('native_scalar'), scalarBound);
  console.log(
    `${name.padEnd(24)} ${`${simd.width}x${simd.height}`.padEnd(11)} ${eMax.toPrecision(4).padStart(7)}   ` +
      `${identical ? 'identical' : 'DIFFERENT'}  ${simdDiff.max_abs.toExponential(2)} (${simdBound.toExponential(1)})` +
      `${' '.repeat(10)}${scalarDiff.max_abs.toExponential(2)} (${scalarBound.toExponential(1)})`,
  );
  if (!identical) fail(`${name}: the SIMD128 frame differs from the native SSE4.2 kernel's (max ${imageDiff(out('wasm_simd'), out('native_sse4'), 0).max_abs})`);
  if (!simdDiff.within) fail(`${name}: SIMD128 vs native scalar: ${JSON.stringify(simdDiff)} over ${simdBound}`);
  if (!scalarDiff.within) fail(`${name}: wasm scalar vs native scalar: ${JSON.stringify(scalarDiff)} over ${scalarBound}`);
}

// Refused scenes: a value the validator refuses, and a JSON syntax error (caught from the JSON
// parser's C++ exception): the message is the native CLI's for the same file.
const spot = JSON.parse(fs.readFileSync(path.join(repo, 'examples/lighting_spot.json'), 'utf8'));
spot.lights[1].color = [1, -0.5, 1];
const refused = {
  'bad_color.json': JSON.stringify(spot, null, 2),
  'bad_syntax.json': fs.readFileSync(path.join(repo, 'examples/lighting_spot.json'), 'utf8').replace('"lights":', '"lights"'),
};
const renderer = par2d.createRenderer();
for (const [name, text] of Object.entries(refused)) {
  fs.writeFileSync(path.join(work, name), text);
  const nativeRun = spawnSync(cli, ['render', name, '--pfm', 'never.pfm'], { cwd: work, encoding: 'utf8' });
  const nativeMessage = nativeRun.stderr.trim().replace(/^par2d: /, '');
  let jsMessage = null;
  try {
    renderer.loadScene(text, { name });
  } catch (e) {
    if (!(e instanceof Par2dError)) throw e;
    jsMessage = e.message;
  }
  console.log(`${name}: native exit ${nativeRun.status}: ${nativeMessage}\n${' '.repeat(name.length)}  par2d.mjs: ${jsMessage}`);
  if (nativeRun.status === 0 || !nativeMessage) fail(`the native CLI accepted ${name}`);
  if (jsMessage !== nativeMessage) fail(`${name}: the message differs: '${jsMessage}' vs native '${nativeMessage}'`);
  if (renderer.width !== 0) fail(`${name}: a refused scene changed the renderer`);
}
renderer.dispose();

// Numbers as text: the module's libc++ has no floating-point std::to_chars, so scene snapshots
// and validator messages use src/scene/shortest_double.hpp's printf/strtod search. Every
// coordinate must read back as the same double, over magnitudes 1e-6 to 1e6 and a few edges.
{
  const values = [0.1, 1 / 3, 100, 0.5, 1e21, 123456789012.5, 1e-7, -2.5e-5, 4096.000000000001];
  let state = 12345;
  const next = () => (state = (state * 1103515245 + 12345) % 2147483648) / 2147483648;
  while (values.length < 3000) values.push((next() - 0.5) * 10 ** Math.floor(next() * 13 - 6));
  const r = par2d.createRenderer();
  r.loadScene('{"width": 16, "height": 16}');
  for (let i = 0; i + 1 < values.length; i += 2) r.addOccluder({ circle: { center: [values[i], values[i + 1]], radius: 1 } });
  const occluders = JSON.parse(r.snapshotJson()).occluders;
  const wrong = occluders.filter((o, k) => o.circle.center[0] !== values[2 * k] || o.circle.center[1] !== values[2 * k + 1]);
  console.log(`snapshot numbers: ${occluders.length} occluders written, ${wrong.length} read back different`);
  if (occluders.length !== values.length / 2 || wrong.length) fail(`snapshot numbers: ${JSON.stringify(wrong.slice(0, 3))}`);
  r.dispose();
}

fs.rmSync(work, { recursive: true, force: true });
console.log(failures ? `${failures} check(s) failed` : `all ${examples.length} examples and the refused scenes pass`);
process.exit(failures ? 1 : 0);
