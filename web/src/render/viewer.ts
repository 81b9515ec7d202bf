// A map view: one <canvas>, a camera, and layers drawn in order. Renders on requestAnimationFrame
// only when something is dirty (camera moved, a store changed, a layer toggled). Pan by dragging,
// zoom with the wheel or a pinch around the pointer, double-click to fit. The scale bar and the
// world coordinates under the cursor are DOM overlays.
import { Camera, niceScaleBar, type WorldBox } from './camera';
import type { DrawContext, Layer } from './layer';
import type { MapLayer } from './map_layer';
import type { PointerTool } from './pose_tool';

export interface FrameStats {
  frames: number;
  drawMeanMs: number;
  drawP95Ms: number;
  drawMaxMs: number;
  uploadMaxMs: number;
  tilesUploaded: number;
}

// Lighter than the walls, darker than free space: unknown cells are transparent over it.
export const kBackground = '#2a2e37';
const kUploadBudgetMs = 6; // per frame; the rest of a large snapshot goes out on later frames
const kFrameSamples = 240;

export class Viewer {
  readonly camera = new Camera();
  readonly canvas: HTMLCanvasElement;
  private readonly ctx: CanvasRenderingContext2D;
  private readonly layers: Layer[] = [];
  private mapLayer: MapLayer | null = null;
  private frameRequested = false;
  private cameraDirty = true;
  private forceDraw = true;
  private disposed = false;
  private dpr = 1;
  private readonly scaleBar: HTMLElement;
  private readonly scaleLabel: HTMLElement;
  private readonly cursorLabel: HTMLElement;
  private cursor: [number, number] | null = null;
  private readonly pointers = new Map<number, { x: number; y: number }>();
  private readonly resizeObserver: ResizeObserver;
  private drawTimes: number[] = [];
  private uploadMax = 0;
  private tilesUploaded = 0;
  private frames = 0;
  // Called after each drawn frame (for linked views and the status line).
  onCameraChange: ((camera: Camera) => void) | null = null;
  // Called when the user moves the camera (drag, wheel, pinch, keys), not when code does.
  onUserCamera: (() => void) | null = null;
  // Called after each frame with its draw time.
  onFrame: ((drawMs: number) => void) | null = null;
  // Follow the robot: called per frame to get the point to centre on (null: free camera).
  follow: (() => { x: number; y: number } | null) | null = null;
  // The world box to fit on double-click and on the first data.
  fitBox: (() => WorldBox | null) | null = null;
  // Describes the map cell under the cursor (occupancy), for the coordinate readout.
  describeCell: ((x: number, y: number) => string) | null = null;
  // Called with world coordinates on a click that was not a drag.
  onClick: ((x: number, y: number) => void) | null = null;
  // While set, a single pointer's press, drag and release go to the tool instead of panning.
  pointerTool: PointerTool | null = null;

  constructor(readonly container: HTMLElement) {
    this.canvas = document.createElement('canvas');
    this.canvas.className = 'map-canvas';
    this.canvas.tabIndex = 0;
    this.canvas.setAttribute('aria-label', 'map view');
    this.ctx = this.canvas.getContext('2d', { alpha: false })!;
    container.appendChild(this.canvas);
    this.scaleBar = document.createElement('div');
    this.scaleBar.className = 'scale-bar';
    this.scaleLabel = document.createElement('span');
    this.scaleBar.appendChild(this.scaleLabel);
    container.appendChild(this.scaleBar);
    this.cursorLabel = document.createElement('div');
    this.cursorLabel.className = 'cursor-readout';
    container.appendChild(this.cursorLabel);
    this.resizeObserver = new ResizeObserver(() => this.resize());
    this.resizeObserver.observe(container);
    this.bindInput();
    this.resize();
  }

  addLayer(layer: Layer): void {
    this.layers.push(layer);
    if (layer.id === 'map') this.mapLayer = layer as MapLayer;
    this.invalidate();
  }

  layer<T extends Layer>(id: string): T | undefined {
    return this.layers.find((l) => l.id === id) as T | undefined;
  }

