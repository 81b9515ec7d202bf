// What "fit" shows: the mapped area and every predicted region (predictions reach past the map,
// into unexplored space), or 10 m around the robot before there is a map.
import type { WorldBox } from '../render/camera';
import type { CellBox } from '../render/hypothesis_layer';

export function fitBox(
  known: WorldBox | null,
  predicted: CellBox | null,
  resolution: number,
  pose: { x: number; y: number } | null,
): WorldBox | null {
  const boxes: WorldBox[] = [];
  if (known) boxes.push(known);
  if (predicted) {
    boxes.push({
      minX: predicted.minX * resolution,
      minY: predicted.minY * resolution,
      maxX: (predicted.maxX + 1) * resolution,
      maxY: (predicted.maxY + 1) * resolution,
    });
  }
  if (boxes.length === 0) return pose ? { minX: pose.x - 5, minY: pose.y - 5, maxX: pose.x + 5, maxY: pose.y + 5 } : null;
  return {
    minX: Math.min(...boxes.map((b) => b.minX)),
    minY: Math.min(...boxes.map((b) => b.minY)),
    maxX: Math.max(...boxes.map((b) => b.maxX)),
    maxY: Math.max(...boxes.map((b) => b.maxY)),
  };
}
