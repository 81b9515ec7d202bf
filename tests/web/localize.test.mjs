// A localize session end to end: a real pslam-server with a site whose map the test draws and
// imports (a map_server PGM + YAML), a session localizing on it fed by the test's own ingest client
// (a robot driving through that room, its scans ray-cast by the test), and the viewer in Debian's
// chromium where the operator sets the robot's pose by a real mouse drag on the map. The session
// starts sure of a pose 2.5 m off and without random particles: only the dragged pose can put it
// right. Also the sites panel: the site, its map version and the version's files as imported.
// An extend session on the same map: the viewer names its phase, localizing and then mapping on.
// Run: npm --prefix web run test:browser (after the build).
import assert from 'node:assert/strict';
import { existsSync, readFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { join } from 'node:path';
import { after, before, describe, it } from 'node:test';
import { distDir, ensureArtifacts, launchBrowser, serverBinary, startServer, tempDir, waitFor, webDir } from './support.mjs';

const WebSocket = createRequire(join(webDir, 'package.json'))('ws');

const missing = [serverBinary, join(distDir, 'index.html')].filter((f) => !existsSync(f));
const skip = missing.length ? `missing ${missing.join(', ')} (build the project and web/ first)` : false;

// The room: 10 m x 8 m with a box and three wall stubs, off the 5 cm lattice (as the server
// tests' synthetic room).
const kWalls = (() => {
  const box = (x0, y0, x1, y1) => [[x0, y0, x1, y0], [x1, y0, x1, y1], [x1, y1, x0, y1], [x0, y1, x0, y0]];
  const walls = [...box(-5, -4, 5, 4), ...box(1.0, 0.5, 1.8, 1.3), [-5, 1, -3.5, 1], [-3.5, 1, -3.5, 2.5], [2.5, -4, 2.5, -2.2]];
  return walls.map(([ax, ay, bx, by]) => [ax + 0.013, ay + 0.021, bx + 0.013, by + 0.021]);
})();

function rayHit(ox, oy, dx, dy) {
  let best = Infinity;
  for (const [ax, ay, bx, by] of kWalls) {
    const ex = bx - ax, ey = by - ay;
    const denom = dx * ey - dy * ex;
    if (Math.abs(denom) < 1e-12) continue;
    const aox = ax - ox, aoy = ay - oy;
    const t = (aox * ey - aoy * ex) / denom;
    const u = (aox * dy - aoy * dx) / denom;
    if (t > 0 && u >= 0 && u <= 1) best = Math.min(best, t);
  }
  return best;
}

function distanceToSegment(px, py, [ax, ay, bx, by]) {
  const ex = bx - ax, ey = by - ay;
  const t = Math.max(0, Math.min(1, ((px - ax) * ex + (py - ay) * ey) / (ex * ex + ey * ey)));
  return Math.hypot(ax + t * ex - px, ay + t * ey - py);
}

// The room's map at 5 cm as map_server files: walls 0, inside 254, outside unknown (205).
function roomMap() {
  const res = 0.05, width = 240, height = 200, ox = -6, oy = -5;
  const pixels = Buffer.alloc(width * height, 205);
  for (let row = 0; row < height; row++) {
    for (let col = 0; col < width; col++) {
      const x = ox + (col + 0.5) * res, y = oy + (height - 1 - row + 0.5) * res;
      const inside = x > -4.987 && x < 5.013 && y > -3.979 && y < 4.021;
      if (kWalls.some((w) => distanceToSegment(x, y, w) <= res * 0.75)) pixels[row * width + col] = 0;
      else if (inside) pixels[row * width + col] = 254;
    }
  }
  const pgm = Buffer.concat([Buffer.from(`P5\n${width} ${height}\n255\n`), pixels]);
  const yaml = `image: room.pgm\nresolution: ${res}\norigin: [${ox}, ${oy}, 0.0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n`;
  return { yaml, pgm };
}

// The robot's true pose at step i: along the room's length and back, turning slowly.
function poseAt(i) {
  const s = (i * 0.08) % 12;
  return { x: s < 6 ? -3 + s : 9 - s, y: -1 + 0.3 * Math.sin(s * 0.5), theta: 0.15 * Math.sin(s) };
}

const kLaser = { angle_min: -Math.PI / 2, angle_increment: Math.PI / 180, beams: 181, max_range: 20, min_range: 0 };

function scanMessage(seq) {
  const p = poseAt(seq);
  const ranges = [];
  for (let i = 0; i < kLaser.beams; i++) {
    const a = p.theta + kLaser.angle_min + i * kLaser.angle_increment;
    ranges.push(Math.min(rayHit(p.x, p.y, Math.cos(a), Math.sin(a)), kLaser.max_range));
  }
  return { type: 'scan', seq, t: 1700000000 + 0.1 * seq, odom: p, ranges };
}

// The ingest side of a robot: hello, welcome, scans, acks.
class IngestClient {
  constructor(url) {
    this.ws = new WebSocket(url);
    this.acked = 0;
    this.messages = [];
    this.ws.on('message', (data) => {
      const m = JSON.parse(data.toString());
      this.messages.push(m);
      if (m.type === 'ack') this.acked = Math.max(this.acked, m.seq);
    });
  }
  async open() {
    await new Promise((resolve, reject) => {
      this.ws.once('open', resolve);
      this.ws.once('error', reject);
    });
  }
  send(message) {
    this.ws.send(JSON.stringify(message));
  }
  async sendScans(from, to) {
    for (let seq = from; seq <= to; seq++) this.send(scanMessage(seq));
    await waitFor(`the ack of scan ${to}`, () => this.acked >= to, { timeoutMs: 30000 });
  }
  close() {
    this.ws.close();
  }
}

async function getJson(url, init) {
  const res = await fetch(url, init);
  const body = await res.json();
  assert.ok(res.ok, `${url}: HTTP ${res.status} ${JSON.stringify(body)}`);
  return body;
}

const postJson = (url, body) => getJson(url, { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(body) });

describe('setting a localize session pose in the viewer', { skip }, () => {
  let dir, server, browser, page, artifacts, robot, site, sessionId, map;
  const pageErrors = [];
  const shot = (name) => page.screenshot({ path: join(artifacts, `${name}.png`) });
  const filterStats = async () => (await getJson(`${server.url}/api/sessions/${sessionId}/stats`)).filter;

  before(async () => {
    artifacts = ensureArtifacts();
    dir = tempDir('pslam-web-localize-');
    server = await startServer({ dataDir: join(dir, 'data') });
    site = (await postJson(`${server.url}/api/sites`, { name: 'room' })).id;
    map = roomMap();
    await postJson(`${server.url}/api/sites/${site}/maps`, { yaml: map.yaml, pgm_base64: map.pgm.toString('base64'), note: 'drawn by the test' });

    // Sure of a pose 2.5 m off, with no random particles to find the way back by itself.
    const wrong = { ...poseAt(1), y: poseAt(1).y + 2.5, std_xy: 0.05, std_theta: 0.05 };
    robot = new IngestClient(`ws://127.0.0.1:${server.port}/api/ingest`);
    await robot.open();
    robot.send({
      type: 'hello',
      version: 1,
      robot_id: 'browser-test-bot',
      session: 'new',
      session_name: 'localize in the viewer',
      laser: kLaser,
      settings: { mode: 'localize', site, initial_pose: wrong, localization: { max_particles: 3000, recovery_alpha_slow: 0, recovery_alpha_fast: 0 } },
    });
    const welcome = await waitFor('the welcome', () => robot.messages.find((m) => m.type === 'welcome' || m.type === 'error'));
    assert.equal(welcome.type, 'welcome', JSON.stringify(welcome));
    sessionId = welcome.session_id;
    await robot.sendScans(1, 40);
    await waitFor('40 scans processed', async () => (await filterStats()).processed_seq >= 40);

    browser = await launchBrowser();
    page = await browser.context.newPage();
    page.on('pageerror', (e) => pageErrors.push(e.message));
    await page.goto(`${server.url}/#/session/${sessionId}`);
  });

  after(async () => {
    if (page && artifacts) await shot('localize-final').catch(() => {});
    robot?.close();
    await browser?.close();
    await server?.stop();
    if (pageErrors.length) console.log('page errors:', pageErrors);
  });

  it('offers the set-pose tool and says the session localizes', async () => {
    await page.locator('button[data-action="set-pose"]:visible').waitFor({ timeout: 30000 });
    await page.locator('[data-stat="mode"]', { hasText: 'localize' }).waitFor();
    await page.locator('[data-stat="localized"]').waitFor();
    await waitFor('the site map drawn', () => page.evaluate(() => window.pslam.app.views[0].client.map.cellCounts().known > 10000));
  });

  it('sets the pose the operator drags on the map', async () => {
    // A user zoom ends auto-fit, so the camera stays where the drag is computed.
    await page.locator('.pane button[aria-label="Zoom in"]').click();
    const truth = poseAt(41);
    const tip = { x: truth.x + 1.5 * Math.cos(truth.theta), y: truth.y + 1.5 * Math.sin(truth.theta) };
    const toPage = (points) =>
      page.evaluate((pts) => {
        const v = window.pslam.app.views[0].viewer;
        const r = v.canvas.getBoundingClientRect();
        const dpr = window.devicePixelRatio || 1;
        return pts.map((p) => ({ x: r.left + v.camera.worldToScreenX(p.x) / dpr, y: r.top + v.camera.worldToScreenY(p.y) / dpr }));
      }, points);
    await page.locator('button[data-action="set-pose"]').click();
    const [from, to] = await toPage([truth, tip]);
    await page.mouse.move(from.x, from.y);
    await page.mouse.down();
    await page.mouse.move((from.x + to.x) / 2, (from.y + to.y) / 2, { steps: 5 });
    await shot('localize-dragging');
    await page.mouse.move(to.x, to.y, { steps: 5 });
    await page.mouse.up();
    await page.locator('.pane-notice[data-pose="info"]:visible').waitFor({ timeout: 10000 });

    // The pose applies, and is logged, at the next scan.
    await robot.sendScans(41, 41);
    const poseEvents = async () => (await getJson(`${server.url}/api/sessions/${sessionId}/events`)).events.filter((e) => e.kind === 'initial_pose');
    await waitFor('the initial_pose event', async () => (await poseEvents()).length > 0);
    const events = await poseEvents();
    assert.equal(events.length, 1, JSON.stringify(events));
    const pose = events[0].detail;
    assert.equal(pose.seq, 41);
    assert.ok(Math.hypot(pose.x - truth.x, pose.y - truth.y) < 0.05, `dragged ${JSON.stringify(pose)}, truth ${JSON.stringify(truth)}`);
    assert.ok(Math.abs(Math.atan2(Math.sin(pose.theta - truth.theta), Math.cos(pose.theta - truth.theta))) < 0.05, `heading ${pose.theta} vs ${truth.theta}`);
    // The tool disarms after one pose: a drag pans the map again.
    assert.equal(await page.evaluate(() => window.pslam.app.views[0].viewer.pointerTool), null);
  });

  it('ends localized where the robot is', async () => {
    await robot.sendScans(42, 150);
    await waitFor('150 scans processed', async () => (await filterStats()).processed_seq >= 150);
    const stats = await filterStats();
    assert.equal(stats.mode, 'localize');
    assert.equal(stats.localization.localized, true, JSON.stringify(stats.localization));
    // The page's numbers are the live stream's, once it has caught up with the last scan.
    await page.locator('[data-stat="scans"]', { hasText: /^150$/ }).waitFor({ timeout: 15000 });
    assert.match(await page.locator('[data-stat="localized"]').innerText(), /^yes \(± 0\.\d\d m, ± \d+\.\d°\)$/);
    await shot('localize-localized');
    // And right: the estimates of the last 50 scans lie within 0.1 m of the truth, where before
    // the drag they were still off by the 2.5 m the session started with.
    const poses = (await getJson(`${server.url}/api/sessions/${sessionId}/trajectory`)).poses;
    const before = poses.find((q) => q.seq === 35);
    assert.ok(Math.hypot(before.x - poseAt(35).x, before.y - poseAt(35).y) > 1, `scan 35: ${JSON.stringify(before)}`);
    for (const p of poses.filter((q) => q.seq > 100)) {
      const t = poseAt(p.seq);
      assert.ok(Math.hypot(p.x - t.x, p.y - t.y) < 0.1, `scan ${p.seq}: estimate ${p.x}, ${p.y}, truth ${t.x}, ${t.y}`);
    }
  });

  it('lists the site and its map version, whose files download as imported', async () => {
    const row = page.locator(`.site-row[data-site="${site}"]`);
    await row.waitFor({ timeout: 20000 });
    assert.match(await row.locator('summary').innerText(), /room\s+1 map/);
    await row.locator('summary').click();
    const version = row.locator('.site-map[data-version="1"]');
    await version.waitFor({ timeout: 10000 });
    assert.match(await version.innerText(), /^v1\nimported · \d+ × \d+ · 0\.05 m\/cell/);
    for (const [file, bytes] of [['map.pgm', map.pgm], ['map.yaml', Buffer.from(map.yaml)]]) {
      const [download] = await Promise.all([page.waitForEvent('download'), version.locator(`a[data-file="${file}"]`).click()]);
      const saved = join(dir, `downloaded-${file}`);
      await download.saveAs(saved);
      assert.ok(readFileSync(saved).equals(bytes), `${file} differs from what was imported`);
    }
  });

  it('shows why a pose is refused', async () => {
    await postJson(`${server.url}/api/sessions/${sessionId}/close`, {});
    await page.locator('button[data-action="set-pose"]').waitFor({ state: 'hidden', timeout: 15000 });
    // A session closed behind the viewer's back: the POST is refused and the reason shown.
    await page.evaluate(() => {
      const v = window.pslam.app.views[0];
      return v.setPose({ x: 0, y: 0, theta: 0 });
    });
    const notice = page.locator('.pane-notice[data-pose="error"]:visible');
    await notice.waitFor({ timeout: 10000 });
    assert.match(await notice.innerText(), /Setting the pose failed/);
    assert.deepEqual(pageErrors, []);
  });
});

describe('an extend session in the viewer', { skip }, () => {
  let dir, server, browser, page, artifacts, robot, site, sessionId;
  const pageErrors = [];
  const filterStats = async () => (await getJson(`${server.url}/api/sessions/${sessionId}/stats`)).filter;

  before(async () => {
    artifacts = ensureArtifacts();
    dir = tempDir('pslam-web-extend-');
    server = await startServer({ dataDir: join(dir, 'data') });
    site = (await postJson(`${server.url}/api/sites`, { name: 'room' })).id;
    const map = roomMap();
    await postJson(`${server.url}/api/sites/${site}/maps`, { yaml: map.yaml, pgm_base64: map.pgm.toString('base64') });
    // No pose: global localization, which three scans from one spot leave undecided.
    robot = new IngestClient(`ws://127.0.0.1:${server.port}/api/ingest`);
    await robot.open();
    robot.send({
      type: 'hello',
      version: 1,
      robot_id: 'browser-test-bot',
      session: 'new',
      session_name: 'extend in the viewer',
      laser: kLaser,
      settings: { mode: 'extend', site, particles: 10, localization: { max_particles: 3000 } },
    });
    const welcome = await waitFor('the welcome', () => robot.messages.find((m) => m.type === 'welcome' || m.type === 'error'));
    assert.equal(welcome.type, 'welcome', JSON.stringify(welcome));
    sessionId = welcome.session_id;
    await robot.sendScans(1, 3);
    await waitFor('3 scans processed', async () => (await filterStats()).processed_seq >= 3);

    browser = await launchBrowser();
    page = await browser.context.newPage();
    page.on('pageerror', (e) => pageErrors.push(e.message));
    await page.goto(`${server.url}/#/session/${sessionId}`);
  });

  after(async () => {
    if (page && artifacts) await page.screenshot({ path: join(artifacts, 'extend-final.png') }).catch(() => {});
    robot?.close();
    await browser?.close();
    await server?.stop();
    if (pageErrors.length) console.log('page errors:', pageErrors);
  });

  it('says it localizes on the site map and offers the set-pose tool', async () => {
    await page.locator('[data-stat="mode"]', { hasText: 'extend a site map: localizing on it' }).waitFor({ timeout: 30000 });
    await page.locator('[data-stat="localized"]', { hasText: /^no/ }).waitFor();
    await page.locator('button[data-action="set-pose"]:visible').waitFor();
  });

  it('maps on from the site map once localized, without the set-pose tool', async () => {
    await postJson(`${server.url}/api/sessions/${sessionId}/initial_pose`, { ...poseAt(4), std_xy: 0.1, std_theta: 0.05 });
    await robot.sendScans(4, 60);
    await waitFor('60 scans processed', async () => (await filterStats()).processed_seq >= 60);
    assert.equal((await filterStats()).mode, 'extend_map');
    await page.locator('[data-stat="mode"]', { hasText: 'extend a site map: mapping on from it' }).waitFor({ timeout: 15000 });
    await page.locator('button[data-action="set-pose"]').waitFor({ state: 'hidden', timeout: 15000 });
    assert.equal(await page.locator('[data-stat="localized"]').count(), 0);
    assert.deepEqual(pageErrors, []);
  });
});
