// Browser tests of how the viewer reads out stored sessions: evaluation metrics as numbers,
// nothing clipped at common window sizes, stored sessions without live-only numbers, and one
// statistics and predictions panel per pane in compare mode. Debian's chromium against the real
// pslam-server, which replays two slices of the Intel log with its relations file (RPE). Needs the
// shared data set (../shared/data or $PSLAM_DATA_DIR); skipped without it.
import assert from 'node:assert/strict';
import { copyFileSync, createReadStream, createWriteStream, existsSync, mkdirSync } from 'node:fs';
import { join, resolve } from 'node:path';
import { createInterface } from 'node:readline';
import { after, before, describe, it } from 'node:test';
import { distDir, ensureArtifacts, launchBrowser, repoRoot, serverBinary, startServer, tempDir, waitFor } from './support.mjs';

const dataDir = resolve(process.env.PSLAM_DATA_DIR ?? join(repoRoot, '..', 'shared', 'data'));
const intelLog = join(dataDir, 'intel', 'intel.clf');
const intelRelations = join(dataDir, 'intel', 'intel.relations');
const missing = [serverBinary, join(distDir, 'index.html'), intelLog, intelRelations].filter((f) => !existsSync(f));
const skip = missing.length ? `missing ${missing.join(', ')}` : false;

// The first 'lasers' laser lines of a CARMEN log and everything between them.
async function sliceLog(from, to, lasers) {
  const out = createWriteStream(to);
  let n = 0;
  for await (const line of createInterface({ input: createReadStream(from) })) {
    out.write(`${line}\n`);
    if (line.startsWith('FLASER') && ++n >= lasers) break;
  }
  await new Promise((r) => out.end(r));
}

async function getJson(url) {
  const res = await fetch(url);
  assert.equal(res.status, 200, `${url}: HTTP ${res.status}`);
  return res.json();
}

// Elements in the side bars whose content is cut off: wider than their box (without an ellipsis
// meant for long names), or reaching past the side bar.
function clippedElements(page) {
  return page.evaluate(() => {
    const out = [];
    for (const bar of document.querySelectorAll('.sidebar')) {
      const barRect = bar.getBoundingClientRect();
      if (bar.scrollWidth > bar.clientWidth + 1) out.push(`${bar.className}: scrolls sideways (${bar.scrollWidth} > ${bar.clientWidth})`);
      for (const el of bar.querySelectorAll('*')) {
        if (el.closest('[hidden]') || el.closest('details:not([open]) > :not(summary)')) continue;
        const style = getComputedStyle(el);
        if (style.display === 'none' || style.textOverflow === 'ellipsis' || el.closest('.session-actions, .u-legend')) continue;
        const r = el.getBoundingClientRect();
        if (r.width === 0) continue;
        const text = (el.textContent ?? '').trim().slice(0, 60);
        if (r.right > barRect.right + 1 && el.children.length === 0) out.push(`'${text}' ends at ${Math.round(r.right)} > ${Math.round(barRect.right)}`);
        if (el.scrollWidth > el.clientWidth + 1 && style.overflowX !== 'visible' && !el.matches('select, input')) out.push(`'${text}' is cut (${el.scrollWidth} > ${el.clientWidth})`);
      }
    }
    return out;
  });
}

