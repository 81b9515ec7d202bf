// The occupancy map as the viewer knows it: square tiles of cells (one byte per cell, percent
// occupied, 255 unknown), keyed by tile index. Pure data, no DOM: the map layer reads the tiles
// that changed (takeDirty) and uploads just those.
//
// Snapshots do not clear the picture: after a reconnect the server resends every tile, so the old
// tiles are kept until the snapshot's last tile arrived and only then are the ones it did not
// resend dropped. The map never flashes empty on a reconnect.
import type { Tile } from '../net/protocol';

export interface StoredTile {
  tx: number;
  ty: number;
  revision: number;
  cells: Uint8Array;
  generation: number;
}

export interface TileBounds {
  minTx: number;
  minTy: number;
  maxTx: number;
  maxTy: number;
}

export const tileKey = (tx: number, ty: number): string => `${tx},${ty}`;

function allUnknown(cells: Uint8Array): boolean {
  for (let i = 0; i < cells.length; i++) if (cells[i] !== 255) return false;
  return true;
}

export class MapStore {
  resolution = 0.05;
  tileSize = 64;
  // Bumped on every change; views compare it to know whether to redraw.
  version = 0;
  tilesApplied = 0;
  readonly tiles = new Map<string, StoredTile>();
  private dirty = new Set<string>();
  private removed = new Set<string>();
  private generation = 0;
  private snapshotTilesExpected = 0;
  private snapshotTilesSeen = 0;
  private geometryChanged = false;

  // Starts a new picture of 'resolution' and 'tileSize' with 'tileCount' tiles to follow.
  applySnapshot(resolution: number, tileSize: number, tileCount: number): void {
    if (resolution !== this.resolution || tileSize !== this.tileSize) {
      for (const key of this.tiles.keys()) this.removed.add(key);
      this.tiles.clear();
      this.dirty.clear();
      this.resolution = resolution;
      this.tileSize = tileSize;
      this.geometryChanged = true;
    }
    this.generation++;
    this.snapshotTilesExpected = tileCount;
    this.snapshotTilesSeen = 0;
    if (tileCount === 0) this.dropStale();
    this.version++;
  }

  // Stores a decoded tile. The cells are copied ('tile.cells' may be a reused scratch buffer).
  // A tile whose cells are all unknown removes the tile (live.md: the best particle changed to
  // one that never saw that area). Frames are applied in arrival order, whatever their revision:
  // the socket delivers them in order, and a tile's revision goes down legitimately when the best
  // particle changes (a removed tile comes with revision 0).
  // Returns an error message for a tile that does not fit the current geometry.
  applyTile(tile: Tile): string | null {
    if (tile.size !== this.tileSize) return `tile (${tile.tx}, ${tile.ty}) has size ${tile.size}, map tiles are ${this.tileSize}`;
    const key = tileKey(tile.tx, tile.ty);
    this.tilesApplied++;
    this.version++;
    if (this.snapshotTilesExpected > 0) this.snapshotTilesSeen++;
    if (allUnknown(tile.cells)) {
      if (this.tiles.delete(key)) {
        this.dirty.delete(key);
        this.removed.add(key);
      }
    } else {
      this.storeTile(key, tile);
    }
    if (this.snapshotTilesExpected > 0 && this.snapshotTilesSeen >= this.snapshotTilesExpected) this.dropStale();
    return null;
  }

  private storeTile(key: string, tile: Tile): void {
    let stored = this.tiles.get(key);
    if (!stored) {
      stored = { tx: tile.tx, ty: tile.ty, revision: 0, cells: new Uint8Array(tile.cells.length), generation: 0 };
      this.tiles.set(key, stored);
    }
    stored.cells.set(tile.cells);
    stored.revision = tile.revision;
    stored.generation = this.generation;
    this.dirty.add(key);
    this.removed.delete(key);
  }

  // True while the tiles of the last snapshot are still arriving.
  get loadingSnapshot(): boolean {
    return this.snapshotTilesExpected > 0;
  }

  // Returns and clears what changed since the last call: tiles to (re)draw, tiles to erase, and
  // whether the geometry changed (every layer resource must then be recreated).
  takeDirty(): { changed: StoredTile[]; removed: { tx: number; ty: number }[]; geometryChanged: boolean } {
    const changed: StoredTile[] = [];
    for (const key of this.dirty) {
      const t = this.tiles.get(key);
      if (t) changed.push(t);
    }
    const removed = [...this.removed].map((key) => {
      const [tx, ty] = key.split(',').map(Number);
      return { tx, ty };
    });
    const geometryChanged = this.geometryChanged;
    this.dirty.clear();
    this.removed.clear();
    this.geometryChanged = false;
    return { changed, removed, geometryChanged };
  }

