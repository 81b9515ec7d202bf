// The Foxglove WebSocket endpoint with Foxglove's own client (@foxglove/ws-protocol), against the
// real pslam-server with tokens and a simulated pslam-agent: both subprotocol names, channels of
// a session advertised when it starts and unadvertised when it closes, subscriptions, a grid whose
// cells are the session's map cell for cell (as the REST tile endpoint serves it), and bad client
// messages that get a status error while the server keeps serving.
import assert from 'node:assert/strict';
import { existsSync } from 'node:fs';
import { createRequire } from 'node:module';
import { join } from 'node:path';
import { after, before, describe, it } from 'node:test';
import { inflateSync } from 'node:zlib';
import { agentBinary, serverBinary, startAgent, startServer, stopChild, tempDir, waitFor, webDir } from './support.mjs';

const requireFromWeb = createRequire(join(webDir, 'package.json'));
const { FoxgloveClient } = requireFromWeb('@foxglove/ws-protocol');
const WebSocket = requireFromWeb('ws');

const missing = [serverBinary, agentBinary].filter((f) => !existsSync(f));
const skip = missing.length ? `missing ${missing.join(', ')} (build the project first)` : false;
const agentToken = 'agent-secret';
const viewerToken = 'viewer-secret';
const kTopics = {
  map: 'foxglove.Grid',
  robot: 'foxglove.PoseInFrame',
  scan: 'foxglove.LaserScan',
  trajectory: 'foxglove.PosesInFrame',
  particles: 'foxglove.PosesInFrame',
  tf: 'foxglove.FrameTransform',
  stats: 'pslam.Stats',
  exploration: 'foxglove.SceneUpdate',
  prediction: 'foxglove.Grid',
};

async function getJson(url, path) {
  const res = await fetch(`${url}${path}`, { headers: { Authorization: `Bearer ${viewerToken}` } });
  assert.equal(res.status, 200, `${path}: HTTP ${res.status}`);
  return res.json();
}

// A FoxgloveClient over a 'ws' socket offering 'protocols', with everything it hears recorded.
function connect(port, protocols, token = viewerToken) {
  const ws = new WebSocket(`ws://127.0.0.1:${port}/foxglove?token=${token}`, protocols);
  const client = new FoxgloveClient({ ws });
  const heard = { serverInfo: null, channels: new Map(), unadvertised: [], statuses: [], messages: [], closed: null };
  client.on('serverInfo', (info) => (heard.serverInfo = info));
  client.on('advertise', (channels) => channels.forEach((c) => heard.channels.set(c.id, c)));
  client.on('unadvertise', (ids) => heard.unadvertised.push(...ids));
  client.on('status', (s) => heard.statuses.push(s));
  client.on('message', (m) => heard.messages.push({ ...m, at: Date.now() }));
  client.on('close', (e) => (heard.closed = e));
  client.on('error', () => {});
  const opened = new Promise((resolve, reject) => {
    ws.once('open', resolve);
    ws.once('unexpected-response', (req, res) => reject(new Error(`HTTP ${res.statusCode}`)));
    ws.once('error', reject);
  });
  return { ws, client, heard, opened };
}

function channelOf(heard, sessionId, name) {
  return [...heard.channels.values()].find((c) => c.topic === `/${sessionId}/${name}`);
}

function payload(message) {
  return JSON.parse(Buffer.from(message.data.buffer, message.data.byteOffset, message.data.byteLength).toString('utf8'));
}

async function nextMessage(heard, subscriptionId, what, since = 0) {
  const found = await waitFor(what, () => heard.messages.find((m) => m.subscriptionId === subscriptionId && m.at >= since), { timeoutMs: 30000 });
  return payload(found);
}

async function statusAfter(heard, count, pattern) {
  const s = await waitFor(`a status matching ${pattern}`, () => heard.statuses.slice(count).find((x) => pattern.test(x.message)), { timeoutMs: 10000 });
  assert.equal(s.level, 2, JSON.stringify(s));
  return s;
}

