// The operator's set-pose tool: press on the map for the robot's position, drag towards its
// heading, release. While armed it takes the map's pointer input instead of panning (see
// Viewer.pointerTool) and draws the arrow being dragged.
import type { DrawContext, Layer } from './layer';

export interface WorldPose {
  x: number;
  y: number;
  theta: number;
}

// A drag shorter than this (in metres) keeps the heading 0: a click sets the position only.
const kMinHeadingDrag = 1e-6;

// The pose a drag from (x0, y0) to (x1, y1) in world coordinates stands for.
export function poseFromDrag(x0: number, y0: number, x1: number, y1: number): WorldPose {
  const dx = x1 - x0, dy = y1 - y0;
  return { x: x0, y: y0, theta: Math.hypot(dx, dy) < kMinHeadingDrag ? 0 : Math.atan2(dy, dx) };
}

// What Viewer calls while a pointer tool is armed, in world coordinates.
export interface PointerTool {
  down(x: number, y: number): void;
  move(x: number, y: number): void;
  up(x: number, y: number): void;
  cancel(): void;
}

export class PoseTool implements Layer, PointerTool {
  readonly id = 'pose-tool';
  visible = true;
  private start: [number, number] | null = null;
  private end: [number, number] = [0, 0];
  private dirty = false;

  // Called with the pose on release.
  constructor(private readonly onPose: (pose: WorldPose) => void) {}

  get dragging(): boolean {
    return this.start !== null;
  }

  down(x: number, y: number): void {
    this.start = [x, y];
    this.end = [x, y];
    this.dirty = true;
  }

  move(x: number, y: number): void {
    if (!this.start) return;
    this.end = [x, y];
    this.dirty = true;
  }

  up(x: number, y: number): void {
    if (!this.start) return;
    const [x0, y0] = this.start;
    this.start = null;
    this.dirty = true;
    this.onPose(poseFromDrag(x0, y0, x, y));
  }

  cancel(): void {
    this.start = null;
    this.dirty = true;
  }

  needsDraw(): boolean {
    return this.dirty;
  }

  draw({ ctx, camera, dpr }: DrawContext): void {
    this.dirty = false;
    if (!this.start) return;
    const sx = camera.worldToScreenX(this.start[0]), sy = camera.worldToScreenY(this.start[1]);
    const ex = camera.worldToScreenX(this.end[0]), ey = camera.worldToScreenY(this.end[1]);
    const angle = Math.atan2(ey - sy, ex - sx);
    const head = 12 * dpr;
    ctx.save();
    ctx.strokeStyle = 'rgb(64, 220, 255)';
    ctx.fillStyle = 'rgba(64, 220, 255, 0.3)';
    ctx.lineWidth = 3 * dpr;
    ctx.beginPath();
    ctx.arc(sx, sy, 8 * dpr, 0, 2 * Math.PI);
    ctx.fill();
    ctx.stroke();
    ctx.beginPath();
    ctx.moveTo(sx, sy);
    ctx.lineTo(ex, ey);
    ctx.moveTo(ex, ey);
    ctx.lineTo(ex - head * Math.cos(angle - 0.45), ey - head * Math.sin(angle - 0.45));
    ctx.moveTo(ex, ey);
    ctx.lineTo(ex - head * Math.cos(angle + 0.45), ey - head * Math.sin(angle + 0.45));
    ctx.stroke();
    ctx.restore();
  }

  dispose(): void {}
}
