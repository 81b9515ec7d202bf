// The 2D camera of a map view: the world point at the centre of the view and the zoom in pixels
// per metre. World x points right and y up; screen y points down (the flip lives here only).

export interface WorldBox {
  minX: number;
  minY: number;
  maxX: number;
  maxY: number;
}

export const kMinScale = 0.5; // pixels per metre: a 2 km wide view on a laptop screen
export const kMaxScale = 2000; // 1 mm per pixel

export class Camera {
  centerX = 0;
  centerY = 0;
  scale = 40; // pixels per metre
  width = 1;
  height = 1;

  setViewport(width: number, height: number): void {
    this.width = Math.max(1, width);
    this.height = Math.max(1, height);
  }

  worldToScreenX(x: number): number {
    return (x - this.centerX) * this.scale + this.width / 2;
  }

  worldToScreenY(y: number): number {
    return this.height / 2 - (y - this.centerY) * this.scale;
  }

  screenToWorld(sx: number, sy: number): [number, number] {
    return [(sx - this.width / 2) / this.scale + this.centerX, (this.height / 2 - sy) / this.scale + this.centerY];
  }

  // Moves the view by a drag of (dx, dy) screen pixels.
  panBy(dx: number, dy: number): void {
    this.centerX -= dx / this.scale;
    this.centerY += dy / this.scale;
  }

  // Zooms by 'factor' keeping the world point under screen (sx, sy) fixed.
  zoomAt(factor: number, sx: number, sy: number): void {
    const [wx, wy] = this.screenToWorld(sx, sy);
    this.scale = clamp(this.scale * factor, kMinScale, kMaxScale);
    this.centerX = wx - (sx - this.width / 2) / this.scale;
    this.centerY = wy - (this.height / 2 - sy) / this.scale;
  }

  // Shows 'box' whole with 'marginPixels' around it.
  fit(box: WorldBox, marginPixels = 24): void {
    const w = Math.max(box.maxX - box.minX, 1e-3), h = Math.max(box.maxY - box.minY, 1e-3);
    const sx = (this.width - 2 * marginPixels) / w, sy = (this.height - 2 * marginPixels) / h;
    this.scale = clamp(Math.min(sx, sy), kMinScale, kMaxScale);
    this.centerX = (box.minX + box.maxX) / 2;
    this.centerY = (box.minY + box.maxY) / 2;
  }

  // The world box the view shows.
  visibleWorld(): WorldBox {
    const [x0, y1] = this.screenToWorld(0, 0);
    const [x1, y0] = this.screenToWorld(this.width, this.height);
    return { minX: x0, minY: y0, maxX: x1, maxY: y1 };
  }

  copyFrom(other: Camera): void {
    this.centerX = other.centerX;
    this.centerY = other.centerY;
    this.scale = other.scale;
  }
}

export function clamp(v: number, lo: number, hi: number): number {
  return Math.min(hi, Math.max(lo, v));
}

// A scale bar length in metres: 1, 2 or 5 times a power of ten, at most 'maxPixels' long.
export function niceScaleBar(scale: number, maxPixels = 120): { meters: number; pixels: number; label: string } {
  const target = maxPixels / scale;
  const power = Math.pow(10, Math.floor(Math.log10(target)));
  let meters = power;
  for (const m of [5, 2, 1]) {
    if (m * power <= target) {
      meters = m * power;
      break;
    }
  }
  const label = meters >= 1000 ? `${meters / 1000} km` : meters >= 1 ? `${meters} m` : meters >= 0.01 ? `${Math.round(meters * 100)} cm` : `${Math.round(meters * 1000)} mm`;
  return { meters, pixels: meters * scale, label };
}
