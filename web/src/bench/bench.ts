// Browser benchmark of the map path (tests/web/bench_tiles.mjs loads this page and prints the
// result): a 2000 x 2000-cell map in 64 x 64 tiles, as the server sends them.
//  1. Initial load: every tile frame decoded, stored and uploaded.
//  2. Tile updates: one changed tile at a time, timed from the frame's arrival to the pixels being
//     in the layer's canvas (inflate + checksum + store + palette + putImageData).
//  3. Pan and zoom: frames drawn on requestAnimationFrame while the camera moves, with and without
//     tiles streaming in.
import { zlibSync } from 'fflate';
import { encodeTileFrame, type Tile } from '../net/protocol';
import { SessionClient } from '../net/session_client';
import { MapLayer } from '../render/map_layer';
import { buildMapPalette } from '../render/palette';
import { Viewer } from '../render/viewer';

const kCells = 2000;
const kTile = 64;
const kTiles = Math.ceil(kCells / kTile); // 32 x 32 tiles

// An office-like world: walls on a 4 m grid with doors, a few pillars, noise in free space.
function cellValue(x: number, y: number, rng: () => number): number {
  if (x >= kCells || y >= kCells) return 255;
  const gx = x % 80, gy = y % 80;
  const wall = (gx < 2 && (y % 80 < 30 || y % 80 > 45)) || (gy < 2 && (x % 80 < 35 || x % 80 > 50));
  if (wall) return 95 + Math.floor(rng() * 5);
  if ((x - 40) % 160 < 4 && (y - 40) % 160 < 4) return 90;
  const r = rng();
  return r < 0.02 ? 255 : Math.floor(r * 12);
}

function makeRng(seed: number): () => number {
  let s = seed >>> 0;
  return () => {
    s = (s * 1664525 + 1013904223) >>> 0;
    return s / 2 ** 32;
  };
}

function makeTile(tx: number, ty: number, revision: number, rng: () => number): Tile {
  const cells = new Uint8Array(kTile * kTile);
  for (let r = 0; r < kTile; r++) for (let c = 0; c < kTile; c++) cells[r * kTile + c] = cellValue(tx * kTile + c, ty * kTile + r, rng);
  return { tx, ty, size: kTile, revision, cells };
}

const zlib = (d: Uint8Array) => zlibSync(d, { level: 6 });

function summary(samples: number[]): { mean: number; p50: number; p95: number; p99: number; max: number; n: number } {
  const s = [...samples].sort((a, b) => a - b);
  const at = (q: number) => s[Math.min(s.length - 1, Math.floor(q * s.length))];
  return { mean: s.reduce((a, b) => a + b, 0) / s.length, p50: at(0.5), p95: at(0.95), p99: at(0.99), max: s[s.length - 1], n: s.length };
}

function nextFrame(): Promise<number> {
  return new Promise((resolve) => requestAnimationFrame(resolve));
}

