// The viewer's shell: sessions and sites (with their map versions) on the left, one or two map
// panes in the middle, layers, predictions and statistics on the right (in compare mode, one block
// per pane, each following its own session). Routes: #/session/ID and #/compare/ID1/ID2.
import { api, type SessionInfo } from '../net/api';
import type { HypothesisColoring } from '../render/hypothesis_layer';
import { h } from './dom';
import { iconElement, icons } from './icons';
import { exportHypotheses, exportMapPgm, exportMapPng, exportViewPng } from './export';
import { HypothesisPanel } from './hypothesis_panel';
import { LayerPanel } from './layer_panel';
import { ReplayDialog } from './replay_dialog';
import { parseRoute, routeFor } from './route';
import { SessionList } from './session_list';
import { SessionView, kLayerIds, type LayerId } from './session_view';
import { SitesPanel } from './sites_panel';
import { StatsPanel } from './stats_panel';

const kPrefsKey = 'pslam.viewer.prefs';

interface Prefs {
  layers: Record<string, boolean>;
  coloring: HypothesisColoring;
  linkCameras: boolean;
}

function loadPrefs(): Prefs {
  const defaults: Prefs = { layers: Object.fromEntries(kLayerIds.map((id) => [id, true])), coloring: 'psi', linkCameras: true };
  try {
    const saved = JSON.parse(localStorage.getItem(kPrefsKey) ?? '{}') as Partial<Prefs>;
    return { ...defaults, ...saved, layers: { ...defaults.layers, ...(saved.layers ?? {}) } };
  } catch {
    return defaults;
  }
}

export class App {
  readonly views: SessionView[] = [];
  focused = 0;
  private readonly prefs = loadPrefs();
  private readonly panes: HTMLElement;
  private readonly sessionList: SessionList;
  private readonly sitesPanel = new SitesPanel();
  private readonly layerPanel: LayerPanel;
  // Per pane: its predictions and statistics panels.
  private readonly panels = new Map<SessionView, { hypotheses: HypothesisPanel; stats: StatsPanel; titles: HTMLElement[] }>();
  private readonly predictionsHost = h('div', { class: 'pane-panels' });
  private readonly statsHost = h('div', { class: 'pane-panels' });
  private readonly replayDialog: ReplayDialog;
  private readonly serverState: HTMLElement;
  private readonly linkButton: HTMLButtonElement;
  private readonly exportMenu: HTMLDetailsElement;
  private readonly empty: HTMLElement;

