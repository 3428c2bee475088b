// par2d for JavaScript: the C API (include/par2d/par2d.h) compiled to WebAssembly
// (par2d_core.mjs, built by `cmake --preset wasm`), wrapped in a small typed API. The same file
// runs in a browser and in node (>= 18). Types: par2d.d.ts. One thread: the module has no
// pthreads, so a frame runs on the calling thread.
//
//   import { loadPar2d } from './par2d.mjs';
//   const par2d = await loadPar2d();
//   const renderer = par2d.createRenderer();
//   renderer.loadScene(jsonText);                 // throws Par2dError with the validator's message
//   const frame = renderer.render();              // RGBA8 (sRGB) in frame.pixels, dirty rectangles
//   ctx.putImageData(new ImageData(frame.pixels, frame.width, frame.height), 0, 0);

// par2d.h's constants and the wasm32 layout of its structs (offsets in bytes).
const OK = 0;
const PIXEL = { RGB_F32: 0, RGBA_F32: 1, RGBA8_SRGB: 2 };
const BACKEND = { auto: 0, simd: 1, scalar: 2 };
const SHAPE_KIND = { polygon: 0, circle: 1, segment: 2 };
const SHAPE_SIZE = 80; // kind@0 vertices@4 vertex_count@8 circle@16 segment@40 holes@72 hole_count@76
const OPTIONS_SIZE = 16; // backend, threads, spp, culling
const ADVANCED_SIZE = 20; // isa, threading, shaded, sample_needs, bounce
const RECT_SIZE = 16; // x0, y0, x1, y1
const FRAME_STATS_SIZE = 48; // pixels, tiles, ... (uint64 each)
const ISA_NAMES = ['scalar', 'sse4', 'avx2', 'avx512', 'neon64'];

/** A failed call: `message` is par2d's one-line error (a scene's names the file and the place). */
export class Par2dError extends Error {
  /** @param {string} message @param {number} status */
  constructor(message, status) {
    super(message);
    this.name = 'Par2dError';
    /** par2d_status of the failed call (2: invalid scene, 1: invalid argument, ...). */
    this.status = status;
  }
}

/**
 * Loads the WebAssembly module. `core` is the module factory's URL or the factory itself
 * (default: par2d_core.mjs next to this file; the scalar-only build is another core).
 * @param {{core?: string | URL | ((options?: object) => Promise<any>)}} [options]
 * @returns {Promise<Par2d>}
 */
export async function loadPar2d(options = {}) {
  let factory = options.core;
  if (typeof factory !== 'function') {
    const url = factory ? new URL(String(factory), import.meta.url) : new URL('./par2d_core.mjs', import.meta.url);
    factory = (await import(url.href)).default;
  }
  return new Par2d(await factory());
}

/** The loaded module: creates renderers, names the SIMD level it was built with. */
export class Par2d {
  /** @param {any} core the emscripten module */
  constructor(core) {
    this.core = core;
    this._scratch = core._malloc(256);
  }

  /** The library's version ("0.2.0"). */
  get version() {
    return this.core.UTF8ToString(this.core._par2d_version());
  }

  /** "sse4" where the module holds the SSE4.2 kernel compiled to SIMD128, "scalar" otherwise. */
  get isa() {
    return ISA_NAMES[this.core._par2d_detect_isa()] ?? 'scalar';
  }

  /**
   * A renderer with an empty world. `backend` "auto" (default), "simd" or "scalar" (the
   * double-precision reference); `spp` samples per pixel (default 1).
   * @param {{backend?: 'auto'|'simd'|'scalar', spp?: number}} [options]
   * @returns {Renderer}
   */
  createRenderer(options = {}) {
    const c = this.core;
    const opts = this._scratch;
    c._par2d_options_default(opts);
    const backend = BACKEND[options.backend ?? 'auto'];
    if (backend === undefined) throw new Par2dError(`createRenderer: unknown backend '${options.backend}'`, 1);
    c.HEAP32[opts >> 2] = backend;
    c.HEAP32[(opts + 4) >> 2] = 1; // one thread: no pthreads in this module
    if (options.spp !== undefined) c.HEAP32[(opts + 8) >> 2] = options.spp;
    const out = this._scratch + OPTIONS_SIZE;
    this._check(c._par2d_renderer_create(opts, out));
    return new Renderer(this, c.HEAPU32[out >> 2]);
  }