async function run(): Promise<object> {
  const host = document.getElementById('view')!;
  const client = new SessionClient('bench', undefined, false);
  const viewer = new Viewer(host);
  const layer = new MapLayer(client.map, buildMapPalette());
  viewer.addLayer(layer);
  viewer.fitBox = () => ({ minX: 0, minY: 0, maxX: kCells * 0.05, maxY: kCells * 0.05 });
  const rng = makeRng(7);

  // 1. Initial load.
  const frames: Uint8Array[] = [];
  for (let ty = 0; ty < kTiles; ty++) for (let tx = 0; tx < kTiles; tx++) frames.push(encodeTileFrame(makeTile(tx, ty, 1, rng), zlib));
  const payloadBytes = frames.reduce((a, f) => a + f.length, 0);
  client.handle({ type: 'snapshot', session_id: 'bench', status: 'active', resolution: 0.05, tile_size: kTile, tile_count: frames.length, pose: null, trajectory: { first_index: 0, poses: [] }, particles: [], hypotheses: [], frontiers: [], target: null, stats: {} });
  let t0 = performance.now();
  for (const f of frames) client.handleTile(f);
  const decodeAll = performance.now() - t0;
  t0 = performance.now();
  layer.collect();
  layer.upload();
  const uploadAll = performance.now() - t0;
  viewer.fit();
  await nextFrame();
  viewer.drawNow();

  // 2. Single-tile updates (frames prepared up front: the server compresses, not the viewer).
  const updates: Uint8Array[] = [];
  for (let i = 0; i < 256; i++) {
    const tx = Math.floor(rng() * kTiles), ty = Math.floor(rng() * kTiles);
    const t = makeTile(tx, ty, 2 + i, rng);
    for (let k = 0; k < 200; k++) t.cells[Math.floor(rng() * t.cells.length)] = Math.floor(rng() * 101);
    updates.push(encodeTileFrame(t, zlib));
  }
  const tileUpdate: number[] = [];
  const decodeOnly: number[] = [];
  for (let i = 0; i < 2000; i++) {
    const f = updates[i % updates.length];
    const a = performance.now();
    client.handleTile(f);
    const b = performance.now();
    layer.collect();
    layer.upload();
    const c = performance.now();
    decodeOnly.push(b - a);
    tileUpdate.push(c - a);
  }
  // Include the GPU/raster flush: draw one frame after a burst of updates.
  viewer.drawNow();

  // 3. Pan and zoom on requestAnimationFrame.
  const animate = async (count: number, tilesPerFrame: number) => {
    viewer.resetFrameStats();
    const intervals: number[] = [];
    const draws: number[] = [];
    const rasters: number[] = [];
    viewer.fit();
    const base = viewer.camera.scale;
    let last = await nextFrame();
    for (let i = 0; i < count; i++) {
      const t = i / count;
      // Zoom between the whole map and 12x, while circling around the centre.
      viewer.camera.scale = base * Math.exp(Math.log(12) * (0.5 - 0.5 * Math.cos(2 * Math.PI * t * 2)));
      viewer.camera.centerX = 50 + 30 * Math.cos(2 * Math.PI * t);
      viewer.camera.centerY = 50 + 30 * Math.sin(2 * Math.PI * t);
      for (let k = 0; k < tilesPerFrame; k++) client.handleTile(updates[(i * tilesPerFrame + k) % updates.length]);
      draws.push(viewer.drawNow());
      // Reading a pixel makes the canvas rasterise now, so this times the real drawing work
      // (drawNow alone only records the commands).
      const r0 = performance.now();
      viewer.canvas.getContext('2d')!.getImageData(0, 0, 1, 1);
      rasters.push(draws[draws.length - 1] + performance.now() - r0);
      const now = await nextFrame();
      intervals.push(now - last);
      last = now;
    }
    const iv = summary(intervals);
    return { frames: count, draw: summary(draws), drawAndRaster: summary(rasters), interval: iv, fps: 1000 / iv.mean };
  };
  // Baseline: the browser's own frame pacing with nothing drawn.
  const idle: number[] = [];
  let prev = await nextFrame();
  for (let i = 0; i < 120; i++) {
    const now = await nextFrame();
    idle.push(now - prev);
    prev = now;
  }
  const panZoom = await animate(300, 0);
  const panZoomStreaming = await animate(300, 10);
  viewer.fit();
  viewer.drawNow();
  return {
    map: { cells: `${kCells} x ${kCells}`, tiles: frames.length, payloadKiB: Math.round(payloadBytes / 1024) },
    initialLoad: { decodeAndStoreMs: decodeAll, uploadMs: uploadAll },
    tileUpdate: summary(tileUpdate),
    tileDecodeAndStore: summary(decodeOnly),
    idleFrameInterval: summary(idle),
    panZoom,
    panZoomStreaming10TilesPerFrame: panZoomStreaming,
    userAgent: navigator.userAgent,
  };
}

run().then(
  (result) => {
    (window as unknown as { benchResult: object }).benchResult = result;
    document.getElementById('out')!.textContent = JSON.stringify(result, (_k, v) => (typeof v === 'number' ? Math.round(v * 1000) / 1000 : v), 2);
  },
  (e: Error) => {
    (window as unknown as { benchResult: object }).benchResult = { error: e.message, stack: e.stack };
    document.getElementById('out')!.textContent = `error: ${e.stack}`;
  },
);
