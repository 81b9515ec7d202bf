// The session client against a mock server: live messages in, stores updated, hypothesis cells
// fetched from REST.
import { zlibSync } from 'fflate';
import { afterEach, beforeEach, describe, expect, it, vi } from 'vitest';
import { decodeLiveMessage, encodeTileFrame, type LiveMessage } from '../src/net/protocol';
import { SessionClient } from '../src/net/session_client';
import { hypothesisAdded, snapshotMessage } from './fixtures/live';

const message = (raw: unknown): LiveMessage => {
  const d = decodeLiveMessage(raw);
  if (!d.ok) throw new Error(d.error);
  return d.value;
};

const frame = (tx: number, ty: number, value: number) =>
  encodeTileFrame({ tx, ty, size: 64, revision: 1, cells: new Uint8Array(64 * 64).fill(value) }, (d) => zlibSync(d));

describe('SessionClient', () => {
  const fetched: string[] = [];
  beforeEach(() => {
    fetched.length = 0;
    vi.stubGlobal('location', new URL('http://127.0.0.1:8080/'));
    vi.stubGlobal('sessionStorage', { getItem: () => null, setItem: () => undefined, removeItem: () => undefined });
    vi.stubGlobal('fetch', async (url: string) => {
      fetched.push(url);
      const id = Number(/hypotheses\/(\d+)/.exec(url)![1]);
      return new Response(JSON.stringify({ id, cells: [[80, 10, 0.9], [81, 10, 0.9], [82, 11, 0.2]] }), { status: 200 });
    });
  });
  afterEach(() => vi.unstubAllGlobals());

  it('builds the picture from a snapshot, its tiles and deltas', async () => {
    const c = new SessionClient('s-1', () => 1000);
    const events: string[] = [];
    c.subscribe((e) => events.push(e.kind));
    c.handle(message(snapshotMessage));
    c.handleTile(frame(0, 0, 0));
    c.handleTile(frame(1, 0, 100));
    expect(c.map.tiles.size).toBe(2);
    expect(c.map.loadingSnapshot).toBe(false);
    expect(c.robot.trajectory.length).toBe(3);
    expect(c.robot.particles).toHaveLength(2);
    expect(c.stats.latest.neff).toBe(22.5);
    c.handle(message({ type: 'trajectory', first_index: 3, poses: [[2, 0, 0, 102]] }));
    c.handle(message({ type: 'pose', x: 2, y: 0, theta: 0 }));
    c.handle(message({ type: 'stats', stats: { neff: 12, scan_rate_hz: 10 } }));
    c.handle(message(hypothesisAdded));
    expect(c.robot.trajectory.length).toBe(4);
    expect(c.stats.series.neff).toEqual([12]);
    expect(c.hypotheses.entries.size).toBe(2);
    await vi.waitFor(() => expect(c.hypotheses.entries.get(4)?.cellsState).toBe('loaded'));
    await vi.waitFor(() => expect(c.hypotheses.entries.get(3)?.cellsState).toBe('loaded'));
    expect(fetched.sort()).toEqual([
      'http://127.0.0.1:8080/api/sessions/s-1/hypotheses/3',
      'http://127.0.0.1:8080/api/sessions/s-1/hypotheses/4',
    ]);
    expect(c.hypotheses.entries.get(3)!.cells!.maxX).toBe(82);
    c.handle(message({ type: 'session', session_id: 's-1', status: 'closed' }));
    expect(c.status).toBe('closed');
    expect(events).toContain('snapshot');
    expect(events).toContain('tile');
    c.stop();
  });

  it('retries the cells of a hypothesis the server has not stored yet', async () => {
    let calls = 0;
    vi.stubGlobal('fetch', async () => {
      calls++;
      if (calls === 1) return new Response(JSON.stringify({ error: { status: 404, code: 'not_found', message: 'no hypothesis 3' } }), { status: 404 });
      return new Response(JSON.stringify({ id: 3, cells: [[1, 1, 0.9]] }), { status: 200 });
    });
    vi.useFakeTimers();
    try {
      const c = new SessionClient('s-1');
      c.handle(message(snapshotMessage));
      await vi.waitFor(() => expect(c.hypotheses.entries.get(3)?.cellsState).toBe('retry'));
      expect(c.errors).toEqual([]);
      await vi.advanceTimersByTimeAsync(1100);
      await vi.waitFor(() => expect(c.hypotheses.entries.get(3)?.cellsState).toBe('loaded'));
      expect(calls).toBe(2);
      c.stop();
    } finally {
      vi.useRealTimers();
    }
  });

  it('holds what arrives while paused and applies it in order on resume', () => {
    const c = new SessionClient('s-1');
    c.handle(message({ ...snapshotMessage, hypotheses: [], tile_count: 0 }));
    c.pause();
    const feed = (c as unknown as { connection: { handlers: { onMessage(m: LiveMessage): void; onTile(f: Uint8Array): void } } }).connection.handlers;
    feed.onMessage(message({ type: 'trajectory', first_index: 3, poses: [[9, 9, 0, 1]] }));
    feed.onTile(frame(5, 5, 50));
    feed.onMessage(message({ type: 'pose', x: 9, y: 9, theta: 0 }));
    expect(c.held).toBe(3);
    expect(c.robot.trajectory.length).toBe(3);
    expect(c.map.tiles.size).toBe(0);
    expect(c.robot.pose).toEqual(snapshotMessage.pose);
    c.resume();
    expect(c.held).toBe(0);
    expect(c.robot.trajectory.length).toBe(4);
    expect(c.map.tiles.size).toBe(1);
    expect(c.robot.pose).toEqual({ x: 9, y: 9, theta: 0 });
  });

  it('reports a corrupt tile and a server error without throwing', () => {
    const c = new SessionClient('s-1');
    c.handle(message({ ...snapshotMessage, hypotheses: [], tile_count: 1 }));
    const bad = frame(0, 0, 5);
    bad[bad.length - 1] ^= 1;
    c.handleTile(bad);
    c.handle(message({ type: 'error', code: 'unknown_session', message: 'no session s-1' }));
    expect(c.errors.map((e) => e.message)).toEqual([expect.stringMatching(/checksum/), 'unknown_session: no session s-1']);
    expect(c.map.tiles.size).toBe(0);
  });
});
