import { describe, expect, it } from 'vitest';
import { RobotStore, scanEndpoints, Trajectory } from '../src/state/robot_store';
import { StatsStore } from '../src/state/stats_store';

describe('Trajectory', () => {
  it('appends contiguous increments', () => {
    const t = new Trajectory();
    t.apply(0, [[0, 0, 0, 1], [1, 0, 0, 2]]);
    t.apply(2, [[2, 0, 0, 3]]);
    expect(t.length).toBe(3);
    expect(t.at(2)).toEqual([2, 0, 0, 3]);
    expect(t.distance()).toBeCloseTo(2);
  });

  it('does not grow the path while the robot stands still and its pose jitters', () => {
    const t = new Trajectory();
    const still = Array.from({ length: 1000 }, (_, i) => [0.02 * Math.sin(i * 1.7), 0.02 * Math.cos(i * 2.3), 0, i] as [number, number, number, number]);
    t.apply(0, still);
    expect(t.distance()).toBeLessThan(0.1);
    // Slow driving in 1 cm steps still counts in full.
    const t2 = new Trajectory();
    t2.apply(0, Array.from({ length: 101 }, (_, i) => [i * 0.01, 0, 0, i] as [number, number, number, number]));
    expect(t2.distance()).toBeCloseTo(1, 5);
  });

  it('replaces the tail when an increment starts inside it (engine restarted)', () => {
    const t = new Trajectory();
    t.apply(0, [[0, 0, 0, 0], [1, 0, 0, 0], [2, 0, 0, 0]]);
    expect(t.apply(1, [[5, 5, 0, 0]]).gap).toBe(false);
    expect(t.length).toBe(2);
    expect(t.at(1)[0]).toBe(5);
  });

  it('reports a gap and stays contiguous', () => {
    const t = new Trajectory();
    t.apply(0, [[0, 0, 0, 0]]);
    expect(t.apply(5, [[1, 1, 0, 0]]).gap).toBe(true);
    expect(t.length).toBe(2);
  });

  it('grows past its initial capacity', () => {
    const t = new Trajectory();
    const poses = Array.from({ length: 5000 }, (_, i) => [i, 0, 0, i] as [number, number, number, number]);
    t.apply(0, poses);
    expect(t.length).toBe(5000);
    expect(t.at(4999)[0]).toBe(4999);
  });
});

describe('RobotStore', () => {
  it('applies snapshot and deltas, bumping its version', () => {
    const r = new RobotStore();
    r.applySnapshot({ pose: { x: 1, y: 2, theta: 0 }, trajectory: { first_index: 0, poses: [[0, 0, 0, 0]] }, particles: [], frontiers: [], target: null });
    const v = r.version;
    r.applyPose({ x: 3, y: 4, theta: 1 });
    r.applyExploration([[1, 1]], { x: 1, y: 1, path: [], pose: null });
    expect(r.version).toBe(v + 2);
    expect(r.pose).toEqual({ x: 3, y: 4, theta: 1 });
    expect(r.target?.x).toBe(1);
  });
});

describe('scanEndpoints', () => {
  it('projects returns into the map frame and skips beams without a return', () => {
    const pts = scanEndpoints({ type: 'scan', pose: { x: 1, y: 1, theta: Math.PI / 2 }, angle_min: 0, angle_increment: Math.PI / 2, max_range: 8, ranges: [2, null, 8, 1] });
    expect(pts.length).toBe(4);
    expect(pts[0]).toBeCloseTo(1);
    expect(pts[1]).toBeCloseTo(3);
    // Beam 3 at theta + 3 pi / 2 = 2 pi: straight along +x.
    expect(pts[2]).toBeCloseTo(2);
    expect(pts[3]).toBeCloseTo(1);
  });
});

describe('StatsStore', () => {
  it('records series, keeps time increasing and stays bounded', () => {
    const s = new StatsStore(100);
    for (let i = 0; i < 300; i++) s.add(10, { neff: i, scan_rate_hz: 10 }, i);
    expect(s.length).toBeLessThanOrEqual(125);
    for (let i = 1; i < s.time.length; i++) expect(s.time[i]).toBeGreaterThan(s.time[i - 1]);
    expect(s.series.neff[s.length - 1]).toBe(299);
    expect(s.series.latency_ms_mean[0]).toBeNull();
  });

  it('plots the server hypothesis count, or the viewer count when absent', () => {
    const s = new StatsStore();
    s.add(1, { hypotheses: 4, predictions_made: 9 }, 2);
    s.add(2, {}, 3);
    expect(s.series.hypotheses).toEqual([4, 3]);
    expect(s.series.predictions).toEqual([9, null]);
  });

  it('marks a gap after data only', () => {
    const s = new StatsStore();
    s.markGap(1);
    expect(s.length).toBe(0);
    s.add(2, { neff: 3 }, 0);
    s.markGap(5);
    s.add(6, { neff: 4 }, 0);
    expect(s.series.neff).toEqual([3, null, 4]);
  });
});
