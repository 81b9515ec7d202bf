// The robot as the viewer knows it: pose, trajectory, particle cloud, exploration state and the
// current laser scan. Pure data, no DOM; 'version' bumps on every change so views redraw lazily.
import type { ExplorationTarget, ParticlePose, Pose, ScanMessage, TrajectoryPose, XY } from '../net/protocol';

// A growable list of poses, packed [x, y, theta, t] per pose, indexed by scan index from 0.
export class Trajectory {
  private data = new Float64Array(4 * 1024);
  private n = 0;

  get length(): number {
    return this.n;
  }

  // Applies poses starting at 'firstIndex'. An increment that starts inside the known list
  // replaces the rest of it (the server's engine restarted and re-ran its inputs); one that
  // starts past the end leaves a gap the server fills with a full trajectory, so the list is
  // cut there and the gap reported.
  apply(firstIndex: number, poses: TrajectoryPose[]): { gap: boolean } {
    let gap = false;
    if (firstIndex > this.n) {
      gap = true;
      firstIndex = this.n;
    }
    this.n = firstIndex;
    this.reserve(this.n + poses.length);
    for (const p of poses) {
      const o = this.n * 4;
      this.data[o] = p[0];
      this.data[o + 1] = p[1];
      this.data[o + 2] = p[2];
      this.data[o + 3] = p[3] ?? 0;
      this.n++;
    }
    return { gap };
  }

  clear(): void {
    this.n = 0;
  }

  // The packed poses (a view: valid until the next apply).
  packed(): Float64Array {
    return this.data.subarray(0, this.n * 4);
  }

  at(i: number): TrajectoryPose {
    const o = i * 4;
    return [this.data[o], this.data[o + 1], this.data[o + 2], this.data[o + 3]];
  }

  // Length of the path in metres. Moves shorter than 'minStep' from the last counted point are
  // not counted on their own: the pose estimate of a robot standing still jitters by a few
  // centimetres per scan, which summed over minutes would grow the path by metres.
  distance(minStep = 0.05): number {
    if (this.n === 0) return 0;
    let d = 0;
    let ax = this.data[0], ay = this.data[1];
    for (let i = 1; i < this.n; i++) {
      const step = Math.hypot(this.data[i * 4] - ax, this.data[i * 4 + 1] - ay);
      if (step < minStep && i < this.n - 1) continue;
      d += step;
      ax = this.data[i * 4];
      ay = this.data[i * 4 + 1];
    }
    return d;
  }

  private reserve(n: number): void {
    if (n * 4 <= this.data.length) return;
    let size = this.data.length;
    while (size < n * 4) size *= 2;
    const next = new Float64Array(size);
    next.set(this.data.subarray(0, this.n * 4));
    this.data = next;
  }
}

export class RobotStore {
  version = 0;
  pose: Pose | null = null;
  readonly trajectory = new Trajectory();
  particles: ParticlePose[] = [];
  frontiers: XY[] = [];
  target: ExplorationTarget | null = null;
  scan: ScanMessage | null = null;
  // Trajectory increments that did not follow on (the server then sends the whole trajectory).
  trajectoryGaps = 0;

  // The input time of the first scan (Unix seconds, or simulated seconds), or null before it.
  startTime(): number | null {
    return this.trajectory.length > 0 ? this.trajectory.at(0)[3] : null;
  }

  applySnapshot(s: {
    pose: Pose | null;
    trajectory: { first_index: number; poses: TrajectoryPose[] };
    particles: ParticlePose[];
    frontiers: XY[];
    target: ExplorationTarget | null;
    scan?: ScanMessage | null;
  }): void {
    this.pose = s.pose;
    this.trajectory.clear();
    // A snapshot's trajectory starts at first_index (0 today); earlier poses are simply absent.
    this.trajectory.apply(0, s.trajectory.poses);
    this.particles = s.particles;
    this.frontiers = s.frontiers;
    this.target = s.target;
    this.scan = s.scan ?? null;
    this.version++;
  }

  applyPose(p: Pose): void {
    this.pose = { x: p.x, y: p.y, theta: p.theta };
    this.version++;
  }

  applyTrajectory(firstIndex: number, poses: TrajectoryPose[]): void {
    if (this.trajectory.apply(firstIndex, poses).gap) this.trajectoryGaps++;
    this.version++;
  }

  applyParticles(poses: ParticlePose[]): void {
    this.particles = poses;
    this.version++;
  }

  applyExploration(frontiers: XY[], target: ExplorationTarget | null): void {
    this.frontiers = frontiers;
    this.target = target;
    this.version++;
  }

  applyScan(scan: ScanMessage): void {
    this.scan = scan;
    this.version++;
  }

  clear(): void {
    this.pose = null;
    this.trajectory.clear();
    this.particles = [];
    this.frontiers = [];
    this.target = null;
    this.scan = null;
    this.version++;
  }
}

// The world points of a scan's returns (beams without a return are skipped).
export function scanEndpoints(scan: ScanMessage): Float64Array {
  const out = new Float64Array(scan.ranges.length * 2);
  let n = 0;
  const { x, y, theta } = scan.pose;
  for (let i = 0; i < scan.ranges.length; i++) {
    const r = scan.ranges[i];
    if (r === null || !(r > 0) || (scan.max_range !== undefined && r >= scan.max_range)) continue;
    const a = theta + scan.angle_min + i * scan.angle_increment;
    out[n++] = x + r * Math.cos(a);
    out[n++] = y + r * Math.sin(a);
  }
  return out.subarray(0, n);
}