  // Shows or hides every layer with this id (a layer may be drawn in parts, e.g. under and over
  // the map).
  setLayerVisible(id: string, visible: boolean): void {
    for (const l of this.layers) {
      if (l.id !== id || l.visible === visible) continue;
      l.visible = visible;
      this.invalidate();
    }
  }

  // Schedules a frame if anything needs drawing; cheap to call often (e.g. per message).
  requestRender(): void {
    if (this.frameRequested || this.disposed) return;
    this.frameRequested = true;
    requestAnimationFrame((t) => this.frame(t));
  }

  // Forces a full redraw on the next frame.
  invalidate(): void {
    this.forceDraw = true;
    this.requestRender();
  }

  fit(): void {
    const box = this.fitBox?.();
    if (!box) return;
    this.camera.fit(box, 24 * this.dpr);
    this.cameraChanged();
  }

  zoomBy(factor: number): void {
    this.camera.zoomAt(factor, this.camera.width / 2, this.camera.height / 2);
    this.cameraChanged();
  }

  setCamera(other: Camera): void {
    // Linked views share the centre and the zoom. Equal cameras are a no-op, which ends the echo
    // between two linked views.
    const c = this.camera;
    if (c.centerX === other.centerX && c.centerY === other.centerY && c.scale === other.scale) return;
    this.camera.centerX = other.centerX;
    this.camera.centerY = other.centerY;
    this.camera.scale = other.scale;
    this.cameraDirty = true;
    this.requestRender();
  }

  frameStats(): FrameStats {
    const sorted = [...this.drawTimes].sort((a, b) => a - b);
    const mean = sorted.length ? sorted.reduce((a, b) => a + b, 0) / sorted.length : 0;
    return {
      frames: this.frames,
      drawMeanMs: mean,
      drawP95Ms: sorted.length ? sorted[Math.min(sorted.length - 1, Math.floor(sorted.length * 0.95))] : 0,
      drawMaxMs: sorted.length ? sorted[sorted.length - 1] : 0,
      uploadMaxMs: this.uploadMax,
      tilesUploaded: this.tilesUploaded,
    };
  }

  resetFrameStats(): void {
    this.drawTimes = [];
    this.uploadMax = 0;
    this.frames = 0;
  }

  dispose(): void {
    this.disposed = true;
    this.resizeObserver.disconnect();
    for (const l of this.layers) l.dispose();
    this.layers.length = 0;
    this.container.replaceChildren();
  }

  // Draws one frame now (the benchmark calls this directly).
  drawNow(now = performance.now()): number {
    const start = performance.now();
    if (this.mapLayer) {
      this.mapLayer.collect();
      const n = this.mapLayer.upload(kUploadBudgetMs);
      if (n > 0) {
        this.uploadMax = Math.max(this.uploadMax, performance.now() - start);
        this.tilesUploaded += n;
      }
    }
    const follow = this.follow?.();
    if (follow) {
      this.camera.centerX = follow.x;
      this.camera.centerY = follow.y;
    }
    const ctx = this.ctx;
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.fillStyle = kBackground;
    ctx.fillRect(0, 0, this.canvas.width, this.canvas.height);
    this.drawGrid();
    const d: DrawContext = { ctx, camera: this.camera, dpr: this.dpr, now };
    for (const l of this.layers) {
      if (l.visible) l.draw(d);
    }
    this.updateOverlays();
    const ms = performance.now() - start;
    this.drawTimes.push(ms);
    if (this.drawTimes.length > kFrameSamples) this.drawTimes.shift();
    this.frames++;
    return ms;
  }

  private frame(now: number): void {
    this.frameRequested = false;
    if (this.disposed) return;
    const dirty = this.forceDraw || this.cameraDirty || this.layers.some((l) => l.visible && l.needsDraw());
    if (!dirty && !(this.mapLayer && this.mapLayer.pendingTiles > 0)) return;
    this.forceDraw = false;
    const cameraMoved = this.cameraDirty;
    this.cameraDirty = false;
    const ms = this.drawNow(now);
    if (this.mapLayer && this.mapLayer.pendingTiles > 0) this.requestRender();
    if (cameraMoved) this.onCameraChange?.(this.camera);
    this.onFrame?.(ms);
  }

