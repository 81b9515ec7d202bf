// Benchmark of the viewer's map path in Debian's chromium (headless): a 2000 x 2000-cell map,
// tile updates and pan/zoom frames. Prints the figures; fails if a tile update takes more than
// 2 ms on average. Run: npm --prefix web run bench (after npm run build).
import { existsSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { distDir, ensureArtifacts, launchBrowser, serveDist, waitFor } from './support.mjs';

if (!existsSync(join(distDir, 'bench.html'))) {
  console.error('web/dist/bench.html is missing: run `npm run build` in web/ first');
  process.exit(2);
}
const site = await serveDist();
const { context, close } = await launchBrowser();
let failed = false;
try {
  const page = await context.newPage();
  page.on('pageerror', (e) => console.error('page error:', e.message));
  await page.goto(`${site.url}/bench.html`);
  const result = await waitFor('the benchmark', () => page.evaluate(() => window.benchResult), { timeoutMs: 240000, intervalMs: 500 });
  if (result.error) throw new Error(result.stack ?? result.error);
  const dir = ensureArtifacts();
  writeFileSync(join(dir, 'bench.json'), JSON.stringify(result, null, 2));
  await page.screenshot({ path: join(dir, 'bench.png') });
  const f = (v) => v.toFixed(3);
  const t = result.tileUpdate;
  console.log(`map: ${result.map.cells} cells, ${result.map.tiles} tiles, ${result.map.payloadKiB} KiB compressed`);
  console.log(`initial load: decode+store ${f(result.initialLoad.decodeAndStoreMs)} ms, upload ${f(result.initialLoad.uploadMs)} ms`);
  console.log(`tile update (inflate+check+store+palette+putImageData): mean ${f(t.mean)} ms, p50 ${f(t.p50)}, p95 ${f(t.p95)}, p99 ${f(t.p99)}, max ${f(t.max)} (n=${t.n})`);
  console.log(`  of which decode+store: mean ${f(result.tileDecodeAndStore.mean)} ms`);
  const idle = result.idleFrameInterval;
  console.log(`browser frame pacing with nothing drawn: interval mean ${f(idle.mean)} ms, p95 ${f(idle.p95)} → ${(1000 / idle.mean).toFixed(1)} fps`);
  for (const [name, r] of [['pan/zoom', result.panZoom], ['pan/zoom + 10 tiles/frame', result.panZoomStreaming10TilesPerFrame]]) {
    console.log(`${name}: draw (commands) mean ${f(r.draw.mean)} ms, p95 ${f(r.draw.p95)}; draw + raster mean ${f(r.drawAndRaster.mean)} ms, p95 ${f(r.drawAndRaster.p95)}, max ${f(r.drawAndRaster.max)}; frame interval mean ${f(r.interval.mean)} ms, p95 ${f(r.interval.p95)} → ${r.fps.toFixed(1)} fps`);
  }
  if (t.mean > 2) {
    console.error(`FAIL: a tile update takes ${f(t.mean)} ms on average (budget 2 ms)`);
    failed = true;
  }
} finally {
  await close();
  await site.close();
}
process.exit(failed ? 1 : 0);
