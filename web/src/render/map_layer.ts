// The occupancy map. Cells live in chunk canvases of 8 x 8 tiles (512 x 512 cells), created once
// when the map first reaches them; a changed tile is painted through the palette into a reused
// 64 x 64 ImageData and put into its chunk at its sub-rectangle. Drawing is then one drawImage per
// visible chunk (16 for a 2000 x 2000-cell map), clipped to the view in whole cells and snapped to
// whole device pixels so that neighbouring chunks meet without seams.
import type { MapStore, StoredTile } from '../state/map_store';
import { paintTile } from './palette';
import { makeCanvas, type DrawContext, type Layer } from './layer';

interface Chunk {
  cx: number;
  cy: number;
  canvas: OffscreenCanvas | HTMLCanvasElement;
  ctx: OffscreenCanvasRenderingContext2D | CanvasRenderingContext2D;
}

export const kTilesPerChunk = 8;

export class MapLayer implements Layer {
  readonly id = 'map';
  visible = true;
  // Tiles waiting for upload, latest state read from the store at upload time.
  private pending = new Map<string, StoredTile>();
  private chunks = new Map<string, Chunk>();
  private scratch: ImageData | null = null;
  private scratch32: Uint32Array | null = null;
  private tileSize = 0;
  private drawnVersion = -1;
  uploadedTiles = 0;

  constructor(
    private readonly store: MapStore,
    private palette: Uint32Array,
  ) {}

  setPalette(palette: Uint32Array): void {
    this.palette = palette;
    this.store.markAllDirty();
  }

  // Moves what changed in the store into the upload queue. Cheap; call once per frame.
  collect(): void {
    const { changed, removed, geometryChanged } = this.store.takeDirty();
    if (geometryChanged || this.tileSize !== this.store.tileSize) {
      this.disposeChunks();
      this.tileSize = this.store.tileSize;
      this.scratch = null;
      for (const t of this.store.tiles.values()) this.pending.set(`${t.tx},${t.ty}`, t);
    }
    for (const t of changed) this.pending.set(`${t.tx},${t.ty}`, t);
    for (const r of removed) {
      this.pending.delete(`${r.tx},${r.ty}`);
      this.eraseTile(r.tx, r.ty);
    }
  }

  get pendingTiles(): number {
    return this.pending.size;
  }

  // Uploads queued tiles until 'budgetMs' is spent; returns how many were uploaded. Tiles left
  // over go out on the next frame, so a large snapshot never freezes the page.
  upload(budgetMs = Infinity): number {
    if (this.pending.size === 0) return 0;
    const start = performance.now();
    let n = 0;
    for (const [key, tile] of this.pending) {
      this.pending.delete(key);
      this.uploadTile(tile);
      n++;
      if ((n & 7) === 0 && performance.now() - start > budgetMs) break;
    }
    this.uploadedTiles += n;
    return n;
  }

  // Paints one tile into its chunk (exposed for the benchmark, which times exactly this).
  uploadTile(tile: StoredTile): void {
    const s = this.tileSize;
    if (!this.scratch || this.scratch.width !== s) {
      this.scratch = new ImageData(s, s);
      this.scratch32 = new Uint32Array(this.scratch.data.buffer);
    }
    paintTile(tile.cells, s, this.palette, this.scratch32!);
    const chunk = this.chunkFor(tile.tx, tile.ty, true)!;
    const { x, y } = this.tileOffset(tile.tx, tile.ty);
    chunk.ctx.putImageData(this.scratch, x, y);
  }

  needsDraw(): boolean {
    return this.pending.size > 0 || this.drawnVersion !== this.store.version;
  }