  // Marks every tile dirty (a layer that lost its resources redraws from the store).
  markAllDirty(): void {
    for (const key of this.tiles.keys()) this.dirty.add(key);
    this.version++;
  }

  bounds(): TileBounds | null {
    if (this.tiles.size === 0) return null;
    const b = { minTx: Infinity, minTy: Infinity, maxTx: -Infinity, maxTy: -Infinity };
    for (const t of this.tiles.values()) {
      b.minTx = Math.min(b.minTx, t.tx);
      b.minTy = Math.min(b.minTy, t.ty);
      b.maxTx = Math.max(b.maxTx, t.tx);
      b.maxTy = Math.max(b.maxTy, t.ty);
    }
    return b;
  }

  // The box of known cells in world metres, or null when nothing is known.
  knownWorldBounds(): { minX: number; minY: number; maxX: number; maxY: number } | null {
    let minCx = Infinity, minCy = Infinity, maxCx = -Infinity, maxCy = -Infinity;
    const s = this.tileSize;
    for (const t of this.tiles.values()) {
      const baseX = t.tx * s, baseY = t.ty * s;
      // Skip the tile quickly if its box cannot widen the current one.
      if (baseX >= minCx && baseX + s - 1 <= maxCx && baseY >= minCy && baseY + s - 1 <= maxCy) continue;
      for (let r = 0; r < s; r++) {
        const row = r * s;
        for (let c = 0; c < s; c++) {
          if (t.cells[row + c] === 255) continue;
          const x = baseX + c, y = baseY + r;
          if (x < minCx) minCx = x;
          if (x > maxCx) maxCx = x;
          if (y < minCy) minCy = y;
          if (y > maxCy) maxCy = y;
        }
      }
    }
    if (minCx === Infinity) return null;
    const res = this.resolution;
    return { minX: minCx * res, minY: minCy * res, maxX: (maxCx + 1) * res, maxY: (maxCy + 1) * res };
  }

  // Occupancy of the cell containing world point (x, y): 0..100, 255 unknown, null outside the map.
  cellAt(x: number, y: number): number | null {
    const cx = Math.floor(x / this.resolution), cy = Math.floor(y / this.resolution);
    const s = this.tileSize;
    const tx = Math.floor(cx / s), ty = Math.floor(cy / s);
    const t = this.tiles.get(tileKey(tx, ty));
    if (!t) return null;
    return t.cells[(cy - ty * s) * s + (cx - tx * s)];
  }

  // A test 'is cell (cx, cy) mapped?' (any value but unknown) for many cells in a row: it keeps
  // the last tile looked up, since neighbouring cells mostly share a tile.
  knownCellTest(): (cx: number, cy: number) => boolean {
    const s = this.tileSize;
    let lastKey = '';
    let last: StoredTile | undefined;
    return (cx, cy) => {
      const tx = Math.floor(cx / s), ty = Math.floor(cy / s);
      const key = tileKey(tx, ty);
      if (key !== lastKey) {
        lastKey = key;
        last = this.tiles.get(key);
      }
      return last !== undefined && last.cells[(cy - ty * s) * s + (cx - tx * s)] !== 255;
    };
  }

  // Counts of known, free (< 25 %) and occupied (> 65 %) cells.
  cellCounts(): { known: number; free: number; occupied: number } {
    let known = 0, free = 0, occupied = 0;
    for (const t of this.tiles.values()) {
      const c = t.cells;
      for (let i = 0; i < c.length; i++) {
        const v = c[i];
        if (v === 255) continue;
        known++;
        if (v < 25) free++;
        else if (v > 65) occupied++;
      }
    }
    return { known, free, occupied };
  }

  clear(): void {
    for (const key of this.tiles.keys()) this.removed.add(key);
    this.tiles.clear();
    this.dirty.clear();
    this.snapshotTilesExpected = 0;
    this.snapshotTilesSeen = 0;
    this.version++;
  }

  private dropStale(): void {
    for (const [key, t] of this.tiles) {
      if (t.generation !== this.generation) {
        this.tiles.delete(key);
        this.dirty.delete(key);
        this.removed.add(key);
      }
    }
    this.snapshotTilesExpected = 0;
    this.snapshotTilesSeen = 0;
  }
}
