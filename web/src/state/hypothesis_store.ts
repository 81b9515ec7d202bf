// The structure predictions of a session: the server's descriptions (live messages) and, fetched
// on demand from REST, their predicted cells. Pure data, no DOM.
import type { Hypothesis } from '../net/protocol';

// Predicted cells of one hypothesis, packed: cell x, cell y (grid indices) and occupancy 0..1.
export interface HypothesisCells {
  xs: Int32Array;
  ys: Int32Array;
  occupancy: Float32Array;
  // Bounding box in cells, inclusive.
  minX: number;
  minY: number;
  maxX: number;
  maxY: number;
}

export interface HypothesisEntry {
  h: Hypothesis;
  cells: HypothesisCells | null;
  cellsState: 'none' | 'loading' | 'retry' | 'loaded' | 'error';
  // Bumped whenever 'h' or 'cells' change, so a layer can cache per entry.
  revision: number;
}

export type HypothesisSortKey = 'id' | 'psi' | 'area' | 'status' | 'hit_ratio';

// The predictor's statuses (pending until later scans confirm or refute a prediction; expired when
// it was never checked), in the order the UI lists them.
export const kHypothesisStatuses = ['pending', 'confirmed', 'refuted', 'expired'] as const;

export function packCells(cells: [number, number, number][]): HypothesisCells {
  const n = cells.length;
  const xs = new Int32Array(n), ys = new Int32Array(n), occupancy = new Float32Array(n);
  let minX = Infinity, minY = Infinity, maxX = -Infinity, maxY = -Infinity;
  for (let i = 0; i < n; i++) {
    const [x, y, p] = cells[i];
    xs[i] = x;
    ys[i] = y;
    occupancy[i] = p;
    if (x < minX) minX = x;
    if (x > maxX) maxX = x;
    if (y < minY) minY = y;
    if (y > maxY) maxY = y;
  }
  if (n === 0) minX = minY = maxX = maxY = 0;
  return { xs, ys, occupancy, minX, minY, maxX, maxY };
}

export class HypothesisStore {
  version = 0;
  readonly entries = new Map<number, HypothesisEntry>();
  selected: number | null = null;

  applySnapshot(list: Hypothesis[]): void {
    const keep = new Set(list.map((h) => h.id));
    for (const id of this.entries.keys()) if (!keep.has(id)) this.entries.delete(id);
    for (const h of list) this.upsert(h);
    if (this.selected !== null && !this.entries.has(this.selected)) this.selected = null;
    this.version++;
  }

  applyEvent(event: 'added' | 'updated' | 'removed', h: Hypothesis | { id: number }): void {
    if (event === 'removed') {
      this.entries.delete(h.id);
      if (this.selected === h.id) this.selected = null;
    } else {
      this.upsert(h as Hypothesis);
    }
    this.version++;
  }

  // Ids of hypotheses whose cells have not been requested yet.
  missingCells(): number[] {
    const out: number[] = [];
    for (const e of this.entries.values()) if (e.cellsState === 'none' && e.h.cell_count > 0) out.push(e.h.id);
    return out;
  }

  // A fetch failed and waits to be retried ('retry'), or the wait is over ('none' again).
  markRetry(id: number, waiting: boolean): void {
    const e = this.entries.get(id);
    if (e && (e.cellsState === 'loading' || e.cellsState === 'retry')) e.cellsState = waiting ? 'retry' : 'none';
  }

  markLoading(id: number): void {
    const e = this.entries.get(id);
    if (e) e.cellsState = 'loading';
  }

  setCells(id: number, cells: HypothesisCells | null): void {
    const e = this.entries.get(id);
    if (!e) return;
    e.cells = cells;
    e.cellsState = cells ? 'loaded' : 'error';
    e.revision++;
    this.version++;
  }

  select(id: number | null): void {
    this.selected = id !== null && this.entries.has(id) ? id : null;
    this.version++;
  }

  list(sort: HypothesisSortKey = 'id', descending = true, status: string | null = null): Hypothesis[] {
    const rows = [...this.entries.values()].map((e) => e.h).filter((h) => status === null || h.status === status);
    const dir = descending ? -1 : 1;
    rows.sort((a, b) => {
      const va = a[sort], vb = b[sort];
      const c = typeof va === 'string' ? va.localeCompare(vb as string) : (va as number) - (vb as number);
      return c !== 0 ? dir * c : dir * (a.id - b.id);
    });
    return rows;
  }

  counts(): Record<string, number> & { total: number } {
    const out: Record<string, number> & { total: number } = { total: 0 };
    for (const s of kHypothesisStatuses) out[s] = 0;
    for (const e of this.entries.values()) {
      out.total++;
      out[e.h.status] = (out[e.h.status] ?? 0) + 1;
    }
    return out;
  }

  clear(): void {
    this.entries.clear();
    this.selected = null;
    this.version++;
  }

  private upsert(h: Hypothesis): void {
    const e = this.entries.get(h.id);
    if (e) {
      e.h = h;
      e.revision++;
    } else {
      this.entries.set(h.id, { h, cells: null, cellsState: 'none', revision: 0 });
    }
  }
}
