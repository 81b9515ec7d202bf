// A layer drawn from the robot store alone: it has something new to show whenever the store's
// version moved on since its last draw.
import type { RobotStore } from '../state/robot_store';
import type { DrawContext, Layer } from './layer';

export abstract class RobotStoreLayer implements Layer {
  abstract readonly id: string;
  visible = true;
  private drawn = -1;
  constructor(protected readonly store: RobotStore) {}

  needsDraw(): boolean {
    return this.drawn !== this.store.version;
  }

  draw(d: DrawContext): void {
    this.drawn = this.store.version;
    this.paint(d);
  }

  protected abstract paint(d: DrawContext): void;

  dispose(): void {}
}
