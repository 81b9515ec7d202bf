// The main job as an operator runs it, with the real pslam-server, pslam-agent (simulator) and
// Chromium: exploration runs to an end the viewer announces, a second start of the agent opens a
// clean session (the first closed, no jump in either trajectory), a log replay starts from the
// replay directory's file list, and the agent names each target once.
//
// The exploration runs in a small world this test draws (14 m x 9 m: a loop around two rooms) at
// PSLAM_EXPLORE_RATE (8) times real time; PSLAM_EXPLORE_WORLD=maze (or office, irregular) runs a
// shipped world instead (the maze takes about three minutes).
import assert from 'node:assert/strict';
import { copyFileSync, existsSync, mkdirSync, readFileSync, writeFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { after, before, describe, it } from 'node:test';
import {
  agentBinary,
  distDir,
  ensureArtifacts,
  launchBrowser,
  repoRoot,
  serverBinary,
  startAgent,
  startServer,
  stopChild,
  tempDir,
  waitFor,
} from './support.mjs';

const missing = [serverBinary, agentBinary, join(distDir, 'index.html')].filter((f) => !existsSync(f));
const skip = missing.length ? `missing ${missing.join(', ')} (build the project and web/ first)` : false;
const world = process.env.PSLAM_EXPLORE_WORLD ?? 'small';
// Simulated seconds per wall second: at 8 the server keeps up on two cores.
const rate = process.env.PSLAM_EXPLORE_RATE ?? '8';
const intelLog = join(repoRoot, '..', 'shared', 'data', 'intel', 'intel.clf');

async function getJson(url, init) {
  const res = await fetch(url, init);
  assert.equal(res.status, 200, `${url}: HTTP ${res.status}`);
  return res.json();
}

// Writes the small world into DIR as map_server files and returns the YAML's path: 14 m x 9 m
// inside 0.15 m walls, and a 8 m x 3 m block in the middle holding two rooms, each with a 1 m door
// onto the loop around it.
function writeSmallWorld(dir) {
  const resolution = 0.05, width = 296, height = 196;  // the interior starts 0.2 m in
  const pixels = new Uint8Array(width * height);  // 0: wall
  const fill = (x0, y0, x1, y1, value) => {  // metres, interior frame
    for (let y = Math.round((y0 + 0.2) / resolution); y < Math.round((y1 + 0.2) / resolution); y++) {
      for (let x = Math.round((x0 + 0.2) / resolution); x < Math.round((x1 + 0.2) / resolution); x++) {
        pixels[(height - 1 - y) * width + x] = value;
      }
    }
  };
  fill(0, 0, 14, 9, 254);
  fill(3, 3, 11, 6, 0);
  fill(3.15, 3.15, 6.925, 5.85, 254);
  fill(7.075, 3.15, 10.85, 5.85, 254);
  fill(4.5, 3, 5.5, 3.15, 254);
  fill(8.5, 3, 9.5, 3.15, 254);
  writeFileSync(join(dir, 'small.pgm'), Buffer.concat([Buffer.from(`P5\n${width} ${height}\n255\n`), pixels]));
  const yaml = join(dir, 'small.yaml');
  writeFileSync(yaml, ['image: small.pgm', `resolution: ${resolution}`, 'origin: [-0.2, -0.2, 0.0]', 'negate: 0',
    'occupied_thresh: 0.65', 'free_thresh: 0.196', 'mode: trinary', '# world: a loop around two rooms, 14 m x 9 m',
    '# start: 1.5, 1.5, 0', ''].join('\n'));
  return yaml;
}

// The free area (m²) the robot can reach in a world: free pixels of its image connected
// (4-neighbours) to the start pose named in its YAML.
function reachableFreeArea(yamlPath) {
  const yaml = readFileSync(yamlPath, 'utf8');
  const resolution = Number(/resolution:\s*([\d.]+)/.exec(yaml)[1]);
  const origin = /origin:\s*\[\s*([-\d.]+),\s*([-\d.]+)/.exec(yaml).slice(1).map(Number);
  const start = /#\s*start:\s*([-\d.]+),\s*([-\d.]+)/.exec(yaml).slice(1).map(Number);
  const pgm = readFileSync(join(dirname(yamlPath), /image:\s*(\S+)/.exec(yaml)[1]));
  // Header: P5, comments, width height, maxval, then one byte per pixel, top row first.
  const fields = [];
  let i = 0;
  while (fields.length < 4) {
    while (/\s/.test(String.fromCharCode(pgm[i]))) i++;
    if (pgm[i] === 0x23) {
      while (pgm[i] !== 0x0a) i++;
      continue;
    }
    let token = '';
    while (!/\s/.test(String.fromCharCode(pgm[i]))) token += String.fromCharCode(pgm[i++]);
    fields.push(token);
  }
  const [width, height] = [Number(fields[1]), Number(fields[2])];
  const pixels = pgm.subarray(i + 1);
  const free = (x, y) => pixels[(height - 1 - y) * width + x] >= 250;
  const sx = Math.floor((start[0] - origin[0]) / resolution);
  const sy = Math.floor((start[1] - origin[1]) / resolution);
  const seen = new Uint8Array(width * height);
  const stack = [[sx, sy]];
  seen[sy * width + sx] = 1;
  let count = 0;
  while (stack.length) {
    const [x, y] = stack.pop();
    count++;
    for (const [nx, ny] of [[x + 1, y], [x - 1, y], [x, y + 1], [x, y - 1]]) {
      if (nx < 0 || ny < 0 || nx >= width || ny >= height || seen[ny * width + nx] || !free(nx, ny)) continue;
      seen[ny * width + nx] = 1;
      stack.push([nx, ny]);
    }
  }
  return count * resolution * resolution;
}

// The largest distance between consecutive poses of a session's trajectory.
async function maxStep(url, id) {
  const { poses } = await getJson(`${url}/api/sessions/${id}/trajectory?limit=1000000`);
  let max = 0;
  for (let i = 1; i < poses.length; i++) max = Math.max(max, Math.hypot(poses[i].x - poses[i - 1].x, poses[i].y - poses[i - 1].y));
  return { max, poses: poses.length };
}

function exited(child) {
  return child.exitCode !== null || child.signalCode !== null
    ? Promise.resolve(child.exitCode)
    : new Promise((r) => child.once('exit', (code) => r(code)));
}

describe('the main job, as an operator runs it', { skip }, () => {
  let dir, server, browser, page, artifacts;
  const agents = [];

  before(async () => {
    artifacts = ensureArtifacts();
    dir = tempDir('pslam-ops-test-');
    const replays = join(dir, 'replays');
    mkdirSync(join(replays, 'intel'), { recursive: true });
    if (existsSync(intelLog)) {
      // The first 300 laser lines of the Intel log (and the odometry among them): a replay of seconds.
      const lines = readFileSync(intelLog, 'utf8').split('\n');
      const slice = [];
      let lasers = 0;
      for (const line of lines) {
        if (lasers >= 300) break;
        slice.push(line);
        if (line.startsWith('FLASER')) lasers++;
      }
      writeFileSync(join(replays, 'intel', 'intel-slice.clf'), `${slice.join('\n')}\n`);
    }
    server = await startServer({
      dataDir: join(dir, 'data'),
      extraArgs: ['--predict', 'on', '--particles', '10', '--checkpoint-seconds', '1', '--replay-dir', replays],
    });
    browser = await launchBrowser();
    page = await browser.context.newPage();
  });

  after(async () => {
    await browser?.close();
    for (const a of agents) await a.stop();
    await server?.stop();
  });

  it('closes the session when the agent stops, and the next start opens a clean one', async () => {
    const spool = join(dir, 'spool-restart');
    const runOnce = async (minScans) => {
      const agent = startAgent({ port: server.port, spoolDir: spool, source: 'sim:maze', name: 'restart', extraArgs: ['--rate', '4'] });
      agents.push(agent);
      const id = await waitFor('the agent session', async () => {
        const { sessions } = await getJson(`${server.url}/api/sessions?status=active`);
        const s = sessions.find((x) => x.name === 'restart' && x.scans >= minScans);
        return s?.id;
      });
      // Ctrl-C as deploy/run.sh passes it on: the agent alone, first.
      agent.child.kill('SIGINT');
      assert.equal(await exited(agent.child), 0, agent.log.join('\n'));
      return { id, log: agent.log };
    };
    const first = await runOnce(100);
    const closed = await getJson(`${server.url}/api/sessions/${first.id}`);
    assert.equal(closed.status, 'closed', 'the agent closes its simulator session on SIGINT');
    assert.ok(first.log.some((l) => l.includes(`session ${first.id} closed`)), first.log.join('\n'));
    assert.ok(!first.log.some((l) => /link lost|reconnecting/.test(l)), first.log.join('\n'));

    const second = await runOnce(100);
    assert.notEqual(second.id, first.id, 'a new session');
    assert.ok(!second.log.some((l) => l.includes('does not know session')), second.log.join('\n'));
    // No teleport: the simulated robot starts afresh, and so does its trajectory.
    for (const id of [first.id, second.id]) {
      const { max, poses } = await maxStep(server.url, id);
      assert.ok(poses >= 100, `${id}: ${poses} poses`);
      assert.ok(max < 0.5, `${id}: consecutive poses ${max.toFixed(2)} m apart`);
    }
  });

  it('keeps the agent linked while a restarted server rebuilds its session', async () => {
    // A server of its own, killed and restarted on the same port and data directory.
    const data = join(dir, 'data-rebuild');
    let own = await startServer({ dataDir: data, extraArgs: ['--predict', 'on', '--particles', '30'] });
    const port = own.port;
    const agent = startAgent({ port, spoolDir: join(dir, 'spool-rebuild'), source: 'sim:maze', name: 'rebuild',
      extraArgs: ['--rate', '8', '--keep-session'] });
    agents.push(agent);
    try {
      const before = await waitFor('a few thousand stored inputs', async () => {
        const { sessions } = await getJson(`${own.url}/api/sessions?status=active`);
        return sessions.find((s) => s.last_seq >= 4000);
      }, { timeoutMs: 180000, intervalMs: 500 });
      await own.stop('SIGKILL');
      own = await startServer({ dataDir: data, port, extraArgs: ['--predict', 'on', '--particles', '30'] });
      const restartedAt = agent.log.length;
      const resumed = await waitFor('the rebuilt session to take new inputs', async () => {
        const s = (await getJson(`${own.url}/api/sessions/${before.id}/stats`)).filter;
        return !s.rebuilding && s.processed_seq > before.last_seq + 200 && s;
      }, { timeoutMs: 240000, intervalMs: 500 });
      const after = agent.log.slice(restartedAt);
      assert.ok(!after.some((l) => / lost \(/.test(l)), `the link dropped during the rebuild:\n${after.join('\n')}`);
      console.log(`rebuilt ${before.last_seq} inputs; the agent streamed on (${resumed.processed_seq} processed)`);
    } finally {
      await agent.stop();
      await own.stop();
    }
  });

  it('explores the world to the end and says so, with the area mapped', { timeout: 40 * 60 * 1000 }, async () => {
    const worldYaml = world === 'small' ? writeSmallWorld(dir) : join(repoRoot, 'core', 'worlds', `${world}.yaml`);
    const agent = startAgent({ port: server.port, spoolDir: join(dir, 'spool-explore'), source: `sim:${worldYaml}`, name: 'explore',
      extraArgs: ['--rate', rate] });
    agents.push(agent);
    const id = await waitFor('the exploring session', async () => {
      const { sessions } = await getJson(`${server.url}/api/sessions?status=active`);
      return sessions.find((x) => x.name === 'explore')?.id;
    });
    await page.goto(`${server.url}/#/session/${id}`);
    const stats = await waitFor('exploration complete', async () => {
      const s = (await getJson(`${server.url}/api/sessions/${id}/stats`)).filter;
      if (agent.child.exitCode !== null) throw new Error(`the agent exited:\n${agent.log.join('\n')}`);
      return s.exploration === 'complete' && s;
    }, { timeoutMs: 38 * 60 * 1000, intervalMs: 2000 });

    const reachable = reachableFreeArea(worldYaml);
    const share = stats.mapped_m2 / reachable;
    console.log(`${world}: ${stats.mapped_m2.toFixed(0)} m² mapped of ${reachable.toFixed(0)} m² reachable (${(100 * share).toFixed(1)} %), ` +
      `${stats.predicted_m2.toFixed(0)} m² predicted and not mapped, ${stats.scans} scans`);
    assert.ok(share >= 0.95, `mapped ${(100 * share).toFixed(1)} % of the reachable free area`);

    const banner = page.locator('.exploration-banner[data-exploration="complete"]');
    await banner.waitFor({ timeout: 30000 });
    assert.match(await banner.innerText(), /Exploration complete · \d+ m² mapped \(\d+ %\)/);
    await page.screenshot({ path: join(artifacts, 'ops-exploration-complete.png') });

    const { events } = await getJson(`${server.url}/api/sessions/${id}/events?limit=1000`);
    const states = events.filter((e) => e.kind === 'exploration').map((e) => e.detail.state);
    assert.ok(states.includes('exploring') && states.includes('complete'), states.join(', '));
    assert.equal((await getJson(`${server.url}/api/sessions/${id}`)).exploration, 'complete');

    // Each target is named once, however often the server re-plans it.
    const targets = agent.log.filter((l) => l.includes('new target')).map((l) => /new target (\([^)]*\))/.exec(l)[1]);
    assert.ok(targets.length > 5, agent.log.join('\n'));
    for (let i = 1; i < targets.length; i++) assert.notEqual(targets[i], targets[i - 1], `target ${targets[i]} logged twice in a row`);
  });

  it('starts a log replay from the replay directory listing', { skip: !existsSync(intelLog) && 'no ../shared/data/intel' }, async () => {
    await page.goto(`${server.url}/`);
    await page.locator('[data-action="open-replay"]').click();
    const dialog = page.locator('dialog.replay-dialog');
    await dialog.waitFor();
    const logSelect = dialog.locator('select[name="log"]');
    await logSelect.locator('option[value="intel/intel-slice.clf"]').waitFor({ state: 'attached' });
    assert.match(await logSelect.locator('option').first().innerText(), /^intel\/intel-slice\.clf \(\d/);
    await dialog.locator('input[name="source"][value="log"]').check();
    await logSelect.selectOption('intel/intel-slice.clf');
    await dialog.locator('input[name="particles"]').fill('4');
    await dialog.locator('input[name="name"]').fill('replay from the list');
    await page.screenshot({ path: join(artifacts, 'ops-replay-dialog.png') });
    await dialog.locator('[data-action="start-replay"]').click();
    const replay = await waitFor('the replay to close', async () => {
      const { sessions } = await getJson(`${server.url}/api/sessions?status=closed`);
      return sessions.find((s) => s.name === 'replay from the list');
    });
    assert.equal(replay.replay_of, 'intel/intel-slice.clf');
    assert.equal(replay.scans, 300);
  });
});