  /** Throws the last error as a Par2dError when `status` is not PAR2D_OK. */
  _check(status) {
    if (status !== OK) throw new Par2dError(this.core.UTF8ToString(this.core._par2d_last_error()), status);
  }
}

let sceneFolders = 0;

/** A persistent renderer (par2d_renderer): a world, its frame, RGBA8 output with dirty rectangles. */
export class Renderer {
  /** @param {Par2d} par2d @param {number} handle */
  constructor(par2d, handle) {
    this.par2d = par2d;
    this.core = par2d.core;
    this.handle = handle;
    this.width = 0;
    this.height = 0;
    /** The last frame, RGBA8 sRGB, alpha 255: hand it to `new ImageData(pixels, width, height)`. */
    this.pixels = new Uint8ClampedArray(0);
    this._buffer = 0; // the frame in wasm memory (par2d_render writes only dirty blocks of it)
    this._bufferBytes = 0;
    this._exposure = 1;
    this.core._par2d_set_incremental(handle, 1);
  }

  /**
   * Replaces the world (frame included) with a scene (docs/contract.md section 3), given as JSON
   * text. A refused scene throws Par2dError with the validator's message, which names `name`
   * and the place ("scene.json: lights[0].color[1]: ..."), and leaves the world as it was.
   * `files` are other files the scene names (a normal_map PNG), by path relative to it.
   * @param {string} json
   * @param {{name?: string, files?: Record<string, Uint8Array>}} [options]
   */
  loadScene(json, options = {}) {
    const { FS } = this.core;
    const name = options.name ?? 'scene.json';
    if (name.includes('/') || name === '' || name === '.' || name === '..')
      throw new Par2dError(`loadScene: name '${name}' must be a plain file name`, 1);
    // A folder of its own per load, so a scene sees only the files given with it.
    const folder = `/par2d_scene_${++sceneFolders}`;
    FS.mkdir(folder);
    try {
      for (const [path, bytes] of Object.entries(options.files ?? {})) {
        const parts = path.split('/');
        if (parts.some((p) => p === '' || p === '.' || p === '..'))
          throw new Par2dError(`loadScene: file '${path}' must be a relative path inside the scene's folder`, 1);
        let dir = folder;
        for (const part of parts.slice(0, -1)) {
          dir += '/' + part;
          if (!FS.analyzePath(dir).exists) FS.mkdir(dir);
        }
        FS.writeFile(`${folder}/${path}`, bytes);
      }
      FS.writeFile(`${folder}/${name}`, json);
      // The message names the file as given, not the folder it was written to here.
      const status = this._loadFrom(folder, name);
      if (status !== OK) {
        // The validator's message alone, without the C function's name before it.
        const message = this.core.UTF8ToString(this.core._par2d_last_error()).replace(/^par2d_load_scene: /, '');
        throw new Par2dError(message, status);
      }
    } finally {
      removeTree(FS, folder);
    }
    this._readFrame();
  }

  _loadFrom(folder, name) {
    const c = this.core;
    const previous = c.FS.cwd();
    c.FS.chdir(folder);
    try {
      return this._withString(name, (path) => c._par2d_load_scene(this.handle, path));
    } finally {
      c.FS.chdir(previous);
    }
  }

  /** Sets the frame: width x height pixels showing the world rectangle `view` [x0, y0, x1, y1]. */
  setFrame(width, height, view) {
    const c = this.core;
    let viewPtr = 0;
    if (view) {
      viewPtr = this.par2d._scratch + 64;
      c.HEAPF64.set(view.map(Number), viewPtr >> 3);
    }
    this._call(c._par2d_set_frame(this.handle, width, height, viewPtr));
    this._readFrame();
  }

