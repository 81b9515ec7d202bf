// REST behaviours an operator meets around the main job, against the real pslam-server: the replay
// directory's file list, status filters that reject a misspelt status, path parameters named as
// such, and the exploration choice for sessions that explore no more.
import assert from 'node:assert/strict';
import { existsSync, mkdirSync, symlinkSync, writeFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { after, before, describe, it } from 'node:test';
import { serverBinary, startServer, tempDir } from './support.mjs';

const skip = existsSync(serverBinary) ? false : `missing ${serverBinary} (build the project first)`;

function writeFile(path, bytes) {
  mkdirSync(dirname(path), { recursive: true });
  writeFileSync(path, 'x'.repeat(bytes));
}

async function call(url, method = 'GET', body = undefined) {
  const res = await fetch(url, { method, body: body === undefined ? undefined : typeof body === 'string' ? body : JSON.stringify(body) });
  const text = await res.text();
  return { status: res.status, text, json: () => JSON.parse(text) };
}

// An agent session of the server's (POST /api/sessions, as an agent may then resume it).
async function newSession(url) {
  const laser = { angle_min: -Math.PI / 2, angle_increment: Math.PI / 180, beams: 181, max_range: 20, min_range: 0, offset: { x: 0, y: 0, theta: 0 } };
  const res = await call(`${url}/api/sessions`, 'POST', { name: 'ops', laser });
  assert.equal(res.status, 201, res.text);
  return res.json().id;
}

describe('REST around the main job', { skip }, () => {
  let dir, server, bare;

  before(async () => {
    dir = tempDir('pslam-rest-ops-');
    const logs = join(dir, 'logs');
    writeFile(join(logs, 'intel', 'intel.clf'), 1234);
    writeFile(join(logs, 'intel', 'intel.relations'), 56);
    writeFile(join(logs, 'maps', 'office.yaml'), 78);
    writeFile(join(logs, 'a', 'b', 'c', 'd', 'four-deep.log'), 12);
    writeFile(join(logs, 'notes.txt'), 9); // not a kind a replay reads
    writeFile(join(logs, '.hidden', 'secret.clf'), 10); // hidden folder
    writeFile(join(logs, 'a', 'b', 'c', 'd', 'e', 'deep.clf'), 11); // deeper than four folders
    symlinkSync('/etc/hostname', join(logs, 'escape.log')); // leaves the directory
    server = await startServer({ dataDir: join(dir, 'data'), extraArgs: ['--replay-dir', logs] });
    bare = await startServer({ dataDir: join(dir, 'bare') });
  });

  after(async () => {
    await server?.stop();
    await bare?.stop();
  });

  it('lists what a replay can name, and nothing else', async () => {
    const listed = await call(`${server.url}/api/replays/files`);
    assert.equal(listed.status, 200, listed.text);
    assert.deepEqual(listed.json().files, [
      { name: 'a/b/c/d/four-deep.log', bytes: 12, kind: 'log' },
      { name: 'intel/intel.clf', bytes: 1234, kind: 'log' },
      { name: 'intel/intel.relations', bytes: 56, kind: 'relations' },
      { name: 'maps/office.yaml', bytes: 78, kind: 'reference_map' },
    ]);
    // A listed name is what a replay request takes: it resolves, and the log reader has its say.
    const replay = await call(`${server.url}/api/replays`, 'POST', { log: 'intel/intel.clf' });
    assert.equal(replay.status, 400, replay.text);
    assert.doesNotMatch(replay.text, /no file|outside/);
  });

  it('refuses the listing without a replay directory, saying why', async () => {
    const listed = await call(`${bare.url}/api/replays/files`);
    assert.equal(listed.status, 403);
    assert.match(listed.text, /--replay-dir/);
  });

  it('answers a misspelt status with 400 everywhere, and names path parameters as such', async () => {
    const id = await newSession(server.url);
    const sessions = await call(`${server.url}/api/sessions?status=bogus`);
    assert.equal(sessions.status, 400);
    assert.match(sessions.text, /query parameter 'status' must be active, closed or failed/);
    const hypotheses = await call(`${server.url}/api/sessions/${id}/hypotheses?status=maybe`);
    assert.equal(hypotheses.status, 400);
    assert.match(hypotheses.text, /must be pending, confirmed, refuted or expired/);
    assert.equal((await call(`${server.url}/api/sessions/${id}/hypotheses?status=pending`)).status, 200);
    const overlay = await call(`${server.url}/api/sessions/${id}/hypotheses/abc/overlay.png`);
    assert.equal(overlay.status, 400);
    assert.match(overlay.text, /path parameter 'hypothesis id'/);
    assert.doesNotMatch(overlay.text, /query parameter/);
  });

  it('takes the exploration choice for a running session only, and records it', async () => {
    const id = await newSession(server.url);
    const path = `${server.url}/api/sessions/${id}/exploration`;
    assert.equal((await call(path, 'POST', { verify_predictions: 'yes' })).status, 400);
    assert.equal((await call(path, 'POST', {})).status, 400);
    assert.equal((await call(path, 'POST', { verify_predictions: false, other: 1 })).status, 400);
    // A session created over REST has no robot to drive (source api).
    const noRobot = await call(path, 'POST', { verify_predictions: false });
    assert.equal(noRobot.status, 409, noRobot.text);
    assert.match(noRobot.text, /no robot/);
    assert.equal((await call(`${server.url}/api/sessions/s-0000000000000000/exploration`, 'POST', { verify_predictions: true })).status, 404);
    assert.equal((await call(`${server.url}/api/sessions/${id}/close`, 'POST')).status, 200);
    assert.equal((await call(path, 'POST', { verify_predictions: true })).status, 409);
  });
});
