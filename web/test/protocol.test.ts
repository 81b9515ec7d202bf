import { zlibSync } from 'fflate';
import { describe, expect, it } from 'vitest';
import {
  adler32,
  binaryKind,
  decodeLiveMessage,
  decodeParticleFrame,
  decodeScanFrame,
  decodeTileFrame,
  encodeParticleFrame,
  encodeScanFrame,
  encodeTileFrame,
  type ScanMessage,
} from '../src/net/protocol';
import { hypothesisAdded, snapshotMessage } from './fixtures/live';

const zlib = (d: Uint8Array) => zlibSync(d);

function tileCells(fill: (i: number) => number, size = 64): Uint8Array {
  const c = new Uint8Array(size * size);
  for (let i = 0; i < c.length; i++) c[i] = fill(i);
  return c;
}

describe('decodeTileFrame', () => {
  it('round-trips a frame as the server writes it', () => {
    const cells = tileCells((i) => (i % 7 === 0 ? 255 : i % 101));
    const frame = encodeTileFrame({ tx: -3, ty: 5, size: 64, revision: 2 ** 40 + 17, cells }, zlib);
    expect(String.fromCharCode(...frame.subarray(0, 4))).toBe('PSTL');
    const d = decodeTileFrame(frame.buffer as ArrayBuffer);
    expect(d.ok).toBe(true);
    if (!d.ok) return;
    expect(d.value.tx).toBe(-3);
    expect(d.value.ty).toBe(5);
    expect(d.value.size).toBe(64);
    expect(d.value.revision).toBe(2 ** 40 + 17);
    expect(d.value.cells).toEqual(cells);
  });

  it('decodes into a reused scratch buffer', () => {
    const scratch = new Uint8Array(64 * 64);
    const frame = encodeTileFrame({ tx: 0, ty: 0, size: 64, revision: 1, cells: tileCells(() => 42) }, zlib);
    const d = decodeTileFrame(frame, scratch);
    expect(d.ok && d.value.cells.buffer).toBe(scratch.buffer);
  });

  it('rejects a bad magic, a short frame, an unknown encoding and a corrupt payload', () => {
    const good = encodeTileFrame({ tx: 1, ty: 1, size: 64, revision: 1, cells: tileCells((i) => i % 100) }, zlib);
    const badMagic = good.slice();
    badMagic[0] = 0x51;
    expect(decodeTileFrame(badMagic).ok).toBe(false);
    expect(decodeTileFrame(good.slice(0, 10)).ok).toBe(false);
    expect(decodeTileFrame(good.slice(0, 24)).ok).toBe(false);
    const badEncoding = good.slice();
    badEncoding[14] = 7;
    const e = decodeTileFrame(badEncoding);
    expect(!e.ok && e.error).toMatch(/encoding 7/);
    const corrupt = good.slice();
    corrupt[corrupt.length - 6] ^= 0xff;
    expect(decodeTileFrame(corrupt).ok).toBe(false);
  });

  it('rejects a payload with the wrong number of cells', () => {
    const short = encodeTileFrame({ tx: 0, ty: 0, size: 64, revision: 1, cells: new Uint8Array(100) }, zlib);
    expect(decodeTileFrame(short).ok).toBe(false);
    // Longer than size*size: fflate truncates into the buffer; the checksum catches it.
    const long = encodeTileFrame({ tx: 0, ty: 0, size: 64, revision: 1, cells: tileCells((i) => i & 0xff, 65) }, zlib);
    const view = new DataView(long.buffer);
    view.setUint16(12, 64, true);
    expect(decodeTileFrame(long).ok).toBe(false);
  });

  it('computes Adler-32 like zlib', () => {
    expect(adler32(new TextEncoder().encode('Wikipedia'))).toBe(0x11e60398);
    expect(adler32(new Uint8Array(100000).fill(255))).toBe(adler32(new Uint8Array(100000).fill(255)));
  });
});

describe('decodeLiveMessage', () => {
  it('accepts the server snapshot and normalises it', () => {
    const d = decodeLiveMessage(snapshotMessage);
    expect(d.ok).toBe(true);
    if (!d.ok || d.value.type !== 'snapshot') return;
    expect(d.value.tile_count).toBe(2);
    expect(d.value.hypotheses[0].psi_observed).toBeNull();
    expect(d.value.target?.path.length).toBe(3);
  });

  it('keeps the site map a hypothesis took its reference from', () => {
    const fromSite = { ...hypothesisAdded, hypothesis: { ...hypothesisAdded.hypothesis, reference_map: { site: 'site-1', version: 2 } } };
    const d = decodeLiveMessage(fromSite);
    expect(d.ok && d.value.type === 'hypothesis' && 'reference_map' in d.value.hypothesis && d.value.hypothesis.reference_map).toEqual({
      site: 'site-1',
      version: 2,
    });
    const own = decodeLiveMessage({ ...hypothesisAdded, hypothesis: { ...hypothesisAdded.hypothesis, reference_map: null } });
    expect(own.ok && own.value.type === 'hypothesis' && 'reference_map' in own.value.hypothesis && own.value.hypothesis.reference_map).toBeNull();
  });

  it('accepts every delta message type', () => {
    const messages = [
      { type: 'pose', x: 1, y: 2, theta: 0.1 },
      { type: 'stats', stats: { scans: 3 } },
      { type: 'exploration', frontiers: [[1, 1]], target: null },
      { type: 'trajectory', first_index: 10, poses: [[1, 2, 0, 5]] },
      hypothesisAdded,
      { type: 'hypothesis', event: 'removed', hypothesis: { id: 4 } },
      { type: 'session', session_id: 's-1', status: 'closed' },
      { type: 'error', code: 'unknown_session', message: 'no session' },
    ];
    for (const m of messages) expect(decodeLiveMessage(m)).toMatchObject({ ok: true, value: { type: m.type } });
  });

  it('reports malformed messages instead of throwing', () => {
    const bad = [
      null,
      'text',
      { type: 42 },
      { type: 'pose', x: 'a', y: 0, theta: 0 },
      { type: 'snapshot', session_id: 's', resolution: 0, tile_size: 64, tile_count: 0 },
      { ...snapshotMessage, trajectory: { first_index: 0, poses: [[1, 'x', 0]] } },
      { type: 'trajectory', first_index: -1, poses: [] },
      { type: 'hypothesis', event: 'changed', hypothesis: { id: 1 } },
      { type: 'hypothesis', event: 'added', hypothesis: { id: 1 } },
      { type: 'stats', stats: 3 },
      { type: 'something-new' },
      // Scans and particles come as binary frames only.
      { type: 'scan', pose: { x: 0, y: 0, theta: 0 }, angle_min: -1.57, angle_increment: 0.0175, ranges: [1, null, 2] },
      { type: 'particles', poses: [[1, 2, 0, 0.5]] },
    ];
    for (const m of bad) {
      const d = decodeLiveMessage(m);
      expect(d.ok, JSON.stringify(m)).toBe(false);
    }
  });
});