  /** Sets the exposure of the 8-bit output (pixels show clamp(exposure * E, 0, 1), sRGB). */
  setExposure(exposure) {
    if (!(exposure >= 0 && Number.isFinite(exposure))) throw new Par2dError(`setExposure: ${exposure} is not a finite number >= 0`, 1);
    this._exposure = exposure;
  }

  /**
   * The SIMD level cap: "scalar" runs the scalar kernel path on the SIMD backend (as PAR2D_ISA=scalar),
   * "default" the best the module has.
   * @param {'default'|'scalar'|'sse4'} isa
   */
  setIsa(isa) {
    const c = this.core;
    const p = this.par2d._scratch;
    c._par2d_get_advanced_options(this.handle, p);
    const value = isa === 'default' ? -1 : ISA_NAMES.indexOf(isa);
    if (value === -1 && isa !== 'default') throw new Par2dError(`setIsa: unknown level '${isa}'`, 1);
    c.HEAP32[p >> 2] = value;
    this._call(c._par2d_set_advanced_options(this.handle, p));
  }

  /** The level frames run at: "sse4" (SIMD128) or "scalar". */
  get isa() {
    return ISA_NAMES[this.core._par2d_renderer_isa(this.handle)] ?? 'scalar';
  }

  /**
   * Renders the frame into `pixels`. Incremental: only the 64x64 blocks whose inputs changed
   * since the last frame are computed and copied; `dirtyRects` are the rectangles that changed
   * (the whole frame the first time, and after setFrame or `{full: true}`).
   * @param {{full?: boolean}} [options]
   * @returns {{pixels: Uint8ClampedArray, width: number, height: number, dirtyRects: Rect[], ms: number}}
   */
  render(options = {}) {
    const c = this.core;
    const bytes = this.width * this.height * 4;
    if (bytes === 0) throw new Par2dError('render: no frame (load a scene or call setFrame first)', 1);
    if (bytes !== this._bufferBytes) {
      if (this._buffer) c._free(this._buffer);
      this._buffer = c._malloc(bytes);
      if (!this._buffer) throw new Par2dError(`render: out of memory for a ${this.width}x${this.height} frame`, 4);
      this._bufferBytes = bytes;
      this.pixels = new Uint8ClampedArray(bytes);
      c._par2d_force_full_frame(this.handle);
    }
    if (options.full) c._par2d_force_full_frame(this.handle);
    const start = performance.now();
    this._call(c._par2d_render(this.handle, this._buffer, PIXEL.RGBA8_SRGB, this.width * 4, this._exposure, 0));
    const ms = performance.now() - start;
    const dirtyRects = this.dirtyRects();
    // Copy out only what changed (HEAPU8 is re-read: memory growth replaces the buffer).
    const heap = c.HEAPU8;
    const stride = this.width * 4;
    for (const r of dirtyRects) {
      for (let y = r.y0; y < r.y1; ++y) {
        const from = this._buffer + y * stride + r.x0 * 4;
        this.pixels.set(heap.subarray(from, from + (r.x1 - r.x0) * 4), y * stride + r.x0 * 4);
      }
    }
    return { pixels: this.pixels, width: this.width, height: this.height, dirtyRects, ms };
  }

  /**
   * Renders the whole frame as linear float RGB (3 floats per pixel, rows from the top): the
   * irradiance itself, for comparisons (docs/contract.md section 5).
   * @returns {Float32Array}
   */
  renderLinear() {
    const c = this.core;
    const count = this.width * this.height * 3;
    const ptr = c._malloc(count * 4);
    if (!ptr) throw new Par2dError('renderLinear: out of memory', 4);
    try {
      c._par2d_set_incremental(this.handle, 0);
      this._call(c._par2d_render(this.handle, ptr, PIXEL.RGB_F32, this.width * 12, 1, 0));
      return new Float32Array(c.HEAPF32.buffer, ptr, count).slice();
    } finally {
      c._par2d_set_incremental(this.handle, 1);
      c._par2d_force_full_frame(this.handle);
      c._free(ptr);
    }
  }

