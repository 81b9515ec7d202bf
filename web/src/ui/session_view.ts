// One map pane: a session's live client, its viewer with every layer, and the pane's header and
// toolbar (status, connection, zoom, fit, follow, pause, and for a running localize session the
// set-pose tool).
import { api } from '../net/api';
import { SessionClient } from '../net/session_client';
import { ExplorationLayer } from '../render/exploration_layer';
import { HypothesisLayer, predictedCellBox, type HypothesisColoring } from '../render/hypothesis_layer';
import { MapLayer } from '../render/map_layer';
import { buildMapPalette } from '../render/palette';
import { ParticleLayer } from '../render/particle_layer';
import { PoseTool, type WorldPose } from '../render/pose_tool';
import { RobotLayer, TrajectoryLayer } from '../render/robot_layer';
import { ScanLayer } from '../render/scan_layer';
import { Viewer } from '../render/viewer';
import { h } from './dom';
import { fitBox } from './fit_box';
import { ExplorationBanner } from './exploration_banner';
import { iconElement, icons } from './icons';
import { isLocalizing } from './localization';

const kPalette = buildMapPalette();

export const kLayerIds = ['map', 'hypotheses', 'exploration', 'trajectory', 'particles', 'scan', 'robot'] as const;
export type LayerId = (typeof kLayerIds)[number];

export class SessionView {
  readonly client: SessionClient;
  readonly viewer: Viewer;
  readonly element: HTMLElement;
  readonly hypothesisLayers: HypothesisLayer[];
  name: string;
  private readonly statusBadge: HTMLElement;
  private readonly connDot: HTMLElement;
  private readonly connText: HTMLElement;
  private readonly titleEl: HTMLElement;
  private readonly pauseButton: HTMLButtonElement;
  private readonly followButton: HTMLButtonElement;
  private readonly notice: HTMLElement;
  private readonly poseButton: HTMLButtonElement;
  private readonly poseTool = new PoseTool((pose) => void this.setPose(pose));
  // The outcome of the last set-pose, shown for a few seconds.
  private poseMessage: { text: string; level: 'info' | 'error'; time: number } | null = null;
  private readonly banner = new ExplorationBanner();
  private following = false;
  // Keep the whole map in view as it grows, until the user moves the camera.
  private autoFit = true;
  private fittedBounds = '';
  private unsubscribe: () => void;
  onFocus: (() => void) | null = null;
  onChange: ((kind: string) => void) | null = null;
  // The user turned auto-fit on or off here (linked panes follow suit).
  onUserAutoFit: ((on: boolean) => void) | null = null;

