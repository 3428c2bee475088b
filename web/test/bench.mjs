// Frame time of examples/paper.json at 1024x768 on one thread, in one run: the native SSE4.2
// kernel (`par2d bench --isa sse4 --threads 1`), the WebAssembly module with SIMD128 (the same
// kernel) and the module built without SIMD128 (its scalar path), both under this node.
// Prints the three times and the ratios; exits 1 when a target is missed: SIMD128 within 2x
// of native SSE4.2, and at least 3x faster than the scalar module.
//
// Usage: node web/test/bench.mjs SITE SCALAR_SITE NATIVE_BUILD [--frames N] [--json FILE]
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';

const args = process.argv.slice(2);
const option = (name, fallback) => {
  const i = args.indexOf(name);
  if (i < 0) return fallback;
  const value = args[i + 1];
  args.splice(i, 2);
  return value;
};
const frames = Number(option('--frames', '10'));
const jsonOut = option('--json', null);
const [site, scalarSite, native] = args;
if (!site || !scalarSite || !native || !(frames >= 1)) {
  console.error('usage: node web/test/bench.mjs SITE SCALAR_SITE NATIVE_BUILD [--frames N] [--json FILE]');
  process.exit(2);
}
const repo = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..');
const scenePath = path.join(repo, 'examples/paper.json');
const json = fs.readFileSync(scenePath, 'utf8');
const { loadPar2d } = await import(pathToFileURL(path.resolve(site, 'par2d.mjs')).href);

// As `par2d bench` does: untimed frames, then `count` whole frames timed together, each
// computing every pixel (incremental frames off) into linear float RGB.
function wasmFrameMs(par2d, count) {
  const renderer = par2d.createRenderer();
  renderer.loadScene(json, { name: 'paper.json' });
  const c = par2d.core;
  c._par2d_set_incremental(renderer.handle, 0);
  const bytes = renderer.width * renderer.height * 12;
  const pixels = c._malloc(bytes);
  const frame = () => {
    const status = c._par2d_render(renderer.handle, pixels, 0, renderer.width * 12, 1, 0);
    if (status !== 0) throw new Error(c.UTF8ToString(c._par2d_last_error()));
  };
  // Untimed frames for three seconds first: V8 runs a module on its baseline compiler (Liftoff)
  // while the optimizing one (TurboFan) compiles it in the background, and a frame started in
  // baseline code finishes there (on paper.json the first eight frames took 370 to 30 ms, the
  // steady state 27 ms). A native build has no such phase.
  for (const warm = performance.now(); performance.now() - warm < 3000; ) frame();
  const start = performance.now();
  for (let k = 0; k < count; ++k) frame();
  const ms = (performance.now() - start) / count;
  const isa = renderer.isa;
  c._free(pixels);
  renderer.dispose();
  return { ms, isa, size: `${renderer.width}x${renderer.height}` };
}

const nativeRun = JSON.parse(
  execFileSync(path.resolve(native, 'tools/par2d'), [
    'bench', scenePath, '--backend', 'simd', '--isa', 'sse4', '--threads', '1', '--frames', String(frames), '--json',
  ], { encoding: 'utf8' }),
);
const simd = wasmFrameMs(await loadPar2d(), frames);
const scalarModule = await loadPar2d({ core: pathToFileURL(path.resolve(scalarSite, 'par2d_core.mjs')).href });
// The scalar module's frames take seconds: fewer of them.
const scalar = wasmFrameMs(scalarModule, Math.max(1, Math.min(frames, 2)));

const result = {
  scene: 'examples/paper.json',
  size: simd.size,
  threads: 1,
  node: process.version,
  native_sse4_ms: nativeRun.ms_per_frame,
  native_isa: nativeRun.isa,
  wasm_simd128_ms: simd.ms,
  wasm_simd128_isa: simd.isa,
  wasm_scalar_ms: scalar.ms,
  wasm_scalar_isa: scalar.isa,
  simd128_over_native: simd.ms / nativeRun.ms_per_frame,
  scalar_over_simd128: scalar.ms / simd.ms,
};
console.log(
  `paper.json ${simd.size}, 1 thread: native SSE4.2 ${result.native_sse4_ms.toFixed(2)} ms/frame, ` +
    `wasm SIMD128 ${simd.ms.toFixed(2)} ms (${result.simd128_over_native.toFixed(2)}x native), ` +
    `wasm scalar ${scalar.ms.toFixed(1)} ms (${result.scalar_over_simd128.toFixed(1)}x SIMD128)`,
);
if (jsonOut) fs.writeFileSync(jsonOut, JSON.stringify(result, null, 2) + '\n');
let failed = false;
if (nativeRun.isa !== 'sse4' || simd.isa !== 'sse4' || scalar.isa !== 'scalar') {
  console.log(`FAIL levels: native ${nativeRun.isa}, SIMD128 module ${simd.isa}, scalar module ${scalar.isa}`);
  failed = true;
}
if (result.simd128_over_native > 2) {
  console.log('FAIL the SIMD128 module takes more than 2x the native SSE4.2 kernel');
  failed = true;
}
if (result.scalar_over_simd128 < 3) {
  console.log('FAIL the SIMD128 module is less than 3x faster than the scalar module');
  failed = true;
}
process.exit(failed ? 1 : 0);
