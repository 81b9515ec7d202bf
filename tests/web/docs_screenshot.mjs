// Makes docs/viewer.png from a real run: pslam-server and pslam-agent driving the simulated
// Pioneer through the office (as deploy/run.sh does, sped up), shown in Debian's chromium once the
// server has kept a few predictions. Not a test; run after building web/ and the binaries:
//   node tests/web/docs_screenshot.mjs [--out docs/viewer.png] [--predictions 4] [--rate 4]
import { join } from 'node:path';
import { parseArgs } from 'node:util';
import { launchBrowser, repoRoot, startAgent, startServer, tempDir, waitFor } from './support.mjs';

const { values } = parseArgs({
  options: {
    out: { type: 'string', default: join(repoRoot, 'docs', 'viewer.png') },
    predictions: { type: 'string', default: '4' },
    rate: { type: 'string', default: '4' },
  },
});

const dir = tempDir('pslam-docs-shot-');
const server = await startServer({ dataDir: join(dir, 'data'), extraArgs: ['--predict', 'on'] });
const agent = startAgent({
  port: server.port,
  spoolDir: join(dir, 'spool'),
  source: 'sim:office',
  name: 'simulated office',
  extraArgs: ['--rate', values.rate],
});
const browser = await launchBrowser();
try {
  const page = await browser.context.newPage();
  await page.setViewportSize({ width: 1440, height: 810 });
  await page.goto(`${server.url}/`);
  await page.locator('.pane[data-connection="open"]').waitFor({ timeout: 60000 });
  const wanted = Number(values.predictions);
  await waitFor(
    `${wanted} predictions with their cells`,
    () => page.evaluate((n) => [...window.pslam.app.views[0].client.hypotheses.entries.values()].filter((e) => e.cellsState === 'loaded').length >= n, wanted),
    { timeoutMs: 900000, intervalMs: 2000 },
  );
  await page.locator('.pane [data-action="fit"]').click();
  await page.waitForTimeout(1500);
  await page.screenshot({ path: values.out });
  console.log(`wrote ${values.out}`);
} finally {
  await browser.close();
  await agent.stop();
  await server.stop();
}
