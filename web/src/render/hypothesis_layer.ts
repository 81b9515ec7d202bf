// The predicted structure of unexplored space, drawn as what it is: predicted walls as solid cells
// in the hypothesis's colour (by Psi in steps, or by status), predicted free space as a light wash
// of that colour. All hypotheses are painted into one image, cell by cell, so where predictions
// overlap the wash does not stack up into darker rectangles and a wall is never hidden by a wash.
// The cells are drawn under the map (part 'cells'): the map's known cells are opaque and its unknown
// ones transparent, so a prediction shows only where the map has not mapped yet; once seen, the
// map shows what is there (the status says whether the prediction was right). The marks (part
// 'marks', over the map): a diamond at each prediction's target (the frontier it was made for),
// visible at any zoom, and the selection.
import type { HypothesisEntry, HypothesisStore } from '../state/hypothesis_store';
import type { MapStore } from '../state/map_store';
import { makeCanvas, type DrawContext, type Layer } from './layer';
import { css, psiColor, statusColor } from './palette';

export type HypothesisColoring = 'psi' | 'status';

export function hypothesisColor(e: HypothesisEntry['h'], coloring: HypothesisColoring): [number, number, number] {
  return coloring === 'psi' ? psiColor(e.psi) : statusColor(e.status);
}

// Predictions that later scans refuted, or that were never checked, are drawn faint.
export const isFaded = (status: string) => status === 'refuted' || status === 'expired';

// Alpha (0..255) of a predicted cell: walls strong, free space a light wash; faded ones fainter.
export function cellAlpha(wall: boolean, faded: boolean): number {
  if (wall) return faded ? 110 : 255;
  return faded ? 24 : 56;
}

// The composite image is at most this many pixels; a larger union of predictions is painted at a
// coarser step (several cells per pixel), so memory stays bounded.
const kMaxPixels = 4096 * 4096;

export interface CellBox {
  minX: number;
  minY: number;
  maxX: number;
  maxY: number;
}

// The union of the predicted cells' bounding boxes (cell indices, inclusive), or null.
export function predictedCellBox(store: HypothesisStore): CellBox | null {
  let box: CellBox | null = null;
  for (const e of store.entries.values()) {
    const c = e.cells;
    if (!c || c.xs.length === 0) continue;
    if (!box) box = { minX: c.minX, minY: c.minY, maxX: c.maxX, maxY: c.maxY };
    else {
      box.minX = Math.min(box.minX, c.minX);
      box.minY = Math.min(box.minY, c.minY);
      box.maxX = Math.max(box.maxX, c.maxX);
      box.maxY = Math.max(box.maxY, c.maxY);
    }
  }
  return box;
}

interface Composite {
  box: CellBox;
  step: number; // cells per pixel
  canvas: OffscreenCanvas | HTMLCanvasElement;
}

export class HypothesisLayer implements Layer {
  // Both parts answer to the one layer toggle.
  readonly id = 'hypotheses';
  visible = true;
  coloring: HypothesisColoring = 'psi';
  private composite: Composite | null = null;
  private paintedVersion = -1;
  private paintedColoring: HypothesisColoring = 'psi';
  private drawn = -1;
  private drawnColoring: HypothesisColoring = 'psi';

  constructor(
    private readonly store: HypothesisStore,
    private readonly map: MapStore,
    readonly part: 'cells' | 'marks',
  ) {}

  needsDraw(): boolean {
    return this.drawn !== this.store.version || this.drawnColoring !== this.coloring;
  }

  draw({ ctx, camera, dpr }: DrawContext): void {
    this.drawn = this.store.version;
    this.drawnColoring = this.coloring;
    const res = this.map.resolution;
    ctx.save();
    ctx.imageSmoothingEnabled = false;
    const comp = this.part === 'cells' ? this.paint() : null;
    if (comp) {
      const { box, step } = comp;
      const left = Math.round(camera.worldToScreenX(box.minX * res)), right = Math.round(camera.worldToScreenX((box.minX + comp.canvas.width * step) * res));
      const top = Math.round(camera.worldToScreenY((box.maxY + 1) * res)), bottom = Math.round(camera.worldToScreenY((box.maxY + 1 - comp.canvas.height * step) * res));
      ctx.drawImage(comp.canvas, left, top, Math.max(1, right - left), Math.max(1, bottom - top));
    }
    if (this.part === 'marks') {
      for (const e of this.store.entries.values()) this.drawMarker(ctx, e, camera, dpr, res);
      const sel = this.store.selected !== null ? this.store.entries.get(this.store.selected) : undefined;
      if (sel) this.drawSelection(ctx, sel, camera, dpr, res);
    }
    ctx.restore();
  }

  dispose(): void {
    if (this.composite) {
      this.composite.canvas.width = 0;
      this.composite.canvas.height = 0;
    }
    this.composite = null;
  }

