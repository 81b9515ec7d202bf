// The current laser scan: its returns as points in the map frame, with faint rays from the sensor.
import { scanEndpoints } from '../state/robot_store';
import type { DrawContext } from './layer';
import { RobotStoreLayer } from './robot_store_layer';

export class ScanLayer extends RobotStoreLayer {
  readonly id = 'scan';

  protected paint({ ctx, camera, dpr }: DrawContext): void {
    const scan = this.store.scan;
    if (!scan) return;
    const pts = scanEndpoints(scan);
    const ox = camera.worldToScreenX(scan.pose.x), oy = camera.worldToScreenY(scan.pose.y);
    ctx.save();
    ctx.strokeStyle = 'rgba(255, 60, 60, 0.12)';
    ctx.lineWidth = dpr;
    ctx.beginPath();
    for (let i = 0; i < pts.length; i += 2) {
      ctx.moveTo(ox, oy);
      ctx.lineTo(camera.worldToScreenX(pts[i]), camera.worldToScreenY(pts[i + 1]));
    }
    ctx.stroke();
    ctx.fillStyle = 'rgb(255, 60, 60)';
    const s = Math.max(2 * dpr, 0.03 * camera.scale);
    for (let i = 0; i < pts.length; i += 2) {
      ctx.fillRect(camera.worldToScreenX(pts[i]) - s / 2, camera.worldToScreenY(pts[i + 1]) - s / 2, s, s);
    }
    ctx.restore();
  }
}
