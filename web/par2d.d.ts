// Types of par2d.mjs: par2d's C API compiled to WebAssembly (docs/platforms.md,
// "WebAssembly and the playground"). One thread: a frame runs on the calling thread.

/** Pixel columns [x0, x1) and rows [y0, y1). */
export interface Rect { x0: number; y0: number; x1: number; y1: number }

/** A shape as the scene format writes it (docs/contract.md section 3), world coordinates, y down. */
export type Shape =
  | { circle: { center: [number, number]; radius: number } }
  | { segment: [[number, number], [number, number]] }
  | { polygon: [number, number][]; holes?: [number, number][][] };

/** A failed call: `message` is par2d's one-line error; a refused scene's names the file and the place. */
export class Par2dError extends Error {
  /** par2d_status: 1 invalid argument, 2 invalid scene, 3 I/O error, 4 out of memory, ... */
  status: number;
}

export interface Frame {
  /** The whole frame, RGBA8 sRGB (alpha 255), rows from the top: `new ImageData(pixels, width, height)`. */
  pixels: Uint8ClampedArray;
  width: number;
  height: number;
  /** What this render changed (the whole frame after a new scene or size): upload only these. */
  dirtyRects: Rect[];
  /** Wall time of the render call. */
  ms: number;
}

/** Loads the module: par2d_core.mjs next to par2d.mjs unless `core` names another (the scalar-only build). */
export function loadPar2d(options?: { core?: string | URL | (() => Promise<unknown>) }): Promise<Par2d>;

/** The shape moved by (dx, dy). */
export function translateShape(shape: Shape, dx: number, dy: number): Shape;

export class Par2d {
  /** The library version, "0.2.0". */
  readonly version: string;
  /** "sse4": the SSE4.2 kernel on SIMD128; "scalar": a module built without SIMD128. */
  readonly isa: 'sse4' | 'scalar';
  createRenderer(options?: { backend?: 'auto' | 'simd' | 'scalar'; spp?: number }): Renderer;
}

export class Renderer {
  /** The frame's size (0 x 0 before a scene or setFrame). */
  readonly width: number;
  readonly height: number;
  /** The last frame's pixels (the same array render returns). */
  readonly pixels: Uint8ClampedArray;
  /** The level frames run at. */
  readonly isa: 'sse4' | 'scalar';

  /**
   * Replaces the world with a scene given as JSON text. Throws Par2dError with the validator's
   * message (naming `name`, default "scene.json") and leaves the world as it was when refused.
   * `files`: files the scene names (its normal_map PNG), by path relative to the scene.
   */
  loadScene(json: string, options?: { name?: string; files?: Record<string, Uint8Array> }): void;
  /** width x height pixels showing the world rectangle view = [x0, y0, x1, y1] (default: 0, 0, width, height). */
  setFrame(width: number, height: number, view?: [number, number, number, number]): void;
  /** The 8-bit output shows clamp(exposure * E, 0, 1), sRGB-encoded (default 1). */
  setExposure(exposure: number): void;
  /** Caps the SIMD level: "scalar" runs the scalar path (as PAR2D_ISA=scalar). */
  setIsa(isa: 'default' | 'scalar' | 'sse4'): void;

  /** Renders incrementally: only blocks whose inputs changed are computed and copied. */
  render(options?: { full?: boolean }): Frame;
  /** The whole frame as linear float RGB, 3 floats per pixel (the irradiance, for comparisons). */
  renderLinear(): Float32Array;
  /** The rectangles the last render wrote. */
  dirtyRects(): Rect[];
  /** Pixels and 16x16 tiles the last render computed. */
  frameStats(): { pixels: number; tiles: number };

  /** Handles, a loaded scene's in the file's order, then those added. */
  lights(): bigint[];
  occluders(): bigint[];
  light(light: bigint): { shape: Shape; color: [number, number, number]; intensity: number };
  occluder(occluder: bigint): Shape;
  addLight(shape: Shape, color: [number, number, number], intensity: number): bigint;
  /** Changes what is given; the rest of the light (and its range, cone, mask, ...) stays. */
  updateLight(light: bigint, change: { shape?: Shape; color?: [number, number, number]; intensity?: number }): void;
  moveLight(light: bigint, dx: number, dy: number): void;
  removeLight(light: bigint): void;
  addOccluder(shape: Shape): bigint;
  updateOccluder(occluder: bigint, shape: Shape): void;
  moveOccluder(occluder: bigint, dx: number, dy: number): void;
  removeOccluder(occluder: bigint): void;

  /** The world as scene JSON (rendering it gives the same image). */
  snapshotJson(): string;
  /** Frees the renderer; it must not be used after. */
  dispose(): void;
}