  /** The rectangles the last render wrote: pixel columns [x0, x1), rows [y0, y1). @returns {Rect[]} */
  dirtyRects() {
    const c = this.core;
    const countPtr = this.par2d._scratch + 128;
    this._call(c._par2d_dirty_rects(this.handle, 0, 0, countPtr));
    const count = c.HEAPU32[countPtr >> 2];
    if (count === 0) return [];
    const ptr = c._malloc(count * RECT_SIZE);
    try {
      this._call(c._par2d_dirty_rects(this.handle, ptr, count, countPtr));
      const rects = [];
      for (let i = 0; i < count; ++i) {
        const p = (ptr >> 2) + i * 4;
        rects.push({ x0: c.HEAP32[p], y0: c.HEAP32[p + 1], x1: c.HEAP32[p + 2], y1: c.HEAP32[p + 3] });
      }
      return rects;
    } finally {
      c._free(ptr);
    }
  }

  /** What the last render computed: pixels and 16x16 tiles (an incremental frame: its changed blocks). */
  frameStats() {
    const c = this.core;
    const p = this.par2d._scratch;
    this._call(c._par2d_get_frame_stats(this.handle, p));
    const u64 = new BigUint64Array(c.HEAPU8.buffer, p, FRAME_STATS_SIZE / 8);
    return { pixels: Number(u64[0]), tiles: Number(u64[1]) };
  }

  /** The lights' handles, a loaded scene's in its order. @returns {bigint[]} */
  lights() {
    return this._handles((out, cap, count) => this.core._par2d_get_light_handles(this.handle, out, cap, count));
  }

  /** The occluders' handles. @returns {bigint[]} */
  occluders() {
    return this._handles((out, cap, count) => this.core._par2d_get_occluder_handles(this.handle, out, cap, count));
  }

  /**
   * A light as last given: its shape, color and intensity.
   * @param {bigint} light
   * @returns {{shape: Shape, color: number[], intensity: number}}
   */
  light(light) {
    const c = this.core;
    const shape = c._malloc(SHAPE_SIZE + 32);
    try {
      this._call(c._par2d_get_light(this.handle, BigInt(light), shape, shape + SHAPE_SIZE, shape + SHAPE_SIZE + 24));
      const color = Array.from(c.HEAPF64.subarray((shape + SHAPE_SIZE) >> 3, ((shape + SHAPE_SIZE) >> 3) + 3));
      return { shape: readShape(c, shape), color, intensity: c.HEAPF64[(shape + SHAPE_SIZE + 24) >> 3] };
    } finally {
      c._free(shape);
    }
  }

  /** An occluder's shape as last given. @param {bigint} occluder @returns {Shape} */
  occluder(occluder) {
    const c = this.core;
    const shape = c._malloc(SHAPE_SIZE);
    try {
      this._call(c._par2d_get_occluder(this.handle, BigInt(occluder), shape));
      return readShape(c, shape);
    } finally {
      c._free(shape);
    }
  }

  /**
   * Changes a light: any of shape, color (linear RGB) and intensity; the rest stays. Its terms
   * (range, cone, mask, ...) stay too.
   * @param {bigint} light
   * @param {{shape?: Shape, color?: number[], intensity?: number}} change
   */
  updateLight(light, change) {
    const now = this.light(light);
    const shape = change.shape ?? now.shape;
    const color = change.color ?? now.color;
    const intensity = change.intensity ?? now.intensity;
    this._withShape(shape, (s) => this._withDoubles(color, (col) =>
      this._call(this.core._par2d_update_light(this.handle, BigInt(light), s, col, intensity))));
  }

  /** Moves a light by (dx, dy) world units. @param {bigint} light */
  moveLight(light, dx, dy) {
    this.updateLight(light, { shape: translateShape(this.light(light).shape, dx, dy) });
  }

  /** Adds a light (default terms). @returns {bigint} its handle */
  addLight(shape, color, intensity) {
    const out = this.par2d._scratch + 192;
    this._withShape(shape, (s) => this._withDoubles(color, (col) =>
      this._call(this.core._par2d_add_light(this.handle, s, col, intensity, out))));
    return new BigUint64Array(this.core.HEAPU8.buffer, out, 1)[0];
  }

