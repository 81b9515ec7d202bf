// The predicted structure of unexplored space: each hypothesis's cells, coloured by Psi (viridis)
// or by status. Each hypothesis gets a small canvas of its bounding box, painted once per change of
// the hypothesis or of the colouring, and drawn with the map's camera.
import type { HypothesisEntry, HypothesisStore } from '../state/hypothesis_store';
import type { MapStore } from '../state/map_store';
import { makeCanvas, type DrawContext, type Layer } from './layer';
import { css, statusColor, viridis } from './palette';

export type HypothesisColoring = 'psi' | 'status';

interface Painted {
  revision: number;
  coloring: HypothesisColoring;
  canvas: OffscreenCanvas | HTMLCanvasElement;
}

export function hypothesisColor(e: HypothesisEntry['h'], coloring: HypothesisColoring): [number, number, number] {
  return coloring === 'psi' ? viridis(e.psi) : statusColor(e.status);
}

// Predictions that later scans refuted, or that were never checked, are drawn faint.
const faded = (status: string) => status === 'refuted' || status === 'expired';

export class HypothesisLayer implements Layer {
  readonly id = 'hypotheses';
  visible = true;
  coloring: HypothesisColoring = 'psi';
  private painted = new Map<number, Painted>();
  private drawn = -1;
  private drawnColoring: HypothesisColoring = 'psi';

  constructor(
    private readonly store: HypothesisStore,
    private readonly map: MapStore,
  ) {}

  needsDraw(): boolean {
    return this.drawn !== this.store.version || this.drawnColoring !== this.coloring;
  }

  draw({ ctx, camera, dpr }: DrawContext): void {
    this.drawn = this.store.version;
    this.drawnColoring = this.coloring;
    for (const id of this.painted.keys()) {
      if (!this.store.entries.has(id)) this.release(id);
    }
    const res = this.map.resolution;
    const view = camera.visibleWorld();
    ctx.save();
    ctx.imageSmoothingEnabled = false;
    for (const e of this.store.entries.values()) {
      const [r, g, b] = hypothesisColor(e.h, this.coloring);
      const alpha = faded(e.h.status) ? 0.35 : 1;
      const c = e.cells;
      if (c && c.xs.length > 0) {
        const x0 = c.minX * res, y0 = c.minY * res, x1 = (c.maxX + 1) * res, y1 = (c.maxY + 1) * res;
        if (x1 < view.minX || x0 > view.maxX || y1 < view.minY || y0 > view.maxY) continue;
        const painted = this.paint(e);
        const left = Math.round(camera.worldToScreenX(x0)), right = Math.round(camera.worldToScreenX(x1));
        const top = Math.round(camera.worldToScreenY(y1)), bottom = Math.round(camera.worldToScreenY(y0));
        ctx.globalAlpha = alpha;
        ctx.drawImage(painted.canvas, left, top, Math.max(1, right - left), Math.max(1, bottom - top));
        ctx.globalAlpha = 1;
      }
      // A marker at the predicted region's centre (the target cell), visible at any zoom.
      const tx = camera.worldToScreenX((e.h.target_cell[0] + 0.5) * res);
      const ty = camera.worldToScreenY((e.h.target_cell[1] + 0.5) * res);
      const s = 5 * dpr;
      ctx.fillStyle = css([r, g, b], alpha);
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
    const sel = this.store.selected !== null ? this.store.entries.get(this.store.selected) : undefined;
    if (sel) this.drawSelection(ctx, sel, camera, dpr, res);
    ctx.restore();
  }

  dispose(): void {
    for (const id of [...this.painted.keys()]) this.release(id);
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

  private paint(e: HypothesisEntry): Painted {
    const old = this.painted.get(e.h.id);
    if (old && old.revision === e.revision && old.coloring === this.coloring) return old;
    const c = e.cells!;
    const w = c.maxX - c.minX + 1, h = c.maxY - c.minY + 1;
    let canvas = old?.canvas;
    if (!canvas || canvas.width !== w || canvas.height !== h) {
      canvas = makeCanvas(w, h).canvas;
    }
    const ctx = canvas.getContext('2d') as OffscreenCanvasRenderingContext2D | CanvasRenderingContext2D;
    const image = ctx.createImageData(w, h);
    const px = image.data;
    const [r, g, b] = hypothesisColor(e.h, this.coloring);
    for (let i = 0; i < c.xs.length; i++) {
      const at = ((c.maxY - c.ys[i]) * w + (c.xs[i] - c.minX)) * 4;
      const p = c.occupancy[i];
      px[at] = r;
      px[at + 1] = g;
      px[at + 2] = b;
      // Predicted walls strong, predicted free space a light wash.
      px[at + 3] = p >= 0.5 ? 235 : 70;
    }
    ctx.putImageData(image, 0, 0);
    const painted = { revision: e.revision, coloring: this.coloring, canvas };
    this.painted.set(e.h.id, painted);
    return painted;
  }

  private release(id: number): void {
    const p = this.painted.get(id);
    if (p) {
      p.canvas.width = 0;
      p.canvas.height = 0;
    }
    this.painted.delete(id);
  }
}
