// Converts the npm package `bunny` (positions + cells) to a Wavefront OBJ with
// area-weighted vertex normals. Run once by hand; nothing runs it at build time:
//   cd /tmp && npm pack bunny && tar xzf bunny-1.0.1.tgz
//   node models/tools/bunny_to_obj.js /tmp/package/index.js > models/bunny.obj
// Faces keep the package's winding; the script flips them if the signed volume
// is negative so that counter-clockwise (seen from outside) faces point out.
"use strict";
const bunny = require(require("path").resolve(process.argv[2]));
const p = bunny.positions;
let cells = bunny.cells.map((c) => c.slice());
const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
let vol = 0;
for (const [a, b, c] of cells) vol += dot(p[a], cross(p[b], p[c])) / 6;
if (vol < 0) cells = cells.map(([a, b, c]) => [a, c, b]);
const n = p.map(() => [0, 0, 0]);
for (const [a, b, c] of cells) {
  const fn = cross(sub(p[b], p[a]), sub(p[c], p[a])); // length = 2 * area
  for (const i of [a, b, c]) for (let k = 0; k < 3; k++) n[i][k] += fn[k];
}
const f = (x) => Number(x.toFixed(6)).toString();
const out = [];
out.push("# Stanford bunny (Stanford 3D Scanning Repository), via npm package bunny@1.0.1.");
out.push("# See models/LICENSES.md. " + p.length + " vertices, " + cells.length + " triangles.");
out.push("# |signed volume| = " + Math.abs(vol).toFixed(3) + "; faces counter-clockwise seen from outside.");
for (const v of p) out.push("v " + v.map(f).join(" "));
for (const v of n) {
  const len = Math.hypot(v[0], v[1], v[2]) || 1;
  out.push("vn " + v.map((x) => f(x / len)).join(" "));
}
for (const [a, b, c] of cells) out.push(`f ${a + 1}//${a + 1} ${b + 1}//${b + 1} ${c + 1}//${c + 1}`);
process.stdout.write(out.join("\n") + "\n");