  /** @param {bigint} light */
  removeLight(light) {
    this._call(this.core._par2d_remove_light(this.handle, BigInt(light)));
  }

  /** Adds an occluder (default terms). @returns {bigint} its handle */
  addOccluder(shape) {
    const out = this.par2d._scratch + 192;
    this._withShape(shape, (s) => this._call(this.core._par2d_add_occluder(this.handle, s, out)));
    return new BigUint64Array(this.core.HEAPU8.buffer, out, 1)[0];
  }

  /** Replaces an occluder's shape (its terms stay). @param {bigint} occluder @param {Shape} shape */
  updateOccluder(occluder, shape) {
    this._withShape(shape, (s) => this._call(this.core._par2d_update_occluder(this.handle, BigInt(occluder), s)));
  }

  /** Moves an occluder by (dx, dy) world units. @param {bigint} occluder */
  moveOccluder(occluder, dx, dy) {
    this.updateOccluder(occluder, translateShape(this.occluder(occluder), dx, dy));
  }

  /** @param {bigint} occluder */
  removeOccluder(occluder) {
    this._call(this.core._par2d_remove_occluder(this.handle, BigInt(occluder)));
  }

  /** The world as scene JSON text (rendering it gives the same image). */
  snapshotJson() {
    const c = this.core;
    const lengthPtr = this.par2d._scratch + 128;
    this._call(c._par2d_snapshot_json(this.handle, 0, 0, lengthPtr));
    const length = c.HEAPU32[lengthPtr >> 2];
    const ptr = c._malloc(length + 1);
    try {
      this._call(c._par2d_snapshot_json(this.handle, ptr, length + 1, lengthPtr));
      return c.UTF8ToString(ptr, length);
    } finally {
      c._free(ptr);
    }
  }

  /** Frees the renderer and its frame. */
  dispose() {
    if (this._buffer) this.core._free(this._buffer);
    this._buffer = 0;
    this.core._par2d_renderer_destroy(this.handle);
    this.handle = 0;
  }

  _call(status) {
    this.par2d._check(status);
  }

  _readFrame() {
    const c = this.core;
    const p = this.par2d._scratch;
    this._call(c._par2d_get_frame(this.handle, p, p + 4, 0));
    this.width = c.HEAP32[p >> 2];
    this.height = c.HEAP32[(p + 4) >> 2];
  }

  _handles(get) {
    const c = this.core;
    const countPtr = this.par2d._scratch + 128;
    this._call(get(0, 0, countPtr));
    const count = c.HEAPU32[countPtr >> 2];
    if (count === 0) return [];
    const ptr = c._malloc(count * 8);
    try {
      this._call(get(ptr, count, countPtr));
      return Array.from(new BigUint64Array(c.HEAPU8.buffer, ptr, count));
    } finally {
      c._free(ptr);
    }
  }

  _withString(text, fn) {
    const c = this.core;
    const size = c.lengthBytesUTF8(text) + 1;
    const ptr = c._malloc(size);
    try {
      c.stringToUTF8(text, ptr, size);
      return fn(ptr);
    } finally {
      c._free(ptr);
    }
  }

  _withDoubles(values, fn) {
    const c = this.core;
    const ptr = c._malloc(values.length * 8);
    try {
      c.HEAPF64.set(values.map(Number), ptr >> 3);
      return fn(ptr);
    } finally {
      c._free(ptr);
    }
  }

