// What the Foxglove endpoint costs on the wire against the live view's deltas: the real
// pslam-server and pslam-agent replaying the Intel log at its own rate (or PSLAM_BENCH_RATE), one
// /live viewer and Foxglove clients (@foxglove/ws-protocol) subscribed to every channel of the
// session. Prints bytes per second by channel and the filter's scan rate, and writes them to
// tests/web/artifacts/foxglove-bench.json.
// Run: node tests/web/bench_foxglove.mjs [--scans N] [--clients N]   (after building the binaries)
import { existsSync, writeFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { join } from 'node:path';
import { agentBinary, ensureArtifacts, repoRoot, serverBinary, startAgent, startServer, tempDir, waitFor, webDir } from './support.mjs';

const requireFromWeb = createRequire(join(webDir, 'package.json'));
const { FoxgloveClient } = requireFromWeb('@foxglove/ws-protocol');
const WebSocket = requireFromWeb('ws');

const arg = (name, fallback) => {
  const i = process.argv.indexOf(name);
  return i > 0 ? process.argv[i + 1] : fallback;
};
const scans = Number(arg('--scans', '1500'));
const clients = Number(arg('--clients', '1'));
const rate = process.env.PSLAM_BENCH_RATE ?? '1';
const log = join(repoRoot, '..', 'shared', 'data', 'intel', 'intel.clf');
for (const f of [serverBinary, agentBinary, log]) {
  if (!existsSync(f)) {
    console.error(`missing ${f}`);
    process.exit(2);
  }
}
// WebSocket wire bytes of a server message of 'n' payload bytes (unmasked header).
const wire = (n) => n + (n < 126 ? 2 : n < 65536 ? 4 : 10);

const dir = tempDir('pslam-foxglove-bench-');
const server = await startServer({ dataDir: join(dir, 'data') });
const agent = startAgent({ port: server.port, spoolDir: join(dir, 'spool'), source: `log:${log}`, name: 'foxglove bench',
                           extraArgs: ['--rate', rate, '--max-scans', String(scans), '--no-drive'] });
const session = await waitFor('the session', async () => {
  const list = await (await fetch(`${server.url}/api/sessions`)).json();
  return list.sessions?.find((s) => s.status === 'active');
});

// The live viewer: bytes after its snapshot, by kind.
const live = { start: 0, bytes: 0, tiles: 0, snapshotLeft: -1 };
const viewer = new WebSocket(`ws://127.0.0.1:${server.port}/api/sessions/${session.id}/live`);
viewer.on('message', (data, binary) => {
  if (live.snapshotLeft < 0) {
    live.snapshotLeft = JSON.parse(data.toString()).tile_count;
    return;
  }
  if (live.snapshotLeft > 0) {
    if (--live.snapshotLeft === 0) live.start = Date.now();
    return;
  }
  if (!live.start) live.start = Date.now();
  live.bytes += wire(data.length);
  if (binary && data.subarray(0, 4).toString() === 'PSTL') live.tiles += wire(data.length);
});

// Foxglove clients subscribed to every channel of the session; the first one counts.
const counted = { start: 0, byTopic: {}, messages: {} };
const sockets = [];
for (let i = 0; i < clients; i++) {
  const ws = new WebSocket(`ws://127.0.0.1:${server.port}/foxglove`, ['foxglove.sdk.v1']);
  const client = new FoxgloveClient({ ws });
  const topics = new Map();
  client.on('advertise', (channels) => {
    for (const c of channels) {
      if (!c.topic.startsWith(`/${session.id}/`)) continue;
      topics.set(client.subscribe(c.id), c.topic.split('/').pop());
    }
  });
  if (i === 0) {
    client.on('message', (m) => {
      if (!counted.start) counted.start = Date.now();
      const topic = topics.get(m.subscriptionId);
      counted.byTopic[topic] = (counted.byTopic[topic] ?? 0) + wire(13 + m.data.byteLength);
      counted.messages[topic] = (counted.messages[topic] ?? 0) + 1;
    });
  }
  client.on('error', () => {});
  sockets.push(client);
}

const rates = [];
const poll = setInterval(async () => {
  try {
    const s = await (await fetch(`${server.url}/api/sessions/${session.id}/stats`)).json();
    if (s.filter?.scan_rate_hz > 0) rates.push(s.filter.scan_rate_hz);
  } catch {}
}, 1000);
await new Promise((resolve) => agent.child.once('exit', resolve));
const end = Date.now();
clearInterval(poll);
const meta = await (await fetch(`${server.url}/api/sessions/${session.id}/map`)).json();
sockets.forEach((c) => c.close());
viewer.close();
await server.stop();

const seconds = (start) => (end - start) / 1000;
const perSecond = (bytes, start) => bytes / seconds(start);
const rows = Object.keys(counted.byTopic).sort().map((t) => ({
  topic: t,
  bytes_per_s: perSecond(counted.byTopic[t], counted.start),
  messages_per_s: counted.messages[t] / seconds(counted.start),
}));
const total = Object.values(counted.byTopic).reduce((a, b) => a + b, 0);
rates.sort((a, b) => a - b);
const result = {
  scans, rate, clients, wall_s: seconds(counted.start),
  map_image: meta.image, resolution: meta.resolution,
  foxglove: { by_topic: rows, total_bytes_per_s: perSecond(total, counted.start) },
  live_view: { delta_bytes_per_s: perSecond(live.bytes, live.start), tile_bytes_per_s: perSecond(live.tiles, live.start) },
  scan_rate_hz_median: rates.length ? rates[Math.floor(rates.length / 2)] : null,
};
writeFileSync(join(ensureArtifacts(), `foxglove-bench-${clients}.json`), JSON.stringify(result, null, 2));
const kib = (v) => `${(v / 1024).toFixed(1)} KiB/s`;
console.log(`${scans} scans at rate ${rate}, ${clients} Foxglove client(s), ${result.wall_s.toFixed(0)} s; map ${meta.image.width}x${meta.image.height} cells at ${meta.resolution} m`);
for (const r of rows) console.log(`  foxglove ${r.topic}: ${kib(r.bytes_per_s)} (${r.messages_per_s.toFixed(2)} msg/s)`);
console.log(`  foxglove total: ${kib(result.foxglove.total_bytes_per_s)}`);
console.log(`  live view deltas: ${kib(result.live_view.delta_bytes_per_s)}, of which tiles ${kib(result.live_view.tile_bytes_per_s)}`);
console.log(`  filter scan rate (median of /stats): ${result.scan_rate_hz_median} Hz`);
