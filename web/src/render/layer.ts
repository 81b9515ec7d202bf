// What every map-view layer implements. Layers own their drawing resources, create them once,
// update them from the stores, and free them in dispose().
import type { Camera } from './camera';

export interface DrawContext {
  ctx: CanvasRenderingContext2D;
  camera: Camera; // in device pixels
  dpr: number; // device pixels per CSS pixel, for line widths and marker sizes
  now: number; // performance.now() of the frame
}

export interface Layer {
  readonly id: string;
  visible: boolean;
  // True when the layer has something new to show since the last draw.
  needsDraw(): boolean;
  draw(d: DrawContext): void;
  dispose(): void;
}

// Makes a 2D canvas off the document when the browser can, else a detached <canvas>.
export function makeCanvas(width: number, height: number): {
  canvas: OffscreenCanvas | HTMLCanvasElement;
  ctx: OffscreenCanvasRenderingContext2D | CanvasRenderingContext2D;
} {
  if (typeof OffscreenCanvas !== 'undefined') {
    const canvas = new OffscreenCanvas(width, height);
    const ctx = canvas.getContext('2d', { alpha: true });
    if (ctx) return { canvas, ctx };
  }
  const canvas = document.createElement('canvas');
  canvas.width = width;
  canvas.height = height;
  return { canvas, ctx: canvas.getContext('2d', { alpha: true })! };
}