  _withShape(shape, fn) {
    const c = this.core;
    const ptr = c._malloc(SHAPE_SIZE);
    c.HEAPU8.fill(0, ptr, ptr + SHAPE_SIZE);
    let vertices = 0;
    let holeCounts = 0;
    try {
      if ('circle' in shape) {
        c.HEAP32[ptr >> 2] = SHAPE_KIND.circle;
        c.HEAPF64.set([...shape.circle.center, shape.circle.radius].map(Number), (ptr + 16) >> 3);
      } else if ('segment' in shape) {
        c.HEAP32[ptr >> 2] = SHAPE_KIND.segment;
        c.HEAPF64.set(shape.segment.flat().map(Number), (ptr + 40) >> 3);
      } else if ('polygon' in shape) {
        const rings = [shape.polygon, ...(shape.holes ?? [])];
        const flat = rings.flat(2).map(Number);
        vertices = c._malloc(flat.length * 8);
        c.HEAPF64.set(flat, vertices >> 3);
        c.HEAP32[ptr >> 2] = SHAPE_KIND.polygon;
        c.HEAPU32[(ptr + 4) >> 2] = vertices;
        c.HEAPU32[(ptr + 8) >> 2] = shape.polygon.length;
        if (shape.holes?.length) {
          holeCounts = c._malloc(shape.holes.length * 4);
          c.HEAPU32.set(shape.holes.map((h) => h.length), holeCounts >> 2);
          c.HEAPU32[(ptr + 72) >> 2] = holeCounts;
          c.HEAPU32[(ptr + 76) >> 2] = shape.holes.length;
        }
      } else {
        throw new Par2dError('shape: expected {circle}, {segment} or {polygon}', 1);
      }
      return fn(ptr);
    } finally {
      if (vertices) c._free(vertices);
      if (holeCounts) c._free(holeCounts);
      c._free(ptr);
    }
  }
}

/** A shape as the scene format writes it: {circle: {center, radius}}, {segment: [a, b]} or {polygon: [[x, y], ...], holes?}. */
function readShape(c, ptr) {
  const kind = c.HEAP32[ptr >> 2];
  if (kind === SHAPE_KIND.circle) {
    const [x, y, r] = c.HEAPF64.subarray((ptr + 16) >> 3, ((ptr + 16) >> 3) + 3);
    return { circle: { center: [x, y], radius: r } };
  }
  if (kind === SHAPE_KIND.segment) {
    const [ax, ay, bx, by] = c.HEAPF64.subarray((ptr + 40) >> 3, ((ptr + 40) >> 3) + 4);
    return { segment: [[ax, ay], [bx, by]] };
  }
  const vertices = c.HEAPU32[(ptr + 4) >> 2];
  const outline = c.HEAPU32[(ptr + 8) >> 2];
  const holeCounts = c.HEAPU32[(ptr + 72) >> 2];
  const holeCount = c.HEAPU32[(ptr + 76) >> 2];
  let k = vertices >> 3;
  const ring = (n) => {
    const points = [];
    for (let i = 0; i < n; ++i, k += 2) points.push([c.HEAPF64[k], c.HEAPF64[k + 1]]);
    return points;
  };
  const shape = { polygon: ring(outline) };
  if (holeCount) {
    shape.holes = [];
    for (let h = 0; h < holeCount; ++h) shape.holes.push(ring(c.HEAPU32[(holeCounts >> 2) + h]));
  }
  return shape;
}

/** The shape moved by (dx, dy). @param {Shape} shape @returns {Shape} */
export function translateShape(shape, dx, dy) {
  const move = ([x, y]) => [x + dx, y + dy];
  if ('circle' in shape) return { circle: { center: move(shape.circle.center), radius: shape.circle.radius } };
  if ('segment' in shape) return { segment: shape.segment.map(move) };
  const moved = { polygon: shape.polygon.map(move) };
  if (shape.holes) moved.holes = shape.holes.map((h) => h.map(move));
  return moved;
}

function removeTree(FS, path) {
  for (const entry of FS.readdir(path)) {
    if (entry === '.' || entry === '..') continue;
    const full = `${path}/${entry}`;
    if (FS.isDir(FS.stat(full).mode)) removeTree(FS, full);
    else FS.unlink(full);
  }
  FS.rmdir(path);
}

/** @typedef {{x0: number, y0: number, x1: number, y1: number}} Rect */
/** @typedef {{circle: {center: number[], radius: number}} | {segment: number[][]} | {polygon: number[][], holes?: number[][][]}} Shape */
