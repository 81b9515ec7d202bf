// Visual stories of the map layers (web/stories.html): each layer drawn by the real viewer code
// from fixed data, screenshotted for review, and checked to draw something of its own. Needs only
// web/dist and chromium, not the server.
import assert from 'node:assert/strict';
import { existsSync } from 'node:fs';
import { join } from 'node:path';
import { after, before, describe, it } from 'node:test';
import { distDir, ensureArtifacts, launchBrowser, serveDist, waitFor } from './support.mjs';

const skip = existsSync(join(distDir, 'stories.html')) ? false : 'web/dist/stories.html is missing (npm run build in web/)';

describe('layer stories', { skip }, () => {
  let site, browser, page;
  before(async () => {
    site = await serveDist();
    browser = await launchBrowser();
    page = await browser.context.newPage();
    await page.goto(`${site.url}/stories.html`);
    await waitFor('the stories', () => page.evaluate(() => window.storiesReady === true));
  });
  after(async () => {
    await browser?.close();
    await site?.close();
  });

  // Pixels of a story's canvas that differ between the layer shown and hidden.
  const layerPixels = (story, layer) =>
    page.evaluate(
      ([name, id]) => {
        const v = window.stories[name];
        const grab = () => {
          v.drawNow();
          const c = v.canvas;
          return c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
        };
        const on = grab();
        v.setLayerVisible(id, false);
        const off = grab();
        v.setLayerVisible(id, true);
        v.drawNow();
        let differ = 0;
        for (let i = 0; i < on.length; i += 4) if (on[i] !== off[i] || on[i + 1] !== off[i + 1] || on[i + 2] !== off[i + 2]) differ++;
        return differ;
      },
      [story, layer],
    );

  it('draws every layer', async () => {
    const expectations = [
      ['built map', 'map', 20000],
      ['predictions by psi, H3 selected', 'hypotheses', 2000],
      ['predictions by status', 'hypotheses', 2000],
      ['robot, trajectory, exploration, particles, scan', 'robot', 100],
      ['robot, trajectory, exploration, particles, scan', 'trajectory', 300],
      ['robot, trajectory, exploration, particles, scan', 'exploration', 300],
      ['robot, trajectory, exploration, particles, scan', 'particles', 50],
      ['robot, trajectory, exploration, particles, scan', 'scan', 200],
    ];
    for (const [story, layer, min] of expectations) {
      const n = await layerPixels(story, layer);
      assert.ok(n >= min, `${story}: layer ${layer} changes ${n} pixels (expected at least ${min})`);
    }
    const dir = ensureArtifacts();
    await page.setViewportSize({ width: 1320, height: 900 });
    await page.screenshot({ path: join(dir, 'stories.png'), fullPage: true });
  });

  it('colours predictions differently by psi and by status', async () => {
    const hash = (story) =>
      page.evaluate((name) => {
        const v = window.stories[name];
        v.drawNow();
        const d = v.canvas.getContext('2d').getImageData(0, 0, v.canvas.width, v.canvas.height).data;
        let h = 0;
        for (let i = 0; i < d.length; i += 16) h = (Math.imul(h, 31) + d[i] + d[i + 1] * 7 + d[i + 2] * 13) >>> 0;
        return h;
      }, story);
    assert.notEqual(await hash('predictions by psi, H3 selected'), await hash('predictions by status'));
  });

  // The colour on screen at the centre of cell (cx, cy), zoomed in to 20 pixels per cell, with only
  // the layers 'shown' drawn (by default the predictions, over the plain background).
  const cellPixel = (story, cx, cy, shown = ['hypotheses']) =>
    page.evaluate(
      ([name, x, y, layers]) => {
        const v = window.stories[name];
        const res = 0.05;
        const saved = { cx: v.camera.centerX, cy: v.camera.centerY, scale: v.camera.scale };
        for (const id of ['map', 'hypotheses', 'exploration', 'trajectory', 'particles', 'scan', 'robot']) v.setLayerVisible(id, layers.includes(id));
        v.camera.centerX = (x + 0.5) * res;
        v.camera.centerY = (y + 0.5) * res;
        v.camera.scale = 20 / res;
        v.drawNow();
        const px = v.canvas.getContext('2d').getImageData(Math.floor(v.canvas.width / 2), Math.floor(v.canvas.height / 2), 1, 1).data;
        v.camera.centerX = saved.cx;
        v.camera.centerY = saved.cy;
        v.camera.scale = saved.scale;
        v.setLayerVisible('map', true);
        v.setLayerVisible('hypotheses', true);
        v.drawNow();
        return [px[0], px[1], px[2]];
      },
      [story, cx, cy, shown],
    );

  // Cells of a story's hypothesis the map has not mapped: its walls and free cells that no other
  // hypothesis predicts, and its free cells that another one predicts free too; and the ones the
  // map has mapped since.
  const cellsOf = (story, id) =>
    page.evaluate(
      ([name, hid]) => {
        const { hypotheses: store, map } = window.storyClients[name];
        const unmapped = (x, y) => (map.cellAt((x + 0.5) * 0.05, (y + 0.5) * 0.05) ?? 255) === 255;
        const key = (x, y) => `${x},${y}`;
        const others = new Map();
        for (const e of store.entries.values()) {
          if (e.h.id === hid) continue;
          for (let i = 0; i < e.cells.xs.length; i++) others.set(key(e.cells.xs[i], e.cells.ys[i]), e.cells.occupancy[i]);
        }
        const c = store.entries.get(hid).cells;
        const out = { walls: [], free: [], freeShared: [], mapped: [] };
        for (let i = 0; i < c.xs.length; i++) {
          const [x, y, wall] = [c.xs[i], c.ys[i], c.occupancy[i] >= 0.5];
          if (!unmapped(x, y)) {
            out.mapped.push([x, y]);
            continue;
          }
          const shared = others.has(key(x, y));
          if (wall && !shared) out.walls.push([x, y]);
          if (!wall && !shared) out.free.push([x, y]);
          if (!wall && shared && others.get(key(x, y)) < 0.5) out.freeShared.push([x, y]);
        }
        return out;
      },
      [story, id],
    );

  const distance = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
  const kBackground = [0x2a, 0x2e, 0x37];

  it('draws predicted walls as solid cells and predicted free space as a light wash that does not stack', async () => {
    const story = 'predictions by psi, H3 selected';
    const h1 = await cellsOf(story, 1);
    assert.ok(h1.walls.length > 0 && h1.free.length > 0 && h1.freeShared.length > 0, `fixture cells: ${JSON.stringify(Object.fromEntries(Object.entries(h1).map(([k, v]) => [k, v.length])))}`);
    const wall = await cellPixel(story, ...h1.walls[0]);
    const free = await cellPixel(story, ...h1.free[Math.floor(h1.free.length / 2)]);
    const shared = await cellPixel(story, ...h1.freeShared[Math.floor(h1.freeShared.length / 2)]);
    const colour = await page.evaluate(() => window.storyClients['predictions by psi, H3 selected'].hypotheses.entries.get(1).h.psi);
    console.log(`H1 (psi ${colour}): wall ${wall}, free ${free}, free where H2 overlaps ${shared}, background ${kBackground}`);
    // A wall is the colour itself; free space stays close to the background, lightly tinted.
    assert.ok(distance(wall, kBackground) > 100, `wall ${wall} stands out`);
    assert.ok(distance(free, kBackground) > 8, `free space ${free} is tinted`);
    assert.ok(distance(free, kBackground) < distance(wall, kBackground) / 3, `free space ${free} is a light wash next to wall ${wall}`);
    // Two predictions of free space over the same cell draw it once, not twice as dark.
    assert.ok(distance(shared, kBackground) < distance(wall, kBackground) / 3, `overlapping free space ${shared} stays a light wash`);
    assert.ok(Math.abs(distance(shared, kBackground) - distance(free, kBackground)) < 12, `overlap ${shared} looks like single free space ${free}`);
    // Where the map has mapped a predicted cell, the map shows it: the prediction does not change it.
    assert.ok(h1.mapped.length > 0, 'the fixture has predicted cells the map knows');
    for (const cell of [h1.mapped[0], h1.mapped[h1.mapped.length - 1]]) {
      assert.deepEqual(await cellPixel(story, ...cell, ['map', 'hypotheses']), await cellPixel(story, ...cell, ['map']));
    }
  });

  it('colours walls of predictions with psi 0.75 and 0.9 visibly differently', async () => {
    const story = 'predictions by psi, H3 selected';
    const h1 = await cellsOf(story, 1);
    const h2 = await cellsOf(story, 2);
    const a = await cellPixel(story, ...h1.walls[0]);
    const b = await cellPixel(story, ...h2.walls[0]);
    console.log(`wall at psi 0.75: ${a}; at psi 0.9: ${b}`);
    assert.ok(distance(a, b) > 80, `psi 0.75 ${a} vs 0.9 ${b}`);
  });
});
