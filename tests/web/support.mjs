// Helpers for the browser tests and benchmark: Debian's chromium through playwright-core (never a
// downloaded browser), a static file server for web/dist, and the real pslam-server and
// pslam-agent as child processes.
import { spawn } from 'node:child_process';
import { createReadStream, existsSync, mkdirSync, mkdtempSync, rmSync, statSync } from 'node:fs';
import { createServer } from 'node:http';
import { createRequire } from 'node:module';
import { tmpdir } from 'node:os';
import { dirname, extname, join, normalize, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';

export const repoRoot = resolve(dirname(fileURLToPath(import.meta.url)), '..', '..');
export const webDir = join(repoRoot, 'web');
export const distDir = join(webDir, 'dist');
export const artifactsDir = join(repoRoot, 'tests', 'web', 'artifacts');
export const binDir = process.env.PSLAM_BIN_DIR ? resolve(process.env.PSLAM_BIN_DIR) : join(repoRoot, 'build', 'bin');
export const serverBinary = join(binDir, 'pslam-server');
export const agentBinary = join(binDir, 'pslam-agent');
export const chromiumPath = process.env.CHROMIUM ?? '/usr/bin/chromium';

// playwright-core is a dependency of web/, not of this folder.
const requireFromWeb = createRequire(join(webDir, 'package.json'));
const { chromium } = requireFromWeb('playwright-core');

export async function launchBrowser() {
  const userDataDir = mkdtempSync(join(tmpdir(), 'pslam-chromium-'));
  const context = await chromium.launchPersistentContext(userDataDir, {
    executablePath: chromiumPath,
    headless: true,
    viewport: { width: 1600, height: 900 },
    acceptDownloads: true,
    args: [
      '--headless',
      '--no-sandbox',
      '--disable-gpu',
      '--disable-quic',
      '--no-first-run',
      '--disable-background-networking',
      '--disable-component-update',
      '--disable-sync',
    ],
  });
  const close = async () => {
    await context.close().catch(() => {});
    rmSync(userDataDir, { recursive: true, force: true });
  };
  return { context, close };
}

const kTypes = { '.html': 'text/html', '.js': 'text/javascript', '.css': 'text/css', '.map': 'application/json', '.svg': 'image/svg+xml' };

// Serves web/dist on 127.0.0.1 (for the benchmark, which needs no pslam-server).
export async function serveDist() {
  const server = createServer((req, res) => {
    const path = normalize(decodeURIComponent(new URL(req.url, 'http://x').pathname)).replace(/^(\.\.[/\\])+/, '');
    const file = join(distDir, path === '/' ? 'index.html' : path);
    if (!file.startsWith(distDir) || !existsSync(file) || !statSync(file).isFile()) {
      res.writeHead(404).end();
      return;
    }
    res.writeHead(200, { 'Content-Type': kTypes[extname(file)] ?? 'application/octet-stream' });
    createReadStream(file).pipe(res);
  });
  await new Promise((r) => server.listen(0, '127.0.0.1', r));
  return { url: `http://127.0.0.1:${server.address().port}`, close: () => new Promise((r) => server.close(r)) };
}

export function ensureArtifacts() {
  mkdirSync(artifactsDir, { recursive: true });
  return artifactsDir;
}

function collect(child, name, lines) {
  const push = (chunk) => {
    for (const line of chunk.toString().split('\n')) {
      if (!line) continue;
      lines.push(line);
      if (lines.length > 400) lines.shift();
      if (process.env.PSLAM_TEST_VERBOSE) console.log(`[${name}] ${line}`);
    }
  };
  child.stdout.on('data', push);
  child.stderr.on('data', push);
}

// Starts pslam-server on 127.0.0.1 ('port' 0: any free port) and resolves once it prints
// "listening on http://127.0.0.1:PORT".
export async function startServer({ dataDir, port = 0, extraArgs = [] }) {
  const args = ['--listen', `127.0.0.1:${port}`, '--data', dataDir, '--web', distDir, ...extraArgs];
  const child = spawn(serverBinary, args, { stdio: ['ignore', 'pipe', 'pipe'] });
  const lines = [];
  collect(child, 'server', lines);
  const actualPort = await new Promise((resolveFn, reject) => {
    const timer = setTimeout(() => reject(new Error(`pslam-server did not start:\n${lines.join('\n')}`)), 30000);
    const onData = (chunk) => {
      const m = /listening on http:\/\/127\.0\.0\.1:(\d+)/.exec(chunk.toString());
      if (m) {
        clearTimeout(timer);
        child.stdout.off('data', onData);
        resolveFn(Number(m[1]));
      }
    };
    child.stdout.on('data', onData);
    child.on('exit', (code) => {
      clearTimeout(timer);
      reject(new Error(`pslam-server exited with ${code}:\n${lines.join('\n')}`));
    });
  });
  return {
    child,
    port: actualPort,
    url: `http://127.0.0.1:${actualPort}`,
    log: lines,
    stop: (signal = 'SIGTERM') => stopChild(child, signal),
  };
}

// The agent's data source for the browser tests: the simulator in the office world (the simulated
// robot drives along the exploration paths the server plans), or $PSLAM_WEB_TEST_SOURCE, e.g.
// log:../shared/data/intel/intel.clf. Returns the --source value and its extra flags.
export function agentSource() {
  return { source: process.env.PSLAM_WEB_TEST_SOURCE ?? 'sim:office', args: ['--rate', process.env.PSLAM_WEB_TEST_RATE ?? '2'] };
}

export function startAgent({ port, spoolDir, source, name = 'browser test', extraArgs = [] }) {
  const args = ['--server', `127.0.0.1:${port}`, '--source', source, '--spool', spoolDir, '--session-name', name, '--status-period', '5', ...extraArgs];
  const child = spawn(agentBinary, args, { stdio: ['ignore', 'pipe', 'pipe'] });
  const lines = [];
  collect(child, 'agent', lines);
  return { child, log: lines, stop: () => stopChild(child, 'SIGTERM') };
}

export function stopChild(child, signal = 'SIGTERM', timeoutMs = 15000) {
  if (child.exitCode !== null || child.signalCode !== null) return Promise.resolve();
  return new Promise((resolveFn) => {
    const timer = setTimeout(() => child.kill('SIGKILL'), timeoutMs);
    child.once('exit', () => {
      clearTimeout(timer);
      resolveFn();
    });
    child.kill(signal);
  });
}

// Temporary folders of this test file. They go when it exits with every test passed, and stay
// (named on stderr) when one failed: a failed run's database and logs are what explains it.
const tempDirs = [];

export function tempDir(prefix) {
  const dir = mkdtempSync(join(tmpdir(), prefix));
  // Registered from the first call, inside a test, so it runs after node:test has set the exit code.
  if (tempDirs.length === 0) process.on('exit', removeTempDirsIfPassed);
  tempDirs.push(dir);
  return dir;
}

function removeTempDirsIfPassed(code) {
  if (code || process.exitCode) {
    console.error(`kept for diagnosis: ${tempDirs.join(' ')}`);
    return;
  }
  for (const dir of tempDirs) rmSync(dir, { recursive: true, force: true });
}

export async function waitFor(what, fn, { timeoutMs = 60000, intervalMs = 250 } = {}) {
  const start = Date.now();
  let last;
  for (;;) {
    try {
      last = await fn();
      if (last) return last;
    } catch (e) {
      last = e;
    }
    if (Date.now() - start > timeoutMs) throw new Error(`timed out after ${timeoutMs} ms waiting for ${what} (last: ${last instanceof Error ? last.message : JSON.stringify(last)})`);
    await new Promise((r) => setTimeout(r, intervalMs));
  }
}