// The session's map as the REST API serves it: cell (x, y) -> percent occupied, 255 unknown.
async function restCells(url, id) {
  const meta = await getJson(url, `/api/sessions/${id}/map`);
  const cells = new Map();
  const size = meta.tile_size;
  for (const t of meta.tiles) {
    const res = await fetch(`${url}/api/sessions/${id}/map/tiles/${t.x}/${t.y}`, { headers: { Authorization: `Bearer ${viewerToken}` } });
    assert.equal(res.status, 200);
    const frame = Buffer.from(await res.arrayBuffer());
    const raw = inflateSync(frame.subarray(24));
    for (let ly = 0; ly < size; ly++) {
      for (let lx = 0; lx < size; lx++) {
        const v = raw[ly * size + lx];
        if (v !== 255) cells.set(`${t.x * size + lx},${t.y * size + ly}`, v);
      }
    }
  }
  return { meta, cells };
}

describe('Foxglove WebSocket endpoint', { skip }, () => {
  let dir, server, agent, sessionId, early;

  before(async () => {
    dir = tempDir('pslam-foxglove-');
    server = await startServer({ dataDir: join(dir, 'data'), extraArgs: ['--agent-token', agentToken, '--viewer-token', viewerToken] });
    // Connected before any session runs: the session's channels must be advertised when it starts.
    early = connect(server.port, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
    await early.opened;
    agent = startAgent({ port: server.port, spoolDir: join(dir, 'spool'), source: 'sim:maze', name: 'foxglove test',
                         extraArgs: ['--rate', '2', '--token', agentToken, '--keep-session'] });
    const session = await waitFor('a running session with a few map tiles', async () => {
      const list = await getJson(server.url, '/api/sessions');
      const s = list.sessions?.find((x) => x.status === 'active');
      if (!s) return null;
      const meta = await getJson(server.url, `/api/sessions/${s.id}/map`);
      return meta.tiles.length >= 4 ? s : null;
    });
    sessionId = session.id;
  });

  after(async () => {
    early?.client.close();
    await agent?.stop();
    await server?.stop();
  });

  it('refuses a client without a token or without a subprotocol it speaks', async () => {
    await assert.rejects(connect(server.port, ['foxglove.sdk.v1'], 'wrong').opened, /HTTP 401/);
    await assert.rejects(connect(server.port, ['some.other.v1']).opened, /HTTP 400/);
  });

  it('counts against the viewer socket quota', async () => {
    const small = await startServer({ dataDir: join(dir, 'small'), extraArgs: ['--max-viewer-sockets', '1'] });
    try {
      const first = connect(small.port, ['foxglove.sdk.v1']);
      await first.opened;
      await waitFor('serverInfo', () => first.heard.serverInfo);
      const second = connect(small.port, ['foxglove.sdk.v1']);
      const closed = await waitFor('the second client refused', () => second.heard.closed);
      assert.equal(closed.code, 1013);
      assert.match(closed.reason.toString(), /too many viewer connections/);
      assert.equal(first.heard.closed, null);
      first.client.close();
    } finally {
      await small.stop();
    }
  });

  it('advertises a session that starts, with JSON channels in well-known schemas', async () => {
    const { heard, ws } = early;
    assert.equal(ws.protocol, 'foxglove.websocket.v1');
    await waitFor('serverInfo', () => heard.serverInfo);
    assert.equal(heard.serverInfo.name, 'pslam-server');
    await waitFor('the session advertised', () => channelOf(heard, sessionId, 'map'));
    for (const [name, schemaName] of Object.entries(kTopics)) {
      const c = channelOf(heard, sessionId, name);
      assert.ok(c, `channel ${name}`);
      assert.equal(c.encoding, 'json');
      assert.equal(c.schemaName, schemaName);
      assert.equal(c.schemaEncoding, 'jsonschema');
      assert.equal(JSON.parse(c.schema).type, 'object');
    }
  });

  it('streams the subscribed channels and stops a channel on unsubscribe', async () => {
    const { heard, client } = early;
    const robot = client.subscribe(channelOf(heard, sessionId, 'robot').id);
    const scan = client.subscribe(channelOf(heard, sessionId, 'scan').id);
    const tf = client.subscribe(channelOf(heard, sessionId, 'tf').id);
    const pose = await nextMessage(heard, robot, 'a robot pose');
    assert.equal(pose.frame_id, 'map');
    assert.equal(typeof pose.pose.position.x, 'number');
    assert.ok(Math.abs(pose.pose.orientation.z ** 2 + pose.pose.orientation.w ** 2 - 1) < 1e-3);
    const laser = await nextMessage(heard, scan, 'a laser scan');
    assert.ok(laser.ranges.length > 100, `${laser.ranges.length} beams`);
    assert.ok(laser.end_angle > laser.start_angle);
    const transform = await nextMessage(heard, tf, 'a transform');
    assert.equal(transform.parent_frame_id, 'map');
    assert.equal(transform.child_frame_id, `${sessionId}/base_link`);
    // Header fields as the spec has them: the client decoded them; the timestamp is the server's clock.
    const last = heard.messages.find((m) => m.subscriptionId === robot);
    assert.ok(Math.abs(Number(last.timestamp / 1000000n) - Date.now()) < 60000);

    client.unsubscribe(robot);
    await new Promise((r) => setTimeout(r, 500)); // what was already on the wire
    const cut = Date.now();
    await nextMessage(heard, scan, 'scans after the unsubscribe', cut + 1000);
    assert.equal(heard.messages.filter((m) => m.subscriptionId === robot && m.at > cut).length, 0);
  });

  it('sends the map as a grid equal to the REST map, cell for cell (subprotocol foxglove.sdk.v1)', async () => {
    // Freeze the map: the agent leaves, its session stays open and running.
    await agent.stop();
    let previous = '';
    await waitFor('the map to settle', async () => {
      const meta = await getJson(server.url, `/api/sessions/${sessionId}/map`);
      const now = JSON.stringify(meta.tiles);
      const settled = now === previous;
      previous = now;
      return settled;
    }, { intervalMs: 1500 });
    const { meta, cells } = await restCells(server.url, sessionId);

    const fox = connect(server.port, ['foxglove.sdk.v1']);
    await fox.opened;
    try {
      assert.equal(fox.ws.protocol, 'foxglove.sdk.v1');
      await waitFor('the map channel', () => channelOf(fox.heard, sessionId, 'map'));
      const sub = fox.client.subscribe(channelOf(fox.heard, sessionId, 'map').id);
      const grid = await nextMessage(fox.heard, sub, 'a grid');
      assert.equal(grid.frame_id, 'map');
      const data = Buffer.from(grid.data, 'base64');
      const field = (name) => grid.fields.find((f) => f.name === name);
      assert.deepEqual(['occupancy', 'red', 'green', 'blue', 'alpha'].map((n) => field(n)?.type), [1, 1, 1, 1, 1]);
      const rows = data.length / grid.row_stride;
      assert.equal(grid.row_stride, grid.column_count * grid.cell_stride);
      const factor = Math.round(grid.cell_size.x / meta.resolution);
      assert.ok(factor >= 1 && Math.abs(factor * meta.resolution - grid.cell_size.x) < 1e-9);
      const x0 = Math.round(grid.pose.position.x / meta.resolution);
      const y0 = Math.round(grid.pose.position.y / meta.resolution);
      // Every grid cell is its block's most occupied known cell (one cell when not coarsened).
      let known = 0, occupied = 0, mismatches = 0;
      for (let r = 0; r < rows; r++) {
        for (let c = 0; c < grid.column_count; c++) {
          let expected = -1;
          for (let y = y0 + r * factor; y < y0 + (r + 1) * factor; y++) {
            for (let x = x0 + c * factor; x < x0 + (c + 1) * factor; x++) {
              const v = cells.get(`${x},${y}`);
              if (v !== undefined) expected = Math.max(expected, v);
            }
          }
          if (expected < 0) expected = 255;
          const at = r * grid.row_stride + c * grid.cell_stride;
          const got = data[at + field('occupancy').offset];
          if (got !== expected) mismatches++;
          if (got !== 255) known++;
          if (got !== 255 && got > 65) occupied++;
          assert.equal(data[at + field('alpha').offset], got === 255 ? 0 : 255);
        }
      }
      assert.equal(mismatches, 0, `${mismatches} of ${rows * grid.column_count} cells differ`);
      // The grid spans every known cell.
      const span = rows * grid.column_count * factor * factor;
      assert.ok(known > 0 && occupied > 0 && span >= cells.size, `${known} known, ${occupied} occupied`);
    } finally {
      fox.client.close();
    }
  });

  it('answers bad client messages with a status error and keeps serving', async () => {
    const fox = connect(server.port, ['foxglove.websocket.v1']);
    await fox.opened;
    const { ws, heard, client } = fox;
    try {
      await waitFor('the channels', () => channelOf(heard, sessionId, 'stats'));
      let n = heard.statuses.length;
      ws.send(JSON.stringify({ op: 'frobnicate' }));
      await statusAfter(heard, n, /unknown op "frobnicate"/);
      n = heard.statuses.length;
      ws.send(JSON.stringify({ op: 'subscribe', subscriptions: [{ id: 5, channelId: 987654 }] }));
      await statusAfter(heard, n, /channel 987654 is not advertised/);
      n = heard.statuses.length;
      ws.send('{"op": "subscribe", "subscriptions": [');
      await statusAfter(heard, n, /malformed JSON/);
      n = heard.statuses.length;
      ws.send(JSON.stringify({ op: 'subscribe', subscriptions: [{ id: 1, channelId: 1 }], padding: 'x'.repeat(100 * 1024) }));
      await statusAfter(heard, n, /bytes refused/);
      n = heard.statuses.length;
      ws.send(JSON.stringify({ op: 'unsubscribe', subscriptionIds: [4242] }));
      await statusAfter(heard, n, /no subscription 4242/);
      n = heard.statuses.length;
      ws.send(JSON.stringify({ op: 'getParameters', parameterNames: [] }));
      await statusAfter(heard, n, /not supported/);
      n = heard.statuses.length;
      ws.send(Buffer.from([1, 0, 0, 0, 0, 42]));
      await statusAfter(heard, n, /binary messages are not accepted/);
      const twice = channelOf(heard, sessionId, 'stats').id;
      client.subscribe(twice);
      n = heard.statuses.length;
      ws.send(JSON.stringify({ op: 'subscribe', subscriptions: [{ id: 77, channelId: twice }] }));
      await statusAfter(heard, n, /already subscribed/);

      // Still serving this client: a valid subscription gets its channel's message.
      const sub = client.subscribe(channelOf(heard, sessionId, 'trajectory').id);
      const trajectory = await nextMessage(heard, sub, 'the trajectory');
      assert.ok(trajectory.poses.length > 10);
    // The prediction overlay: a grid in RGBA with Ψ (empty while nothing is pending).
    const overlay = await nextMessage(heard, client.subscribe(channelOf(heard, sessionId, 'prediction').id), 'the overlay');
    assert.equal(overlay.cell_stride, 5);
    assert.deepEqual(overlay.fields.map((f) => f.name), ['red', 'green', 'blue', 'alpha', 'psi']);
    assert.equal(overlay.row_stride, overlay.column_count * 5);
    assert.equal(Buffer.from(overlay.data, 'base64').length % Math.max(overlay.row_stride, 1), 0);
    } finally {
      client.close();
    }

    // A message past the read limit closes that socket (1009), and only that socket.
    const huge = connect(server.port, ['foxglove.websocket.v1']);
    await huge.opened;
    huge.ws.send('x'.repeat(300 * 1024));
    const closed = await waitFor('the oversized client closed', () => huge.heard.closed);
    assert.equal(closed.code, 1009);
    const again = connect(server.port, ['foxglove.sdk.v1']);
    await again.opened;
    try {
      await waitFor('serverInfo on a new connection', () => again.heard.serverInfo);
      await waitFor('the channels on a new connection', () => channelOf(again.heard, sessionId, 'map'));
    } finally {
      again.client.close();
    }
  });

  it('unadvertises the channels of a session that closes', async () => {
    const ids = Object.keys(kTopics).map((name) => channelOf(early.heard, sessionId, name).id);
    const res = await fetch(`${server.url}/api/sessions/${sessionId}/close`, { method: 'POST', headers: { Authorization: `Bearer ${agentToken}` } });
    assert.ok(res.status < 300, `close: HTTP ${res.status}`);
    await waitFor('the unadvertise', () => ids.every((id) => early.heard.unadvertised.includes(id)));
  });
});