  constructor(root: HTMLElement) {
    this.sessionList = new SessionList({
      open: (id) => this.navigate([id]),
      compare: (id) => {
        const current = this.views[this.focused]?.sessionId;
        if (current !== id) this.navigate(current ? [current, id] : [id]);
      },
      replay: (id) => this.replayDialog.open(this.sessionList.sessions, id),
    });
    this.sessionList.onReachability = (ok, detail) => this.setServerState(ok, detail);
    this.sessionList.onSessions = (sessions) => {
      this.nameViews(sessions);
      this.openLiveSessionOnArrival(sessions);
    };
    this.layerPanel = new LayerPanel(
      this.prefs.layers,
      this.prefs.coloring,
      (id, visible) => this.setLayer(id, visible),
      (coloring) => {
        this.prefs.coloring = coloring;
        this.savePrefs();
        for (const v of this.views) v.setColoring(coloring);
      },
    );
    this.replayDialog = new ReplayDialog((started) => {
      void this.sessionList.refresh();
      this.navigate(started.map((s) => s.id));
    });
    this.serverState = h('span', { class: 'server-state ok', 'data-server': 'ok' }, 'server connected');
    this.linkButton = h(
      'button',
      { class: 'small', title: 'Pan and zoom both panes together', onclick: () => this.toggleLink(), hidden: true },
      '',
    );
    this.updateLinkButton();
    const exportItem = (label: string, action: (v: SessionView) => Promise<void>, id: string) =>
      h('button', { class: 'menu-item', 'data-export': id, onclick: () => this.runExport(action) }, label);
    this.exportMenu = h(
      'details',
      { class: 'menu' },
      h('summary', { class: 'button' }, 'Export'),
      h(
        'div',
        { class: 'menu-items' },
        exportItem('Map as PNG', exportMapPng, 'png'),
        exportItem('Map as PGM + YAML (map_server)', exportMapPgm, 'pgm'),
        exportItem('Current view as PNG', exportViewPng, 'view'),
        exportItem('Hypotheses as JSON', exportHypotheses, 'hypotheses'),
      ),
    );
    this.empty = h(
      'div',
      { class: 'empty-state' },
      h('h2', {}, 'No session open'),
      h('p', {}, 'Pick a live or stored session on the left, or start a replay.'),
      h('p', { class: 'hint' }, 'Drag to pan · wheel to zoom · double-click to fit · click a prediction to select it'),
    );
    this.panes = h('main', { class: 'panes' }, this.empty);
    const section = (title: string, body: HTMLElement, id: string) =>
      h('details', { class: 'panel', open: true, 'data-panel': id }, h('summary', {}, title), body);
    root.replaceChildren(
      h(
        'div',
        { class: 'app' },
        h(
          'header',
          { class: 'topbar' },
          h('span', { class: 'brand' }, h('b', {}, 'P-SLAM'), ' viewer'),
          this.serverState,
          h('span', { class: 'spacer' }),
          this.linkButton,
          h('button', { 'data-action': 'open-replay', onclick: () => this.replayDialog.open(this.sessionList.sessions, this.views[this.focused]?.sessionId) }, 'Replay…'),
          this.exportMenu,
        ),
        h('aside', { class: 'sidebar left' }, section('Sessions', this.sessionList.element, 'sessions'), section('Sites', this.sitesPanel.element, 'sites')),
        this.panes,
        h(
          'aside',
          { class: 'sidebar right' },
          section('Layers', this.layerPanel.element, 'layers'),
          section('Predictions', this.predictionsHost, 'hypotheses'),
          section('Statistics', this.statsHost, 'stats'),
        ),
        this.replayDialog.element,
      ),
    );
    window.addEventListener('hashchange', () => this.route());
    document.addEventListener('visibilitychange', () => {
      if (document.visibilityState === 'visible') for (const v of this.views) v.client.reconnectNow();
    });
    window.addEventListener('online', () => {
      for (const v of this.views) v.client.reconnectNow();
    });
  }

  start(): void {
    this.sessionList.start();
    this.sitesPanel.start();
    this.route();
  }

  // An operator who opens the page while a robot maps wants to see it at once: the first time the
  // session list arrives with nothing chosen in the URL, the newest live session opens.
  private autoOpened = false;
  private openLiveSessionOnArrival(sessions: { id: string; running: boolean }[]): void {
    if (this.autoOpened) return;
    this.autoOpened = true;
    if (parseRoute(location.hash).length > 0) return;
    const live = sessions.find((s) => s.running);
    if (live) this.navigate([live.id]);
  }

  navigate(ids: string[]): void {
    const hash = routeFor(ids.slice(0, 2));
    if (location.hash === hash) this.route();
    else location.hash = hash;
  }

  private route(): void {
    const ids = parseRoute(location.hash);
    // Keep panes that stay; close the others.
    const keep: SessionView[] = [];
    for (const id of ids) {
      const existing = this.views.find((v) => v.sessionId === id && !keep.includes(v));
      keep.push(existing ?? this.makeView(id));
    }
    for (const v of this.views) if (!keep.includes(v)) v.dispose();
    this.views.splice(0, this.views.length, ...keep);
    this.panes.replaceChildren(...(keep.length ? keep.map((v) => v.element) : [this.empty]));
    this.panes.classList.toggle('compare', keep.length === 2);
    this.linkButton.hidden = keep.length !== 2;
    this.focus(Math.min(this.focused, Math.max(0, keep.length - 1)));
    this.placePanels();
    this.sessionList.setCurrent(ids);
    this.nameViews(this.sessionList.sessions);
    if (keep.length === 2 && this.prefs.linkCameras) keep[1].viewer.setCamera(keep[0].viewer.camera);
  }

  private makeView(id: string): SessionView {
    const v = new SessionView(id, this.prefs.layers, this.prefs.coloring);
    v.onFocus = () => this.focus(this.views.indexOf(v));
    v.onChange = (kind) => {
      if (kind === 'hypotheses' || kind === 'snapshot') this.panels.get(v)?.hypotheses.update();
    };
    v.viewer.onCameraChange = (camera) => {
      if (!this.prefs.linkCameras || this.views.length !== 2) return;
      for (const other of this.views) if (other !== v) other.viewer.setCamera(camera);
    };
    // Linked panes share one camera, so a pane left fitting itself would pull the other back.
    v.onUserAutoFit = (on) => {
      if (!this.prefs.linkCameras || this.views.length !== 2) return;
      for (const other of this.views) if (other !== v) other.setAutoFit(on);
    };
    v.start();
    return v;
  }

