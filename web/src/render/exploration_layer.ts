// Exploration: frontier points, the current target and the planned path to it.
import type { DrawContext } from './layer';
import { RobotStoreLayer } from './robot_store_layer';

export class ExplorationLayer extends RobotStoreLayer {
  readonly id = 'exploration';

  protected paint({ ctx, camera, dpr }: DrawContext): void {
    ctx.save();
    ctx.fillStyle = 'rgba(0, 220, 255, 0.85)';
    const r = Math.max(2 * dpr, 0.04 * camera.scale);
    ctx.beginPath();
    for (const [fx, fy] of this.store.frontiers) {
      const x = camera.worldToScreenX(fx), y = camera.worldToScreenY(fy);
      ctx.moveTo(x + r, y);
      ctx.arc(x, y, r, 0, 2 * Math.PI);
    }
    ctx.fill();
    const t = this.store.target;
    if (t) {
      if (t.path.length > 1) {
        ctx.strokeStyle = 'rgba(236, 72, 255, 0.95)';
        ctx.lineWidth = 2 * dpr;
        ctx.setLineDash([6 * dpr, 4 * dpr]);
        ctx.beginPath();
        t.path.forEach(([px, py], i) => {
          const x = camera.worldToScreenX(px), y = camera.worldToScreenY(py);
          if (i === 0) ctx.moveTo(x, y);
          else ctx.lineTo(x, y);
        });
        ctx.stroke();
        ctx.setLineDash([]);
      }
      const x = camera.worldToScreenX(t.x), y = camera.worldToScreenY(t.y);
      const s = 9 * dpr;
      ctx.strokeStyle = 'rgb(236, 72, 255)';
      ctx.lineWidth = 2.5 * dpr;
      ctx.beginPath();
      ctx.arc(x, y, s, 0, 2 * Math.PI);
      ctx.moveTo(x - s * 1.6, y);
      ctx.lineTo(x + s * 1.6, y);
      ctx.moveTo(x, y - s * 1.6);
      ctx.lineTo(x, y + s * 1.6);
      ctx.stroke();
    }
    ctx.restore();
  }
}