  constructor(readonly sessionId: string, visibility: Record<string, boolean>, coloring: HypothesisColoring) {
    this.name = sessionId;
    this.client = new SessionClient(sessionId);
    const mapHost = h('div', { class: 'map-host', 'data-session': sessionId });
    this.titleEl = h('span', { class: 'pane-title' }, sessionId);
    this.statusBadge = h('span', { class: 'badge' }, '…');
    this.connDot = h('span', { class: 'conn-dot', title: 'live connection' });
    this.connText = h('span', { class: 'conn-text' }, 'connecting');
    const button = (icon: string, title: string, onclick: () => void, extra: Record<string, unknown> = {}) =>
      h('button', { class: 'icon-button', title, 'aria-label': title, onclick, ...extra }, iconElement(icon));
    this.pauseButton = button(icons.pause, 'Pause the view (updates are kept and shown on play)', () => this.setPaused(!this.client.isPaused), {
      'data-action': 'pause',
    });
    this.followButton = button(icons.follow, 'Follow the robot', () => this.setFollow(!this.following), { 'data-action': 'follow' });
    this.poseButton = h(
      'button',
      { class: 'small', 'data-action': 'set-pose', hidden: true, title: "Set the robot's pose: press on the map at its position, drag towards its heading, release", onclick: () => this.setPoseToolArmed(this.viewer.pointerTool === null) },
      'Set pose',
    );
    this.notice = h('div', { class: 'pane-notice', hidden: true });
    this.element = h(
      'section',
      { class: 'pane', onpointerdown: () => this.onFocus?.() },
      h(
        'header',
        { class: 'pane-header' },
        this.connDot,
        this.titleEl,
        this.statusBadge,
        this.connText,
        h('span', { class: 'spacer' }),
        this.poseButton,
        button(icons.zoomOut, 'Zoom out', () => this.userZoom(0.8)),
        button(icons.zoomIn, 'Zoom in', () => this.userZoom(1.25)),
        button(icons.fit, 'Fit the map and keep it fitted as it grows (double-click the map)', () => this.userAutoFit(true), { 'data-action': 'fit' }),
        this.followButton,
        this.pauseButton,
      ),
      mapHost,
    );
    mapHost.appendChild(this.notice);
    mapHost.appendChild(this.banner.element);
    this.viewer = new Viewer(mapHost);
    const v = this.viewer;
    // Predicted cells under the map (they show where it is still unknown), their marks over it.
    this.hypothesisLayers = [
      new HypothesisLayer(this.client.hypotheses, this.client.map, 'cells'),
      new HypothesisLayer(this.client.hypotheses, this.client.map, 'marks'),
    ];
    for (const l of this.hypothesisLayers) l.coloring = coloring;
    v.addLayer(this.hypothesisLayers[0]);
    v.addLayer(new MapLayer(this.client.map, kPalette));
    v.addLayer(this.hypothesisLayers[1]);
    v.addLayer(new ExplorationLayer(this.client.robot));
    v.addLayer(new TrajectoryLayer(this.client.robot));
    v.addLayer(new ParticleLayer(this.client.robot));
    v.addLayer(new ScanLayer(this.client.robot));
    v.addLayer(new RobotLayer(this.client.robot));
    v.addLayer(this.poseTool);
    for (const id of kLayerIds) v.setLayerVisible(id, visibility[id] !== false);
    v.fitBox = () =>
      fitBox(this.client.map.knownWorldBounds(), predictedCellBox(this.client.hypotheses), this.client.map.resolution, this.client.robot.pose);
    v.describeCell = (x, y) => {
      const c = this.client.map.cellAt(x, y);
      if (c === null) return '';
      return c === 255 ? 'unknown' : `${c} % occupied`;
    };
    v.follow = () => (this.following ? this.client.robot.pose : null);
    v.onUserCamera = () => this.userAutoFit(false);
    mapHost.addEventListener('dblclick', () => this.userAutoFit(true));
    v.onClick = (x, y) => this.pickHypothesis(x, y);
    this.unsubscribe = this.client.subscribe((e) => {
      if (e.kind === 'state' || e.kind === 'status' || e.kind === 'snapshot' || e.kind === 'error') this.updateHeader();
      else if (e.kind === 'stats' && this.poseButton.hidden === this.canSetPose) this.updateHeader();
      if (e.kind === 'stats' || e.kind === 'snapshot') this.banner.update(this.client.stats.latest);
      if (e.kind === 'tile' || e.kind === 'snapshot' || e.kind === 'hypotheses') this.maybeFit();
      v.requestRender();
      this.onChange?.(e.kind);
    });
    this.updateHeader();
  }

  // The set-pose tool is offered while the session localizes on a site's map and runs.
  get canSetPose(): boolean {
    return isLocalizing(this.client.stats.latest.mode) && this.client.status === 'active' && !this.client.isPaused;
  }

  // Armed, the next press-drag-release on the map sets the pose instead of panning.
  setPoseToolArmed(on: boolean): void {
    const armed = on && this.canSetPose;
    if (!armed) this.poseTool.cancel();
    this.viewer.pointerTool = armed ? this.poseTool : null;
    this.poseButton.classList.toggle('active', armed);
    this.element.classList.toggle('placing-pose', armed);
    this.viewer.invalidate();
  }