  draw({ ctx, camera }: DrawContext): void {
    this.drawnVersion = this.store.version;
    const res = this.store.resolution;
    const chunkCells = this.tileSize * kTilesPerChunk;
    if (chunkCells === 0) return;
    const view = camera.visibleWorld();
    const vx0 = Math.floor(view.minX / res), vx1 = Math.ceil(view.maxX / res);
    const vy0 = Math.floor(view.minY / res), vy1 = Math.ceil(view.maxY / res);
    const cellPixels = camera.scale * res;
    // Below one device pixel per cell nearest-neighbour sampling drops thin walls; let the browser
    // filter instead.
    ctx.imageSmoothingEnabled = cellPixels < 1;
    ctx.imageSmoothingQuality = cellPixels < 0.4 ? 'medium' : 'low';
    for (const chunk of this.chunks.values()) {
      const x0 = chunk.cx * chunkCells, y0 = chunk.cy * chunkCells;
      const cx0 = Math.max(x0, vx0), cx1 = Math.min(x0 + chunkCells, vx1);
      const cy0 = Math.max(y0, vy0), cy1 = Math.min(y0 + chunkCells, vy1);
      if (cx0 >= cx1 || cy0 >= cy1) continue;
      const left = Math.round(camera.worldToScreenX(cx0 * res));
      const right = Math.round(camera.worldToScreenX(cx1 * res));
      const top = Math.round(camera.worldToScreenY(cy1 * res));
      const bottom = Math.round(camera.worldToScreenY(cy0 * res));
      if (right <= left || bottom <= top) continue;
      ctx.drawImage(chunk.canvas, cx0 - x0, y0 + chunkCells - cy1, cx1 - cx0, cy1 - cy0, left, top, right - left, bottom - top);
    }
    ctx.imageSmoothingEnabled = true;
  }

  // The map as an image, one pixel per cell, cropped to the tiles the store holds (exports).
  renderImage(): { canvas: OffscreenCanvas | HTMLCanvasElement; originX: number; originY: number } | null {
    const b = this.store.bounds();
    if (!b) return null;
    this.collect();
    this.upload();
    const s = this.tileSize;
    const w = (b.maxTx - b.minTx + 1) * s, h = (b.maxTy - b.minTy + 1) * s;
    const { canvas, ctx } = makeCanvas(w, h);
    const chunkCells = s * kTilesPerChunk;
    for (const chunk of this.chunks.values()) {
      const left = chunk.cx * chunkCells - b.minTx * s;
      const top = (b.maxTy + 1) * s - (chunk.cy + 1) * chunkCells;
      ctx.drawImage(chunk.canvas, left, top);
    }
    return { canvas, originX: b.minTx * s * this.store.resolution, originY: b.minTy * s * this.store.resolution };
  }

  dispose(): void {
    this.disposeChunks();
    this.pending.clear();
    this.scratch = null;
    this.scratch32 = null;
  }

  private tileOffset(tx: number, ty: number): { x: number; y: number } {
    const lx = tx - Math.floor(tx / kTilesPerChunk) * kTilesPerChunk;
    const ly = ty - Math.floor(ty / kTilesPerChunk) * kTilesPerChunk;
    // Chunk row 0 is the top, i.e. the highest tile row.
    return { x: lx * this.tileSize, y: (kTilesPerChunk - 1 - ly) * this.tileSize };
  }

  private chunkFor(tx: number, ty: number, create: boolean): Chunk | null {
    const cx = Math.floor(tx / kTilesPerChunk), cy = Math.floor(ty / kTilesPerChunk);
    const key = `${cx},${cy}`;
    let chunk = this.chunks.get(key);
    if (!chunk && create) {
      const side = this.tileSize * kTilesPerChunk;
      const { canvas, ctx } = makeCanvas(side, side);
      chunk = { cx, cy, canvas, ctx };
      this.chunks.set(key, chunk);
    }
    return chunk ?? null;
  }

  private eraseTile(tx: number, ty: number): void {
    const chunk = this.chunkFor(tx, ty, false);
    if (!chunk) return;
    const { x, y } = this.tileOffset(tx, ty);
    chunk.ctx.clearRect(x, y, this.tileSize, this.tileSize);
  }

  private disposeChunks(): void {
    for (const c of this.chunks.values()) {
      // Shrinking the backing store releases its memory now rather than at garbage collection.
      c.canvas.width = 0;
      c.canvas.height = 0;
    }
    this.chunks.clear();
  }
}
