// Regenerates the bundled models (data/models/NOTICE.md):
//   npm pack bunny@1.0.1 teapot@1.0.0, unpack each into ./bunny and ./teapot, then
//   node make_models.js BUNNY_DIR TEAPOT_DIR
// bunny.ply and teapot.ply are binary little-endian PLY (float32 x y z, uchar/int32 face
// lists) holding exactly the packages' positions and cells; chair.obj is generated here.
'use strict';
const fs = require('fs');
const path = require('path');

// Binary PLY: float32 keeps the packages' 6-digit coordinates exactly enough and halves
// the size against double.
function writePly(file, positions, cells, comment) {
  const header = 'ply\nformat binary_little_endian 1.0\n' + `comment ${comment}\n` +
      `element vertex ${positions.length}\nproperty float x\nproperty float y\n` +
      `property float z\nelement face ${cells.length}\n` +
      'property list uchar int vertex_indices\nend_header\n';
  const body = Buffer.alloc(positions.length * 12 + cells.length * 13);
  let o = 0;
  for (const p of positions) {
    for (let k = 0; k < 3; ++k) { body.writeFloatLE(p[k], o); o += 4; }
  }
  for (const c of cells) {
    if (c.length !== 3) throw new Error('non-triangle cell');
    body.writeUInt8(3, o++);
    for (const i of c) { body.writeInt32LE(i, o); o += 4; }
  }
  fs.writeFileSync(file, Buffer.concat([Buffer.from(header, 'ascii'), body]));
}

// The chair of apps/synth_trace.cpp without its ball: 0.48 m square seat at 0.45 m,
// four legs and two back posts as octagonal prisms, a back rest and two stretchers as
// boxes. Metres, y up, the back towards +z, footprint centred on the origin.
function makeChair() {
  const v = [], f = [];
  const box = (lo, hi) => {
    const b = v.length;
    for (let i = 0; i < 8; ++i) {
      v.push([i & 1 ? hi[0] : lo[0], i & 2 ? hi[1] : lo[1], i & 4 ? hi[2] : lo[2]]);
    }
    // Counter-clockwise seen from outside.
    const quads = [[0, 4, 6, 2], [1, 3, 7, 5], [0, 1, 5, 4], [2, 6, 7, 3], [0, 2, 3, 1],
                   [4, 5, 7, 6]];
    for (const q of quads) f.push(q.map((i) => b + i));
  };
  const prism = (cx, cz, r, y0, y1, n) => {
    const b = v.length;
    for (let i = 0; i < n; ++i) {
      const a = (2 * Math.PI * (i + 0.5)) / n;
      v.push([cx + r * Math.cos(a), y0, cz - r * Math.sin(a)]);
      v.push([cx + r * Math.cos(a), y1, cz - r * Math.sin(a)]);
    }
    for (let i = 0; i < n; ++i) {
      const j = (i + 1) % n;
      f.push([b + 2 * i, b + 2 * j, b + 2 * j + 1, b + 2 * i + 1]);
    }
    f.push([...Array(n).keys()].reverse().map((i) => b + 2 * i));  // bottom cap
    f.push([...Array(n).keys()].map((i) => b + 2 * i + 1));        // top cap
  };
  const half = 0.24, legR = 0.025, seatY = 0.45, seatT = 0.05, inset = half - legR - 0.01;
  for (const sx of [-1, 1]) {
    for (const sz of [-1, 1]) prism(sx * inset, sz * inset, legR, 0, seatY, 8);
  }
  box([-half, seatY, -half], [half, seatY + seatT, half]);
  for (const sx of [-1, 1]) prism(sx * inset, inset, legR, seatY + seatT, 0.95, 8);
  box([-half + 0.02, 0.72, half - 0.06], [half - 0.02, 0.95, half - 0.02]);
  for (const sx of [-1, 1]) {
    box([sx * inset - 0.012, 0.15, -inset], [sx * inset + 0.012, 0.18, inset]);
  }
  const lines = ['# Penumbra showroom chair (data/models/make_models.js): metres, y up,',
                 '# back towards +z, quads and octagons (loaders triangulate as fans).'];
  for (const p of v) lines.push('v ' + p.map((x) => +x.toFixed(6)).join(' '));
  for (const q of f) lines.push('f ' + q.map((i) => i + 1).join(' '));
  fs.writeFileSync(path.join(__dirname, 'chair.obj'), lines.join('\n') + '\n');
}

const [bunnyDir, teapotDir] = process.argv.slice(2);
if (!bunnyDir || !teapotDir) {
  console.error('usage: node make_models.js BUNNY_PACKAGE_DIR TEAPOT_PACKAGE_DIR');
  process.exit(2);
}
const bunny = require(path.resolve(bunnyDir, 'index.js'));
writePly(path.join(__dirname, 'bunny.ply'), bunny.positions, bunny.cells,
         'Stanford bunny via npm bunny@1.0.1 (see NOTICE.md)');
const teapot = require(path.resolve(teapotDir, 'teapot.js'));
writePly(path.join(__dirname, 'teapot.ply'), teapot.positions, teapot.cells,
         'Utah teapot (Martin Newell 1975) via npm teapot@1.0.0 (see NOTICE.md)');
makeChair();
