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
});