  private focus(index: number): void {
    this.focused = Math.max(0, index);
    this.views.forEach((v, i) => v.setFocused(this.views.length > 1 && i === this.focused));
    const view = this.views[this.focused] ?? null;
    document.title = view ? `${view.name} · P-SLAM viewer` : 'P-SLAM viewer';
  }

  // One predictions and one statistics panel per pane, in pane order; headed by the pane's name
  // when two panes are open.
  private placePanels(): void {
    for (const [view, p] of this.panels) {
      if (this.views.includes(view)) continue;
      p.stats.dispose();
      this.panels.delete(view);
    }
    const compare = this.views.length === 2;
    const blocks = (pick: (p: { hypotheses: HypothesisPanel; stats: StatsPanel; titles: HTMLElement[] }) => HTMLElement) =>
      this.views.map((view, i) => {
        let p = this.panels.get(view);
        if (!p) {
          p = { hypotheses: new HypothesisPanel(view), stats: new StatsPanel(view), titles: [] };
          this.panels.set(view, p);
        }
        const title = h('div', { class: 'pane-block-title', hidden: !compare }, `${i === 0 ? 'Left' : 'Right'}: ${view.name}`);
        p.titles.push(title);
        return h('div', { class: 'pane-block', 'data-pane': i }, title, pick(p));
      });
    for (const p of this.panels.values()) p.titles = [];
    this.predictionsHost.replaceChildren(...blocks((p) => p.hypotheses.element));
    this.statsHost.replaceChildren(...blocks((p) => p.stats.element));
    if (this.views.length === 0) this.predictionsHost.replaceChildren(h('div', { class: 'no-live-data' }, 'No session open'));
  }

  private nameViews(sessions: SessionInfo[]): void {
    for (const v of this.views) {
      const s = sessions.find((x) => x.id === v.sessionId);
      if (s) v.setTitle(s.name || s.id);
      else if (v.name === v.sessionId) {
        api.session(v.sessionId).then((info) => v.setTitle(info.name || info.id), () => undefined);
      }
    }
    this.views.forEach((v, i) => {
      for (const t of this.panels.get(v)?.titles ?? []) t.textContent = `${i === 0 ? 'Left' : 'Right'}: ${v.name}`;
    });
    const view = this.views[this.focused];
    if (view) document.title = `${view.name} · P-SLAM viewer`;
  }

  private setLayer(id: LayerId, visible: boolean): void {
    this.prefs.layers[id] = visible;
    this.savePrefs();
    for (const v of this.views) v.setLayerVisible(id, visible);
  }

  private toggleLink(): void {
    this.prefs.linkCameras = !this.prefs.linkCameras;
    this.savePrefs();
    this.updateLinkButton();
    if (this.prefs.linkCameras && this.views.length === 2) this.views[1].viewer.setCamera(this.views[0].viewer.camera);
  }

  private updateLinkButton(): void {
    this.linkButton.replaceChildren(iconElement(icons.link), this.prefs.linkCameras ? ' Views linked' : ' Views independent');
    this.linkButton.classList.toggle('active', this.prefs.linkCameras);
  }

  private setServerState(ok: boolean, detail: string): void {
    this.serverState.textContent = ok ? 'server connected' : 'server unreachable';
    this.serverState.title = detail;
    this.serverState.className = `server-state ${ok ? 'ok' : 'down'}`;
    this.serverState.dataset.server = ok ? 'ok' : 'down';
    if (ok) for (const v of this.views) v.client.reconnectNow();
  }

  private async runExport(action: (v: SessionView) => Promise<void>): Promise<void> {
    this.exportMenu.open = false;
    const view = this.views[this.focused];
    if (!view) return;
    try {
      await action(view);
    } catch (e) {
      alert(`Export failed: ${(e as Error).message}`);
    }
  }

  private savePrefs(): void {
    localStorage.setItem(kPrefsKey, JSON.stringify(this.prefs));
  }
}