  private cameraChanged(): void {
    this.cameraDirty = true;
    this.requestRender();
  }

  // A faint metric grid: 1, 5, 10 ... m spacing chosen to be about 60-150 CSS pixels apart.
  private drawGrid(): void {
    const { ctx, camera } = this;
    const { meters } = niceScaleBar(camera.scale, 120 * this.dpr);
    const v = camera.visibleWorld();
    ctx.strokeStyle = 'rgba(255,255,255,0.05)';
    ctx.lineWidth = 1;
    ctx.beginPath();
    for (let x = Math.ceil(v.minX / meters) * meters; x <= v.maxX; x += meters) {
      const sx = Math.round(camera.worldToScreenX(x)) + 0.5;
      ctx.moveTo(sx, 0);
      ctx.lineTo(sx, camera.height);
    }
    for (let y = Math.ceil(v.minY / meters) * meters; y <= v.maxY; y += meters) {
      const sy = Math.round(camera.worldToScreenY(y)) + 0.5;
      ctx.moveTo(0, sy);
      ctx.lineTo(camera.width, sy);
    }
    ctx.stroke();
    // The world origin's axes: x red, y green, 1 m long.
    const ox = camera.worldToScreenX(0), oy = camera.worldToScreenY(0);
    const len = Math.max(20 * this.dpr, camera.scale);
    ctx.lineWidth = 2 * this.dpr;
    ctx.strokeStyle = 'rgba(255,80,80,0.6)';
    ctx.beginPath();
    ctx.moveTo(ox, oy);
    ctx.lineTo(ox + len, oy);
    ctx.stroke();
    ctx.strokeStyle = 'rgba(80,220,80,0.6)';
    ctx.beginPath();
    ctx.moveTo(ox, oy);
    ctx.lineTo(ox, oy - len);
    ctx.stroke();
  }

  private updateOverlays(): void {
    const bar = niceScaleBar(this.camera.scale / this.dpr, 120);
    this.scaleBar.style.width = `${bar.pixels}px`;
    this.scaleLabel.textContent = bar.label;
    this.updateCursor();
  }

  private updateCursor(): void {
    if (!this.cursor) {
      this.cursorLabel.textContent = '';
      return;
    }
    const [x, y] = this.camera.screenToWorld(this.cursor[0] * this.dpr, this.cursor[1] * this.dpr);
    const cell = this.describeCell ? this.describeCell(x, y) : '';
    this.cursorLabel.textContent = `x ${x.toFixed(2)} m  y ${y.toFixed(2)} m${cell ? '  ' + cell : ''}`;
  }

  private resize(): void {
    const rect = this.container.getBoundingClientRect();
    const dpr = window.devicePixelRatio || 1;
    // The camera works in device pixels: keep the zoom per CSS pixel when the ratio changes
    // (a window moved to another screen). The centre stays where it is.
    if (dpr !== this.dpr) this.camera.scale *= dpr / this.dpr;
    this.dpr = dpr;
    const w = Math.max(1, Math.round(rect.width * dpr)), h = Math.max(1, Math.round(rect.height * dpr));
    if (this.canvas.width !== w || this.canvas.height !== h) {
      this.canvas.width = w;
      this.canvas.height = h;
      this.canvas.style.width = `${rect.width}px`;
      this.canvas.style.height = `${rect.height}px`;
      this.camera.setViewport(w, h);
      this.invalidate();
    }
  }