  // A diamond at the predicted region's target cell, in the hypothesis's colour.
  private drawMarker(ctx: CanvasRenderingContext2D, e: HypothesisEntry, camera: DrawContext['camera'], dpr: number, res: number): void {
    const tx = camera.worldToScreenX((e.h.target_cell[0] + 0.5) * res);
    const ty = camera.worldToScreenY((e.h.target_cell[1] + 0.5) * res);
    const s = 5 * dpr;
    ctx.fillStyle = css(hypothesisColor(e.h, this.coloring), isFaded(e.h.status) ? 0.35 : 1);
    ctx.strokeStyle = 'rgba(0,0,0,0.7)';
    ctx.lineWidth = dpr;
    ctx.beginPath();
    ctx.moveTo(tx, ty - s);
    ctx.lineTo(tx + s, ty);
    ctx.lineTo(tx, ty + s);
    ctx.lineTo(tx - s, ty);
    ctx.closePath();
    ctx.fill();
    ctx.stroke();
  }

  private drawSelection(ctx: CanvasRenderingContext2D, e: HypothesisEntry, camera: DrawContext['camera'], dpr: number, res: number): void {
    const c = e.cells;
    const box = c
      ? { x0: c.minX * res, y0: c.minY * res, x1: (c.maxX + 1) * res, y1: (c.maxY + 1) * res }
      : { x0: (e.h.target_cell[0] - 10) * res, y0: (e.h.target_cell[1] - 10) * res, x1: (e.h.target_cell[0] + 11) * res, y1: (e.h.target_cell[1] + 11) * res };
    const pad = 6 * dpr;
    const left = camera.worldToScreenX(box.x0) - pad, right = camera.worldToScreenX(box.x1) + pad;
    const top = camera.worldToScreenY(box.y1) - pad, bottom = camera.worldToScreenY(box.y0) + pad;
    ctx.strokeStyle = 'rgba(0,0,0,0.8)';
    ctx.lineWidth = 5 * dpr;
    ctx.strokeRect(left, top, right - left, bottom - top);
    ctx.strokeStyle = 'rgb(255,255,255)';
    ctx.lineWidth = 2 * dpr;
    ctx.setLineDash([6 * dpr, 4 * dpr]);
    ctx.strokeRect(left, top, right - left, bottom - top);
    ctx.setLineDash([]);
    ctx.font = `${12 * dpr}px system-ui, sans-serif`;
    ctx.fillStyle = 'white';
    ctx.strokeStyle = 'black';
    ctx.lineWidth = 3 * dpr;
    const label = `H${e.h.id}  Ψ ${e.h.psi.toFixed(2)}  ${e.h.status}`;
    ctx.strokeText(label, left, top - 6 * dpr);
    ctx.fillText(label, left, top - 6 * dpr);
  }

  // Repaints the composite when a hypothesis or the colouring changed. Order: washes first (the
  // first wash on a pixel stays), then walls over them, faded before current ones, so a current
  // prediction's wall is what shows where predictions disagree.
  private paint(): Composite | null {
    if (this.paintedVersion === this.store.version && this.paintedColoring === this.coloring) return this.composite;
    this.paintedVersion = this.store.version;
    this.paintedColoring = this.coloring;
    const box = predictedCellBox(this.store);
    if (!box) {
      this.dispose();
      return null;
    }
    const cellsW = box.maxX - box.minX + 1, cellsH = box.maxY - box.minY + 1;
    const step = Math.max(1, Math.ceil(Math.sqrt((cellsW * cellsH) / kMaxPixels)));
    const w = Math.ceil(cellsW / step), h = Math.ceil(cellsH / step);
    let canvas = this.composite?.canvas;
    if (!canvas || canvas.width !== w || canvas.height !== h) canvas = makeCanvas(w, h).canvas;
    const ctx = canvas.getContext('2d') as OffscreenCanvasRenderingContext2D | CanvasRenderingContext2D;
    const image = ctx.createImageData(w, h);
    const px = image.data;
    const entries = [...this.store.entries.values()].filter((e) => e.cells && e.cells.xs.length > 0);
    entries.sort((a, b) => Number(isFaded(b.h.status)) - Number(isFaded(a.h.status)) || a.h.psi - b.h.psi);
    const paintCells = (walls: boolean) => {
      for (const e of entries) {
        const c = e.cells!;
        const [r, g, b] = hypothesisColor(e.h, this.coloring);
        const alpha = cellAlpha(walls, isFaded(e.h.status));
        for (let i = 0; i < c.xs.length; i++) {
          if (c.occupancy[i] >= 0.5 !== walls) continue;
          const at = (Math.floor((box.maxY - c.ys[i]) / step) * w + Math.floor((c.xs[i] - box.minX) / step)) * 4;
          if (!walls && px[at + 3] !== 0) continue;
          if (walls && px[at + 3] > alpha) continue;
          px[at] = r;
          px[at + 1] = g;
          px[at + 2] = b;
          px[at + 3] = alpha;
        }
      }
    };
    paintCells(false);
    paintCells(true);
    ctx.putImageData(image, 0, 0);
    this.composite = { box, step, canvas };
    return this.composite;
  }
}
