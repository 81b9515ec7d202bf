import { afterEach, beforeEach, describe, expect, it, vi } from 'vitest';
import { backoffDelay, kBackoffMaxMs, LiveConnection, type ConnectionState } from '../src/net/connection';
import { encodeParticleFrame, encodeScanFrame } from '../src/net/protocol';
import { snapshotMessage } from './fixtures/live';

// A WebSocket stand-in the test drives by hand.
class FakeSocket {
  static all: FakeSocket[] = [];
  binaryType = 'blob';
  onopen: (() => void) | null = null;
  onclose: ((e: { code: number; reason: string }) => void) | null = null;
  onerror: (() => void) | null = null;
  onmessage: ((e: { data: unknown }) => void) | null = null;
  closed = false;
  constructor(readonly url: string) {
    FakeSocket.all.push(this);
  }
  close(): void {
    this.closed = true;
  }
  open(): void {
    this.onopen?.();
  }
  receive(data: unknown): void {
    this.onmessage?.({ data });
  }
  drop(code = 1006, reason = ''): void {
    this.onclose?.({ code, reason });
  }
}

describe('backoffDelay', () => {
  it('doubles from 0.5 s up to the cap, with jitter', () => {
    expect(backoffDelay(0, () => 0.5)).toBe(500);
    expect(backoffDelay(1, () => 0.5)).toBe(1000);
    expect(backoffDelay(3, () => 0.5)).toBe(4000);
    expect(backoffDelay(50, () => 0.5)).toBe(kBackoffMaxMs);
    expect(backoffDelay(0, () => 0)).toBe(400);
    expect(backoffDelay(0, () => 1)).toBe(600);
  });
});

describe('LiveConnection', () => {
  beforeEach(() => {
    vi.useFakeTimers();
    FakeSocket.all = [];
  });
  afterEach(() => vi.useRealTimers());

  function connect() {
    const states: ConnectionState[] = [];
    const messages: unknown[] = [];
    const tiles: ArrayBuffer[] = [];
    const invalid: string[] = [];
    const c = new LiveConnection(
      () => 'ws://server/api/sessions/s-1/live',
      {
        onMessage: (m) => messages.push(m),
        onTile: (t) => tiles.push(t),
        onInvalid: (e) => invalid.push(e),
        onState: (s) => states.push(s),
      },
      (u) => new FakeSocket(u) as unknown as WebSocket,
    );
    return { c, states, messages, tiles, invalid };
  }

  it('decodes text, scan and particle frames and passes tile frames through', () => {
    const { c, messages, tiles, invalid, states } = connect();
    c.start();
    const s = FakeSocket.all[0];
    expect(s.binaryType).toBe('arraybuffer');
    s.open();
    s.receive(JSON.stringify(snapshotMessage));
    const tile = new Uint8Array(30);
    tile.set([0x50, 0x53, 0x54, 0x4c]);
    s.receive(tile.buffer);
    const scan = encodeScanFrame({ type: 'scan', pose: { x: 1, y: 2, theta: 0 }, angle_min: -1, angle_increment: 0.5, max_range: 8, ranges: [1.5, null] }, 7);
    s.receive(scan.buffer);
    s.receive(encodeParticleFrame([[1, 2, 0.5, 0.25]]).buffer);
    s.receive(new ArrayBuffer(30));
    s.receive(scan.slice(0, 41).buffer);
    s.receive('{not json');
    s.receive(JSON.stringify({ type: 'pose', x: 'bad' }));
    expect(messages).toHaveLength(3);
    expect(messages[1]).toMatchObject({ type: 'scan', seq: 7, ranges: [1.5, null] });
    expect(messages[2]).toMatchObject({ type: 'particles', poses: [[1, 2, 0.5, 0.25]] });
    expect(tiles).toHaveLength(1);
    expect(invalid).toHaveLength(4);
    expect(states).toEqual(['connecting', 'open']);
    expect(c.counters).toMatchObject({ messages: 7, tiles: 1, invalid: 4 });
  });

  it('reconnects with backoff after a loss and resubscribes by opening a new socket', () => {
    const { c, states } = connect();
    c.start();
    FakeSocket.all[0].open();
    FakeSocket.all[0].drop(1001, 'server shutting down');
    expect(states.at(-1)).toBe('reconnecting');
    vi.advanceTimersByTime(300);
    expect(FakeSocket.all).toHaveLength(1);
    vi.advanceTimersByTime(400); // 0.5 s +- 20 %
    expect(FakeSocket.all).toHaveLength(2);
    // The server is still down: the next attempt waits longer.
    FakeSocket.all[1].drop();
    vi.advanceTimersByTime(700);
    expect(FakeSocket.all).toHaveLength(2);
    vi.advanceTimersByTime(600);
    expect(FakeSocket.all).toHaveLength(3);
    FakeSocket.all[2].open();
    expect(states.at(-1)).toBe('open');
    // A message resets the backoff.
    FakeSocket.all[2].receive(JSON.stringify(snapshotMessage));
    FakeSocket.all[2].drop();
    vi.advanceTimersByTime(700);
    expect(FakeSocket.all).toHaveLength(4);
  });

  it('stops retrying when the server refuses (1008) and when stopped', () => {
    const { c, states } = connect();
    c.start();
    FakeSocket.all[0].drop(1008, 'unknown session');
    expect(states.at(-1)).toBe('failed');
    vi.advanceTimersByTime(60000);
    expect(FakeSocket.all).toHaveLength(1);
    c.reconnectNow();
    expect(FakeSocket.all).toHaveLength(2);
    c.stop();
    expect(FakeSocket.all[1].closed).toBe(true);
    vi.advanceTimersByTime(60000);
    expect(FakeSocket.all).toHaveLength(2);
    expect(states.at(-1)).toBe('stopped');
  });
});
