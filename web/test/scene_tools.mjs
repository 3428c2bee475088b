// Helpers of the node tests: a scene's e_max (docs/contract.md section 5), linear PFM files,
// and the files a scene names (its normal map) read for par2d.mjs's loadScene.
import fs from 'node:fs';
import path from 'node:path';

// A light's normalize factor: pi / asin(min(1, rho / normalize)), rho its radius (a segment's
// half length, a polygon's farthest vertex from the vertex mean); 1 without `normalize`.
function normalizeScale(light) {
  if (!light.normalize) return 1;
  let rho = 0;
  if (light.circle) rho = light.circle.radius;
  else if (light.segment) {
    const [[ax, ay], [bx, by]] = light.segment;
    rho = Math.hypot(bx - ax, by - ay) / 2;
  } else {
    const v = light.polygon;
    const mx = v.reduce((s, p) => s + p[0], 0) / v.length;
    const my = v.reduce((s, p) => s + p[1], 0) / v.length;
    for (const [x, y] of v) rho = Math.max(rho, Math.hypot(x - mx, y - my));
  }
  return Math.PI / Math.asin(Math.min(1, rho / light.normalize));
}

/** e_max: each light's largest emission channel summed, the directional lights' and the ambient's. */
export function emissionMax(scene) {
  let sum = 0;
  for (const l of scene.lights ?? []) sum += l.intensity * Math.max(...l.color) * normalizeScale(l);
  for (const d of scene.directional_lights ?? []) sum += d.intensity * Math.max(...d.color);
  return sum + (scene.ambient ? Math.max(...scene.ambient) : 0);
}

/** Writes width x height RGB floats (rows from the top) as a little-endian PFM (rows from the bottom). */
export function writePfm(file, width, height, rgb) {
  const header = Buffer.from(`PF\n${width} ${height}\n-1.0\n`, 'ascii');
  const body = Buffer.alloc(width * height * 12);
  for (let y = 0; y < height; ++y) {
    const row = Buffer.from(rgb.buffer, rgb.byteOffset + y * width * 12, width * 12);
    row.copy(body, (height - 1 - y) * width * 12);
  }
  fs.writeFileSync(file, Buffer.concat([header, body]));
}

/** The files `scene` names relative to its folder (its normal_map), as loadScene's `files`. */
export function sceneFiles(scene, folder) {
  const files = {};
  if (typeof scene.normal_map === 'string') files[scene.normal_map] = fs.readFileSync(path.join(folder, scene.normal_map));
  return files;
}
