import { describe, expect, it } from 'vitest';
import { MapStore } from '../src/state/map_store';

const tile = (tx: number, ty: number, value: number, revision = 1, size = 64) => ({
  tx,
  ty,
  size,
  revision,
  cells: new Uint8Array(size * size).fill(value),
});

describe('MapStore', () => {
  it('applies a snapshot and its tiles, recording what changed', () => {
    const s = new MapStore();
    s.applySnapshot(0.05, 64, 2);
    expect(s.applyTile(tile(0, 0, 0))).toBeNull();
    expect(s.applyTile(tile(1, -1, 100))).toBeNull();
    const d = s.takeDirty();
    expect(d.changed.map((t) => [t.tx, t.ty])).toEqual([[0, 0], [1, -1]]);
    expect(s.takeDirty().changed).toEqual([]);
    expect(s.bounds()).toEqual({ minTx: 0, minTy: -1, maxTx: 1, maxTy: 0 });
  });

  it('copies cells, so the decoder may reuse its buffer', () => {
    const s = new MapStore();
    const t = tile(0, 0, 10);
    s.applyTile(t);
    t.cells.fill(99);
    expect(s.tiles.get('0,0')!.cells[0]).toBe(10);
  });

  it('applies a delta over the same tile', () => {
    const s = new MapStore();
    s.applySnapshot(0.05, 64, 1);
    s.applyTile(tile(2, 3, 255));
    s.takeDirty();
    const v = s.version;
    s.applyTile(tile(2, 3, 40, 2));
    expect(s.version).toBeGreaterThan(v);
    expect(s.tiles.get('2,3')!.revision).toBe(2);
    expect(s.takeDirty().changed.length).toBe(1);
    expect(s.cellAt(2 * 64 * 0.05 + 0.01, 3 * 64 * 0.05 + 0.01)).toBe(40);
  });

  it('keeps the old picture during a resubscribe and drops only what the new snapshot lacks', () => {
    const s = new MapStore();
    s.applySnapshot(0.05, 64, 3);
    s.applyTile(tile(0, 0, 1));
    s.applyTile(tile(1, 0, 1));
    s.applyTile(tile(2, 0, 1));
    s.takeDirty();
    // Reconnect: a snapshot of two tiles; (2, 0) no longer exists on the server.
    s.applySnapshot(0.05, 64, 2);
    expect(s.tiles.size).toBe(3);
    expect(s.loadingSnapshot).toBe(true);
    s.applyTile(tile(0, 0, 2));
    expect(s.tiles.size).toBe(3);
    s.applyTile(tile(1, 0, 2));
    expect(s.loadingSnapshot).toBe(false);
    expect([...s.tiles.keys()].sort()).toEqual(['0,0', '1,0']);
    expect(s.takeDirty().removed).toEqual([{ tx: 2, ty: 0 }]);
  });

  it('clears everything when the geometry changes', () => {
    const s = new MapStore();
    s.applySnapshot(0.05, 64, 1);
    s.applyTile(tile(0, 0, 1));
    s.takeDirty();
    s.applySnapshot(0.1, 64, 0);
    expect(s.tiles.size).toBe(0);
    const d = s.takeDirty();
    expect(d.geometryChanged).toBe(true);
    expect(d.removed).toEqual([{ tx: 0, ty: 0 }]);
  });

  it('removes a tile sent with every cell unknown, whatever its revision', () => {
    const s = new MapStore();
    s.applySnapshot(0.05, 64, 0);
    s.applyTile(tile(4, 4, 50, 9));
    s.takeDirty();
    s.applyTile(tile(4, 4, 255, 0));
    expect(s.tiles.size).toBe(0);
    expect(s.takeDirty()).toMatchObject({ changed: [], removed: [{ tx: 4, ty: 4 }] });
    // A later frame brings it back, with a lower revision than before.
    s.applyTile(tile(4, 4, 20, 3));
    expect(s.tiles.get('4,4')!.revision).toBe(3);
  });

  it('counts an all-unknown snapshot tile towards the snapshot', () => {
    const s = new MapStore();
    s.applyTile(tile(0, 0, 1));
    s.applySnapshot(0.05, 64, 2);
    s.applyTile(tile(1, 1, 255));
    s.applyTile(tile(2, 2, 7));
    expect(s.loadingSnapshot).toBe(false);
    expect([...s.tiles.keys()]).toEqual(['2,2']);
  });

  it('rejects a tile of the wrong size', () => {
    const s = new MapStore();
    s.applySnapshot(0.05, 64, 0);
    expect(s.applyTile(tile(0, 0, 1, 1, 32))).toMatch(/size 32/);
  });

  it('an empty snapshot drops everything at once', () => {
    const s = new MapStore();
    s.applyTile(tile(0, 0, 1));
    s.applySnapshot(0.05, 64, 0);
    expect(s.tiles.size).toBe(0);
  });

  it('finds the known bounds in world metres and counts cells', () => {
    const s = new MapStore();
    const t = tile(1, 0, 255);
    t.cells[5 * 64 + 3] = 0; // cell (67, 5)
    t.cells[10 * 64 + 20] = 90; // cell (84, 10)
    s.applyTile(t);
    const b = s.knownWorldBounds()!;
    expect(b.minX).toBeCloseTo(67 * 0.05);
    expect(b.maxX).toBeCloseTo(85 * 0.05);
    expect(b.minY).toBeCloseTo(5 * 0.05);
    expect(b.maxY).toBeCloseTo(11 * 0.05);
    expect(s.cellCounts()).toEqual({ known: 2, free: 1, occupied: 1 });
    expect(s.cellAt(-1, -1)).toBeNull();
  });
});