describe('viewer read-outs of stored sessions', { skip }, () => {
  let dir, server, browser, page, artifacts, short, long;
  const pageErrors = [];
  const shot = (name) => page.screenshot({ path: join(artifacts, `${name}.png`) });

  before(async () => {
    artifacts = ensureArtifacts();
    dir = tempDir('pslam-web-eval-');
    const logs = join(dir, 'logs');
    mkdirSync(logs);
    // 300 and 600 scans of the Intel log: the first relations lie in this stretch.
    await sliceLog(intelLog, join(logs, 'intel-300.clf'), 300);
    await sliceLog(intelLog, join(logs, 'intel-600.clf'), 600);
    copyFileSync(intelRelations, join(logs, 'intel.relations'));
    server = await startServer({ dataDir: join(dir, 'data'), extraArgs: ['--replay-dir', logs, '--checkpoint-seconds', '1'] });
    const replay = async (log, name) => {
      const res = await fetch(`${server.url}/api/replays`, {
        method: 'POST',
        headers: { 'Content-Type': 'application/json' },
        body: JSON.stringify({ log, relations: 'intel.relations', name, settings: { particles: 4, seed: 3 } }),
      });
      const body = await res.text();
      assert.equal(res.status, 201, body);
      return JSON.parse(body).id;
    };
    short = await replay('intel-300.clf', 'intel 300 scans');
    long = await replay('intel-600.clf', 'intel 600 scans');
    for (const id of [short, long]) {
      let seen = '';
      const ended = await waitFor(
        `replay ${id} to end with its RPE`,
        async () => {
          const stats = await getJson(`${server.url}/api/sessions/${id}/stats`);
          seen = `${stats.status}, ${stats.filter?.scans} scans`;
          return stats.status === 'failed' ? { failed: true } : stats.metrics?.rpe;
        },
        { timeoutMs: 240000, intervalMs: 500 },
      ).catch((e) => {
        throw new Error(`${e.message}; the session: ${seen}`);
      });
      if (ended.failed) throw new Error(`replay ${id} failed:\n${server.log.slice(-5).join('\n')}`);
    }
    browser = await launchBrowser();
    page = await browser.context.newPage();
    page.on('pageerror', (e) => pageErrors.push(e.message));
    await page.setViewportSize({ width: 1280, height: 720 });
  });

  after(async () => {
    await browser?.close();
    await server?.stop();
    if (pageErrors.length) console.log('page errors:', pageErrors);
  });

  it('shows the RPE as mean ± std numbers in the statistics panel and the session list', async () => {
    await page.goto(`${server.url}/#/session/${long}`);
    const rpe = (await getJson(`${server.url}/api/sessions/${long}/stats`)).metrics.rpe;
    assert.ok(rpe.used > 0, `relations used: ${JSON.stringify(rpe)}`);
    const stat = (label) => page.locator(`.stats-panel [data-stat="${label}"]`);
    await stat('RPE translation').waitFor({ timeout: 20000 });
    assert.equal(await stat('RPE translation').innerText(), `${rpe.trans_mean_m.toFixed(3)} ± ${rpe.trans_std_m.toFixed(3)} m`);
    assert.equal(await stat('RPE rotation').innerText(), `${rpe.rot_mean_deg.toFixed(2)} ± ${rpe.rot_std_deg.toFixed(2)} °`);
    assert.match(await stat('relations used').innerText(), new RegExp(`^${rpe.used}\\b`));
    const row = page.locator(`.session-row[data-session="${long}"] [data-metrics]`);
    assert.equal(await row.innerText(), `RPE ${rpe.trans_mean_m.toFixed(3)} ± ${rpe.trans_std_m.toFixed(3)} m, ${rpe.rot_mean_deg.toFixed(2)} ± ${rpe.rot_std_deg.toFixed(2)} °`);
    await page.locator('.session-details [data-detail="RPE translation"]').waitFor();
    const text = await page.locator('.app').innerText();
    assert.ok(!/[{"]/.test(text.replace(/“|”/g, '')), 'no raw JSON on the page');
    await shot('eval-1280x720');
  });

  it('clips nothing in the side bars at 1280x720 and 1920x1080', async () => {
    for (const [width, height] of [
      [1280, 720],
      [1920, 1080],
    ]) {
      await page.setViewportSize({ width, height });
      await page.waitForTimeout(600);
      const clipped = await clippedElements(page);
      await shot(`eval-clipping-${width}x${height}`);
      assert.deepEqual(clipped, [], `${width}x${height}`);
    }
    await page.setViewportSize({ width: 1280, height: 720 });
  });

  it('shows a stored session without latency or rates, and says its plots need live data', async () => {
    await page.locator('.stats-panel [data-stat="scans"]').waitFor();
    for (const label of ['latency', 'scan rate', 'queued']) {
      assert.equal(await page.locator(`.stats-panel [data-stat="${label}"]`).count(), 0, `${label} is hidden`);
    }
    assert.ok(await page.locator('.stats-panel .no-live-data').isVisible(), 'the panel says there is no live data');
    assert.equal(await page.locator('.stats-panel .plot:visible').count(), 0, 'no empty plots');
  });

  it('shows the legend of every mark of a prediction', async () => {
    const marks = await page.locator('[data-legend="prediction-marks"]').innerText();
    for (const word of ['predicted wall', 'predicted free', 'target']) assert.ok(marks.includes(word), `legend: ${marks}`);
    assert.equal(await page.locator('[data-legend="prediction-marks"] .swatch.diamond').count(), 1);
    assert.equal(await page.locator('[data-legend="psi"] .psi-step').count(), 7, 'Ψ in steps');
  });

  it('in compare mode gives each pane its own statistics and predictions', async () => {
    await page.goto(`${server.url}/#/compare/${short}/${long}`);
    for (const [id, scans] of [
      [short, 300],
      [long, 600],
    ]) {
      const panel = page.locator(`.stats-panel[data-session="${id}"]`);
      await waitFor(`the statistics of ${id}`, async () => (await panel.locator('[data-stat="scans"]').innerText()) === String(scans), { timeoutMs: 20000 });
      await panel.locator('[data-stat="RPE translation"]').waitFor();
      const kept = (await getJson(`${server.url}/api/sessions/${id}/hypotheses?limit=1`)).total;
      const summary = page.locator(`.hypothesis-panel[data-session="${id}"] .hyp-summary b`);
      await waitFor(`the predictions of ${id}`, async () => (await summary.innerText()) === String(kept), { timeoutMs: 20000 });
      console.log(`pane of ${id}: ${scans} scans, ${kept} predictions`);
    }
    const titles = await page.locator('[data-panel="stats"] .pane-block-title').allInnerTexts();
    assert.deepEqual(titles, ['Left: intel 300 scans', 'Right: intel 600 scans']);
    // Focusing the other pane does not change what the panels show.
    await page.locator('.pane').nth(1).locator('.map-canvas').click({ position: { x: 30, y: 30 } });
    assert.equal(await page.locator(`.stats-panel[data-session="${short}"] [data-stat="scans"]`).innerText(), '300');
    await shot('eval-compare');
    // Both panes keep every header button inside the pane, and a readable title.
    const header = await page.evaluate(() =>
      [...document.querySelectorAll('.pane')].map((pane) => {
        const r = pane.getBoundingClientRect();
        const buttons = [...pane.querySelectorAll('.pane-header button')];
        return {
          outside: buttons.filter((b) => b.getBoundingClientRect().right > r.right + 1).map((b) => b.title),
          title: pane.querySelector('.pane-title').getBoundingClientRect().width,
        };
      }),
    );
    for (const p of header) {
      assert.deepEqual(p.outside, [], 'header buttons inside the pane');
      assert.ok(p.title >= 30, `pane title ${p.title} px wide`);
    }
    assert.deepEqual(await clippedElements(page), []);
    assert.deepEqual(pageErrors, []);
  });
});
