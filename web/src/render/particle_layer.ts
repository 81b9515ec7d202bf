// The particle cloud: one short arrow per particle, brighter for heavier particles.
import type { DrawContext } from './layer';
import { RobotStoreLayer } from './robot_store_layer';
import { viridis } from './palette';

export class ParticleLayer extends RobotStoreLayer {
  readonly id = 'particles';

  protected paint({ ctx, camera, dpr }: DrawContext): void {
    const particles = this.store.particles;
    if (particles.length === 0) return;
    let maxW = 0;
    for (const p of particles) maxW = Math.max(maxW, p[3] ?? 0);
    const len = Math.max(8 * dpr, 0.15 * camera.scale);
    ctx.save();
    ctx.lineWidth = 1.5 * dpr;
    for (const p of particles) {
      const x = camera.worldToScreenX(p[0]), y = camera.worldToScreenY(p[1]);
      const t = maxW > 0 ? (p[3] ?? 0) / maxW : 0.5;
      const [r, g, b] = viridis(0.25 + 0.75 * t);
      ctx.strokeStyle = `rgb(${r},${g},${b})`;
      ctx.fillStyle = ctx.strokeStyle;
      ctx.beginPath();
      ctx.arc(x, y, 2 * dpr, 0, 2 * Math.PI);
      ctx.fill();
      ctx.beginPath();
      ctx.moveTo(x, y);
      ctx.lineTo(x + len * Math.cos(p[2]), y - len * Math.sin(p[2]));
      ctx.stroke();
    }
    ctx.restore();
  }
}
