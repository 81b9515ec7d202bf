// Layer stories (like foxglove's): each layer drawn by the real viewer from fixed data in a small
// synthetic office, so its look can be reviewed in a screenshot and checked by
// tests/web/stories.test.mjs without a server.
import '../styles.css';
import { zlibSync } from 'fflate';
import { encodeTileFrame, type Hypothesis, type LiveMessage } from '../net/protocol';
import { SessionClient } from '../net/session_client';
import { ExplorationLayer } from '../render/exploration_layer';
import { HypothesisLayer, type HypothesisColoring } from '../render/hypothesis_layer';
import { MapLayer } from '../render/map_layer';
import { buildMapPalette } from '../render/palette';
import { ParticleLayer } from '../render/particle_layer';
import { RobotLayer, TrajectoryLayer } from '../render/robot_layer';
import { ScanLayer } from '../render/scan_layer';
import { Viewer } from '../render/viewer';
import { packCells } from '../state/hypothesis_store';

const kRes = 0.05;
const kSize = 64;

// A corridor along y = 2 m with rooms on both sides, 16 x 8 m; x > 10 m is unexplored.
function occupancy(cx: number, cy: number): number {
  const x = cx * kRes, y = cy * kRes;
  if (x < 0 || y < -4 || y > 4 || x > 10) return 255;
  const wall = (Math.abs(y - 1) < 0.06 || Math.abs(y + 1) < 0.06) && !(x % 4 > 1.5 && x % 4 < 2.4);
  const roomWall = Math.abs(x % 4) < 0.06 && Math.abs(y) > 1;
  const outer = Math.abs(Math.abs(y) - 4) < 0.06;
  if (wall || roomWall || outer) return 100;
  return Math.abs(y) > 3.6 && x > 8 ? 255 : 3;
}

function mapFrames(): Uint8Array[] {
  const frames: Uint8Array[] = [];
  for (let ty = -2; ty <= 1; ty++) {
    for (let tx = 0; tx <= 3; tx++) {
      const cells = new Uint8Array(kSize * kSize);
      for (let r = 0; r < kSize; r++) for (let c = 0; c < kSize; c++) cells[r * kSize + c] = occupancy(tx * kSize + c, ty * kSize + r);
      if (cells.every((v) => v === 255)) continue;
      frames.push(encodeTileFrame({ tx, ty, size: kSize, revision: 1, cells }, (d) => zlibSync(d)));
    }
  }
  return frames;
}

// Predicted rooms beyond x = 10 m: the known room pattern shifted by 4 m. H1 and H2 overlap by
// half a metre (predictions of neighbouring frontiers do), with Psi 0.75 and 0.9.
function hypotheses(): { h: Hypothesis; cells: [number, number, number][] }[] {
  const statuses = ['pending', 'confirmed', 'refuted', 'expired'];
  return [0, 1, 2, 3].map((i) => {
    const cells: [number, number, number][] = [];
    const x0 = 10 + (i % 2) * 1.5, y0 = i < 2 ? 1 : -4;
    for (let cx = Math.round(x0 / kRes); cx < Math.round((x0 + 2) / kRes); cx++) {
      for (let cy = Math.round(y0 / kRes); cy < Math.round((y0 + 3) / kRes); cy++) {
        const v = occupancy(cx - 80, cy);
        if (v !== 255) cells.push([cx, cy, v / 100]);
      }
    }
    const h: Hypothesis = {
      id: i + 1,
      time: 0,
      target_cell: [Math.round((x0 + 1) / kRes), Math.round((y0 + 1.5) / kRes)],
      reference_cell: [Math.round((x0 - 3) / kRes), Math.round((y0 + 1.5) / kRes)],
      theta: 0,
      translation: [4, 0],
      psi: [0.75, 0.9, 0.6, 0.45][i],
      area: cells.length * kRes * kRes,
      cell_count: cells.length,
      status: statuses[i],
      hit_ratio: i * 0.25,
      psi_observed: null,
    };
    return { h, cells };
  });
}

const pose = { x: 8.6, y: 0.1, theta: 0.2 };