  // Sends the pose to the server and shows the outcome.
  async setPose(pose: WorldPose): Promise<void> {
    this.setPoseToolArmed(false);
    try {
      await api.setInitialPose(this.sessionId, pose);
      const deg = (pose.theta * 180) / Math.PI;
      this.showPoseMessage(`Pose set: x ${pose.x.toFixed(2)} m, y ${pose.y.toFixed(2)} m, heading ${deg.toFixed(0)}°`, 'info');
    } catch (e) {
      this.showPoseMessage(`Setting the pose failed: ${(e as Error).message}`, 'error');
    }
  }

  private showPoseMessage(text: string, level: 'info' | 'error'): void {
    this.poseMessage = { text, level, time: Date.now() };
    this.element.dataset.poseResult = level;
    this.updateHeader();
  }

  start(): void {
    this.client.start();
  }

  setTitle(name: string): void {
    this.name = name;
    this.titleEl.textContent = name;
    this.titleEl.title = `${name} (${this.sessionId})`;
  }

  setFocused(focused: boolean): void {
    this.element.classList.toggle('focused', focused);
  }

  setLayerVisible(id: string, visible: boolean): void {
    this.viewer.setLayerVisible(id, visible);
  }

  setColoring(coloring: HypothesisColoring): void {
    for (const l of this.hypothesisLayers) l.coloring = coloring;
    this.viewer.invalidate();
  }

  get paused(): boolean {
    return this.client.isPaused;
  }

  // Pauses the picture: the stores stop changing (what arrives is held) until play.
  setPaused(paused: boolean): void {
    if (paused) this.client.pause();
    else this.client.resume();
    this.pauseButton.replaceChildren(iconElement(paused ? icons.play : icons.pause));
    this.pauseButton.title = paused ? 'Play: show the latest state' : 'Pause the view (updates are kept and shown on play)';
    this.pauseButton.classList.toggle('active', paused);
    if (paused) this.setPoseToolArmed(false);
    this.element.classList.toggle('paused', paused);
    this.viewer.invalidate();
    this.updateHeader();
  }

  setAutoFit(on: boolean): void {
    this.autoFit = on;
    this.fittedBounds = '';
    if (on) {
      this.setFollow(false);
      this.maybeFit();
    }
  }

  private userAutoFit(on: boolean): void {
    this.setAutoFit(on);
    this.onUserAutoFit?.(on);
  }

  private userZoom(factor: number): void {
    this.userAutoFit(false);
    this.viewer.zoomBy(factor);
  }

  // Fits when the map's tile bounds or the predicted regions' bounds changed (cheap to check per
  // tile) while auto-fit is on.
  private maybeFit(): void {
    if (!this.autoFit || this.client.map.loadingSnapshot) return;
    const b = this.client.map.bounds();
    const p = predictedCellBox(this.client.hypotheses);
    const predicted = p ? `|${p.minX},${p.minY},${p.maxX},${p.maxY}` : '';
    const key = b ? `${b.minTx},${b.minTy},${b.maxTx},${b.maxTy}${predicted}` : this.client.robot.pose ? `pose${predicted}` : '';
    if (!key || key === this.fittedBounds) return;
    this.fittedBounds = key;
    this.viewer.fit();
  }

  setFollow(on: boolean): void {
    if (on) this.autoFit = false;
    this.following = on;
    this.followButton.classList.toggle('active', on);
    this.viewer.invalidate();
  }

