// The robot: pose estimate and footprint (a Pioneer 3-DX body, 455 x 381 mm), drawn at least a
// few pixels large so it stays visible when zoomed out.
import type { DrawContext } from './layer';
import { RobotStoreLayer } from './robot_store_layer';

export const kFootprintLengthMeters = 0.455;
export const kFootprintWidthMeters = 0.381;

export class RobotLayer extends RobotStoreLayer {
  readonly id = 'robot';

  protected paint({ ctx, camera, dpr }: DrawContext): void {
    const p = this.store.pose;
    if (!p) return;
    const x = camera.worldToScreenX(p.x), y = camera.worldToScreenY(p.y);
    const minPixels = 14 * dpr;
    const k = Math.max(camera.scale, minPixels / kFootprintLengthMeters);
    const l = kFootprintLengthMeters * k, w = kFootprintWidthMeters * k;
    ctx.save();
    ctx.translate(x, y);
    ctx.rotate(-p.theta); // screen y is flipped
    ctx.fillStyle = 'rgba(255, 92, 64, 0.35)';
    ctx.strokeStyle = 'rgb(255, 92, 64)';
    ctx.lineWidth = 2 * dpr;
    ctx.beginPath();
    ctx.roundRect(-l / 2, -w / 2, l, w, Math.min(l, w) * 0.2);
    ctx.fill();
    ctx.stroke();
    // Heading.
    ctx.beginPath();
    ctx.moveTo(0, 0);
    ctx.lineTo(l * 0.75, 0);
    ctx.lineTo(l * 0.55, -w * 0.2);
    ctx.moveTo(l * 0.75, 0);
    ctx.lineTo(l * 0.55, w * 0.2);
    ctx.stroke();
    ctx.restore();
  }
}

// The path the robot took (the trajectory estimate), decimated on screen: points closer than about
// a pixel to the last drawn one are skipped, so a long run costs little per frame.
export class TrajectoryLayer extends RobotStoreLayer {
  readonly id = 'trajectory';

  protected paint({ ctx, camera, dpr }: DrawContext): void {
    const poses = this.store.trajectory.packed();
    const n = poses.length / 4;
    if (n < 2) return;
    ctx.save();
    ctx.strokeStyle = 'rgba(255, 196, 0, 0.9)';
    ctx.lineWidth = 2 * dpr;
    ctx.lineJoin = 'round';
    ctx.beginPath();
    let lx = camera.worldToScreenX(poses[0]), ly = camera.worldToScreenY(poses[1]);
    ctx.moveTo(lx, ly);
    const minStep = 1.5 * dpr;
    for (let i = 1; i < n; i++) {
      const x = camera.worldToScreenX(poses[i * 4]), y = camera.worldToScreenY(poses[i * 4 + 1]);
      if (i < n - 1 && Math.abs(x - lx) < minStep && Math.abs(y - ly) < minStep) continue;
      ctx.lineTo(x, y);
      lx = x;
      ly = y;
    }
    ctx.stroke();
    ctx.restore();
  }
}