function snapshot(tileCount: number, hyps: Hypothesis[]): LiveMessage {
  const trajectory = Array.from({ length: 60 }, (_, i) => [0.5 + (i / 59) * 8.1, 0.3 * Math.sin(i / 9), 0, i] as [number, number, number, number]);
  const particles = Array.from({ length: 30 }, (_, i) => [pose.x + 0.15 * Math.cos(i * 2.4), pose.y + 0.1 * Math.sin(i * 1.7), pose.theta + 0.1 * Math.sin(i), (i % 7) / 7] as [number, number, number, number]);
  return {
    type: 'snapshot',
    session_id: 'story',
    status: 'active',
    resolution: kRes,
    tile_size: kSize,
    tile_count: tileCount,
    pose,
    trajectory: { first_index: 0, poses: trajectory },
    particles,
    hypotheses: hyps,
    frontiers: Array.from({ length: 16 }, (_, i) => [10, -0.9 + i * 0.12] as [number, number]),
    target: { x: 10.2, y: 0, path: [[pose.x, pose.y], [9.4, 0.2], [10.2, 0]], pose },
    stats: {},
  };
}

function story(title: string, layers: string[], coloring: HypothesisColoring, selected: number | null): Viewer {
  const host = document.createElement('div');
  host.className = 'story';
  host.dataset.story = title;
  const label = document.createElement('div');
  label.className = 'story-title';
  label.textContent = title;
  const view = document.createElement('div');
  view.className = 'story-view map-host';
  host.append(label, view);
  document.getElementById('stories')!.appendChild(host);

  const client = new SessionClient('story', undefined, false);
  clients[title] = client;
  const frames = mapFrames();
  const hyps = hypotheses();
  client.handle(snapshot(frames.length, hyps.map((x) => x.h)));
  for (const f of frames) client.handleTile(f);
  for (const x of hyps) client.hypotheses.setCells(x.h.id, packCells(x.cells));
  client.hypotheses.select(selected);
  client.handle({ type: 'scan', pose, angle_min: -Math.PI / 2, angle_increment: Math.PI / 180, max_range: 8, ranges: Array.from({ length: 181 }, (_, i) => (i % 13 === 0 ? null : 0.9 + 0.3 * Math.abs(Math.sin(i / 20)))) });

  const v = new Viewer(view);
  const [cells, marks] = (['cells', 'marks'] as const).map((part) => new HypothesisLayer(client.hypotheses, client.map, part));
  cells.coloring = marks.coloring = coloring;
  v.addLayer(cells);
  v.addLayer(new MapLayer(client.map, buildMapPalette()));
  v.addLayer(marks);
  v.addLayer(new ExplorationLayer(client.robot));
  v.addLayer(new TrajectoryLayer(client.robot));
  v.addLayer(new ParticleLayer(client.robot));
  v.addLayer(new ScanLayer(client.robot));
  v.addLayer(new RobotLayer(client.robot));
  for (const id of ['map', 'hypotheses', 'exploration', 'trajectory', 'particles', 'scan', 'robot']) v.setLayerVisible(id, layers.includes(id));
  v.fitBox = () => ({ minX: -0.5, minY: -4.5, maxX: 14.5, maxY: 4.5 });
  v.fit();
  return v;
}

const clients: Record<string, SessionClient> = {};

const style = document.createElement('style');
style.textContent = `
  html, body { overflow: auto; }
  #stories { display: grid; grid-template-columns: repeat(2, 640px); gap: 12px; padding: 12px; }
  .story-title { color: #d7dce4; font: 600 12px system-ui, sans-serif; margin-bottom: 4px; }
  .story-view { position: relative; width: 640px; height: 400px; }
`;
document.head.appendChild(style);

const all = ['map', 'hypotheses', 'exploration', 'trajectory', 'particles', 'scan', 'robot'];
const viewers: Record<string, Viewer> = {
  'built map': story('built map', ['map'], 'psi', null),
  'predictions by psi, H3 selected': story('predictions by psi, H3 selected', ['map', 'hypotheses'], 'psi', 3),
  'predictions by status': story('predictions by status', ['map', 'hypotheses'], 'status', null),
  'robot, trajectory, exploration, particles, scan': story('robot, trajectory, exploration, particles, scan', all.filter((l) => l !== 'hypotheses'), 'psi', null),
};

// For the test: draw every story now, then report.
requestAnimationFrame(() => {
  for (const v of Object.values(viewers)) v.drawNow();
  (window as unknown as { storiesReady: boolean }).storiesReady = true;
  (window as unknown as { stories: Record<string, Viewer> }).stories = viewers;
  (window as unknown as { storyClients: Record<string, SessionClient> }).storyClients = clients;
});