  // Centres the view on a hypothesis and selects it.
  focusHypothesis(id: number): void {
    const store = this.client.hypotheses;
    store.select(id);
    const e = store.entries.get(id);
    if (!e) return;
    const res = this.client.map.resolution;
    const c = e.cells;
    const box = c
      ? { minX: c.minX * res, minY: c.minY * res, maxX: (c.maxX + 1) * res, maxY: (c.maxY + 1) * res }
      : { minX: (e.h.target_cell[0] - 40) * res, minY: (e.h.target_cell[1] - 40) * res, maxX: (e.h.target_cell[0] + 40) * res, maxY: (e.h.target_cell[1] + 40) * res };
    const pad = Math.max(box.maxX - box.minX, box.maxY - box.minY) * 0.6 + 1;
    this.setFollow(false);
    this.userAutoFit(false);
    this.viewer.camera.fit({ minX: box.minX - pad, minY: box.minY - pad, maxX: box.maxX + pad, maxY: box.maxY + pad });
    this.viewer.invalidate();
    this.viewer.onCameraChange?.(this.viewer.camera);
    this.onChange?.('hypotheses');
  }

  dispose(): void {
    this.unsubscribe();
    this.client.stop();
    this.viewer.dispose();
    this.element.remove();
  }

  private pickHypothesis(x: number, y: number): void {
    const res = this.client.map.resolution;
    const cx = Math.floor(x / res), cy = Math.floor(y / res);
    let best: number | null = null;
    let bestArea = Infinity;
    for (const e of this.client.hypotheses.entries.values()) {
      const c = e.cells;
      const inside = c
        ? cx >= c.minX && cx <= c.maxX && cy >= c.minY && cy <= c.maxY
        : Math.abs(cx - e.h.target_cell[0]) <= 4 && Math.abs(cy - e.h.target_cell[1]) <= 4;
      const area = c ? (c.maxX - c.minX + 1) * (c.maxY - c.minY + 1) : 1;
      if (inside && area < bestArea) {
        best = e.h.id;
        bestArea = area;
      }
    }
    if (best !== this.client.hypotheses.selected) {
      this.client.hypotheses.select(best);
      this.viewer.requestRender();
      this.onChange?.('hypotheses');
    }
  }

  private updateHeader(): void {
    const c = this.client;
    this.poseButton.hidden = !this.canSetPose;
    if (!this.canSetPose && this.viewer.pointerTool) this.setPoseToolArmed(false);
    const status = c.isPaused ? 'paused' : c.status;
    this.statusBadge.textContent = status;
    this.statusBadge.className = `badge status-${status}`;
    this.connDot.className = `conn-dot conn-${c.connectionState}`;
    const text: Record<string, string> = {
      connecting: 'connecting…',
      open: 'live',
      reconnecting: 'reconnecting',
      stopped: 'stopped',
      failed: 'refused',
    };
    // An open socket on a session that no longer runs shows what is stored, not a live stream.
    const label = c.connectionState === 'open' && c.status !== 'active' && c.status !== 'unknown' ? 'stored' : text[c.connectionState];
    this.connText.textContent = label ?? c.connectionState;
    this.connText.title = c.connectionDetail;
    this.element.dataset.connection = c.connectionState;
    this.element.dataset.status = c.status;
    const last = c.errors[c.errors.length - 1];
    delete this.notice.dataset.pose;
    if (c.connectionState === 'reconnecting' || c.connectionState === 'failed') {
      this.notice.hidden = false;
      this.notice.textContent = c.connectionState === 'failed' ? `Live view refused: ${c.connectionDetail}` : `Connection lost: ${c.connectionDetail}`;
      this.notice.className = 'pane-notice warn';
    } else if (this.poseMessage && Date.now() - this.poseMessage.time < 8000) {
      this.notice.hidden = false;
      this.notice.textContent = this.poseMessage.text;
      this.notice.className = `pane-notice ${this.poseMessage.level}`;
      this.notice.dataset.pose = this.poseMessage.level;
      setTimeout(() => this.updateHeader(), 8100);
    } else if (last && Date.now() - last.time < 8000) {
      this.notice.hidden = false;
      this.notice.textContent = last.message;
      this.notice.className = 'pane-notice error';
      setTimeout(() => this.updateHeader(), 8100);
    } else {
      this.notice.hidden = true;
    }
  }
}