describe('binary scan and particle frames', () => {
  const scan: ScanMessage = {
    type: 'scan',
    pose: { x: 1.25, y: -2.5, theta: 0.5 },
    angle_min: -Math.PI / 2,
    angle_increment: Math.PI / 180,
    max_range: 8,
    ranges: [0.01, null, 2.31, 655.34, 7.99],
  };

  it('tells frames apart by their magic', () => {
    expect(binaryKind(encodeScanFrame(scan, 1))).toBe('scan');
    expect(binaryKind(encodeParticleFrame([]))).toBe('particles');
    expect(binaryKind(encodeTileFrame({ tx: 0, ty: 0, size: 64, revision: 1, cells: tileCells(() => 1) }, zlib))).toBe('tile');
    expect(binaryKind(new Uint8Array([0x50, 0x53, 0x58, 0x58]))).toBe('unknown');
    expect(binaryKind(new Uint8Array(2))).toBe('unknown');
  });

  it('round-trips a scan: centimetre ranges, no-return beams as null, the seq', () => {
    const frame = encodeScanFrame(scan, 2 ** 40 + 3);
    expect(frame.length).toBe(40 + 2 * 5);
    const d = decodeScanFrame(frame.buffer as ArrayBuffer);
    expect(d.ok).toBe(true);
    if (!d.ok) return;
    expect(d.value.seq).toBe(2 ** 40 + 3);
    expect(d.value.ranges).toEqual([0.01, null, 2.31, 655.34, 7.99]);
    expect(d.value.pose.x).toBeCloseTo(1.25, 6);
    expect(d.value.pose.theta).toBeCloseTo(0.5, 6);
    expect(d.value.angle_increment).toBeCloseTo(Math.PI / 180, 6);
    expect(d.value.max_range).toBe(8);
  });

  it('decodes a scan frame inside a larger buffer', () => {
    const frame = encodeScanFrame(scan, 9);
    const padded = new Uint8Array(frame.length + 3);
    padded.set(frame, 3);
    const d = decodeScanFrame(padded.subarray(3));
    expect(d.ok && d.value.seq).toBe(9);
  });

  it('rejects a truncated, oversized or unknown-encoding scan frame', () => {
    const frame = encodeScanFrame(scan, 1);
    expect(decodeScanFrame(frame.slice(0, 20)).ok).toBe(false);
    expect(decodeScanFrame(frame.slice(0, frame.length - 1)).ok).toBe(false);
    const longer = new Uint8Array(frame.length + 2);
    longer.set(frame);
    expect(decodeScanFrame(longer).ok).toBe(false);
    const badEncoding = frame.slice();
    badEncoding[6] = 2;
    const e = decodeScanFrame(badEncoding);
    expect(!e.ok && e.error).toMatch(/encoding 2/);
    const notFinite = frame.slice();
    new DataView(notFinite.buffer).setFloat32(16, NaN, true);
    expect(decodeScanFrame(notFinite).ok).toBe(false);
    expect(decodeScanFrame(encodeParticleFrame([])).ok).toBe(false);
  });

  it('round-trips particles at single precision', () => {
    const d = decodeParticleFrame(encodeParticleFrame([[1.5, -2.25, 0.125, 0.5], [3, 4, -1, 0.03125]]));
    expect(d).toEqual({ ok: true, value: { type: 'particles', poses: [[1.5, -2.25, 0.125, 0.5], [3, 4, -1, 0.03125]] } });
  });

  it('rejects a particle frame whose length does not match its count, or too many particles', () => {
    const frame = encodeParticleFrame([[1, 2, 3, 4]]);
    expect(decodeParticleFrame(frame.slice(0, frame.length - 4)).ok).toBe(false);
    const lying = frame.slice();
    new DataView(lying.buffer).setUint32(4, 5000, true);
    expect(decodeParticleFrame(lying).ok).toBe(false);
    const nan = frame.slice();
    new DataView(nan.buffer).setFloat32(8, Infinity, true);
    expect(decodeParticleFrame(nan).ok).toBe(false);
  });
});