  private bindInput(): void {
    const c = this.canvas;
    let dragDistance = 0;
    let pinchDistance = 0;
    const local = (e: PointerEvent | WheelEvent | MouseEvent): [number, number] => {
      const r = c.getBoundingClientRect();
      return [e.clientX - r.left, e.clientY - r.top];
    };
    c.addEventListener(
      'wheel',
      (e) => {
        e.preventDefault();
        const [x, y] = local(e);
        // deltaMode 1 is lines (Firefox); about 40 pixels each.
        const delta = e.deltaMode === 1 ? e.deltaY * 40 : e.deltaY;
        this.camera.zoomAt(Math.exp(-delta * 0.0015), x * this.dpr, y * this.dpr);
        this.cameraChanged();
        this.onUserCamera?.();
      },
      { passive: false },
    );
    const world = (e: PointerEvent): [number, number] => {
      const [x, y] = local(e);
      return this.camera.screenToWorld(x * this.dpr, y * this.dpr);
    };
    let toolPointer: number | null = null;
    c.addEventListener('pointerdown', (e) => {
      c.setPointerCapture(e.pointerId);
      if (this.pointerTool && this.pointers.size === 0 && toolPointer === null && e.button === 0) {
        toolPointer = e.pointerId;
        this.pointerTool.down(...world(e));
        this.requestRender();
        return;
      }
      const [x, y] = local(e);
      this.pointers.set(e.pointerId, { x, y });
      dragDistance = 0;
      if (this.pointers.size === 2) pinchDistance = this.pinchSpan();
    });
    c.addEventListener('pointermove', (e) => {
      const [x, y] = local(e);
      this.cursor = [x, y];
      if (e.pointerId === toolPointer) {
        this.pointerTool?.move(...world(e));
        this.updateCursor();
        this.requestRender();
        return;
      }
      const p = this.pointers.get(e.pointerId);
      if (!p) {
        this.updateCursor();
        return;
      }
      if (this.pointers.size === 1) {
        const dx = x - p.x, dy = y - p.y;
        dragDistance += Math.abs(dx) + Math.abs(dy);
        this.camera.panBy(dx * this.dpr, dy * this.dpr);
        this.cameraChanged();
        if (dx !== 0 || dy !== 0) this.onUserCamera?.();
      }
      p.x = x;
      p.y = y;
      if (this.pointers.size === 2) {
        const span = this.pinchSpan();
        const [cx, cy] = this.pinchCentre();
        if (pinchDistance > 0) this.camera.zoomAt(span / pinchDistance, cx * this.dpr, cy * this.dpr);
        pinchDistance = span;
        dragDistance += 10;
        this.cameraChanged();
        this.onUserCamera?.();
      }
      this.updateCursor();
    });
    const end = (e: PointerEvent) => {
      if (e.pointerId === toolPointer) {
        toolPointer = null;
        if (e.type === 'pointerup') this.pointerTool?.up(...world(e));
        else this.pointerTool?.cancel();
        this.requestRender();
        return;
      }
      const wasSingle = this.pointers.size === 1;
      this.pointers.delete(e.pointerId);
      if (e.type === 'pointerup' && wasSingle && dragDistance < 4 && this.onClick) {
        const [x, y] = local(e);
        const [wx, wy] = this.camera.screenToWorld(x * this.dpr, y * this.dpr);
        this.onClick(wx, wy);
      }
    };
    c.addEventListener('pointerup', end);
    c.addEventListener('pointercancel', end);
    c.addEventListener('pointerleave', () => {
      this.cursor = null;
      this.updateCursor();
    });
    c.addEventListener('dblclick', () => this.fit());
    c.addEventListener('keydown', (e) => {
      const step = 60 * this.dpr;
      const keys: Record<string, () => void> = {
        '+': () => this.zoomBy(1.25),
        '=': () => this.zoomBy(1.25),
        '-': () => this.zoomBy(0.8),
        f: () => this.fit(),
        ArrowLeft: () => this.camera.panBy(step, 0),
        ArrowRight: () => this.camera.panBy(-step, 0),
        ArrowUp: () => this.camera.panBy(0, step),
        ArrowDown: () => this.camera.panBy(0, -step),
      };
      const action = keys[e.key];
      if (!action) return;
      e.preventDefault();
      action();
      this.cameraChanged();
      if (e.key !== 'f') this.onUserCamera?.();
    });
  }

  private pinchSpan(): number {
    const [a, b] = [...this.pointers.values()];
    return Math.hypot(a.x - b.x, a.y - b.y);
  }

  private pinchCentre(): [number, number] {
    const [a, b] = [...this.pointers.values()];
    return [(a.x + b.x) / 2, (a.y + b.y) / 2];
  }
}
