import { describe, expect, it } from 'vitest';
import { decodeLiveMessage, type Hypothesis } from '../src/net/protocol';
import { HypothesisStore, packCells } from '../src/state/hypothesis_store';
import { hypothesisAdded, snapshotMessage } from './fixtures/live';

const h = (id: number, psi: number, status = 'pending', area = 1): Hypothesis => ({
  id,
  time: 0,
  target_cell: [0, 0],
  reference_cell: [0, 0],
  theta: 0,
  translation: [0, 0],
  psi,
  area,
  cell_count: 2,
  status,
  hit_ratio: 0,
  psi_observed: null,
});

describe('HypothesisStore', () => {
  it('loads a snapshot and applies added, updated and removed events', () => {
    const s = new HypothesisStore();
    const snap = decodeLiveMessage(snapshotMessage);
    if (!snap.ok || snap.value.type !== 'snapshot') throw new Error('fixture');
    s.applySnapshot(snap.value.hypotheses);
    expect([...s.entries.keys()]).toEqual([3]);
    const added = decodeLiveMessage(hypothesisAdded);
    if (!added.ok || added.value.type !== 'hypothesis') throw new Error('fixture');
    s.applyEvent(added.value.event, added.value.hypothesis);
    expect(s.entries.size).toBe(2);
    s.applyEvent('updated', { ...h(4, 0.9, 'confirmed'), hit_ratio: 0.8 });
    expect(s.entries.get(4)!.h.status).toBe('confirmed');
    expect(s.entries.get(4)!.revision).toBe(1);
    s.select(4);
    s.applyEvent('removed', { id: 4 });
    expect(s.entries.has(4)).toBe(false);
    expect(s.selected).toBeNull();
  });

  it('a snapshot replaces the list but keeps loaded cells of hypotheses that stay', () => {
    const s = new HypothesisStore();
    s.applySnapshot([h(1, 0.5), h(2, 0.6)]);
    s.setCells(1, packCells([[1, 2, 0.9]]));
    s.applySnapshot([h(1, 0.55)]);
    expect(s.entries.size).toBe(1);
    expect(s.entries.get(1)!.cells!.xs[0]).toBe(1);
    expect(s.entries.get(1)!.h.psi).toBe(0.55);
  });

  it('sorts, filters and counts', () => {
    const s = new HypothesisStore();
    s.applySnapshot([h(1, 0.5, 'confirmed', 3), h(2, 0.9, 'refuted', 1), h(3, 0.7, 'confirmed', 2)]);
    expect(s.list('psi', true).map((x) => x.id)).toEqual([2, 3, 1]);
    expect(s.list('area', false).map((x) => x.id)).toEqual([2, 3, 1]);
    expect(s.list('id', true, 'confirmed').map((x) => x.id)).toEqual([3, 1]);
    expect(s.counts()).toMatchObject({ total: 3, confirmed: 2, refuted: 1, pending: 0 });
  });

  it('tracks which cells to fetch', () => {
    const s = new HypothesisStore();
    s.applySnapshot([h(1, 0.5), { ...h(2, 0.5), cell_count: 0 }]);
    expect(s.missingCells()).toEqual([1]);
    s.markLoading(1);
    expect(s.missingCells()).toEqual([]);
    s.setCells(1, null);
    expect(s.entries.get(1)!.cellsState).toBe('error');
  });

  it('packs cells with their bounding box', () => {
    const c = packCells([[5, -2, 0.9], [7, 3, 0.1]]);
    expect([c.minX, c.minY, c.maxX, c.maxY]).toEqual([5, -2, 7, 3]);
    expect(c.occupancy[1]).toBeCloseTo(0.1);
  });
});
