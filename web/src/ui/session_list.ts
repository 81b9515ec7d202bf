// Sessions on the server, live and stored, refreshed every few seconds, with their statistics;
// open one, add one to a side-by-side comparison, or replay it.
import { api, ApiError, type SessionInfo, type SessionStatistics } from '../net/api';
import { formatAge, formatNumber, h } from './dom';
import { evaluationRows, evaluationSummary } from './evaluation';

const kRefreshMs = 3000;

export interface SessionListActions {
  open(id: string): void;
  compare(id: string): void;
  replay(id: string): void;
}

export class SessionList {
  readonly element: HTMLElement;
  sessions: SessionInfo[] = [];
  reachable = true;
  private readonly list: HTMLElement;
  private readonly details: HTMLElement;
  private readonly filterInput: HTMLInputElement;
  private readonly state: HTMLElement;
  private current: string[] = [];
  private detailsFor: string | null = null;
  private timer: ReturnType<typeof setTimeout> | null = null;
  onReachability: ((reachable: boolean, detail: string) => void) | null = null;
  onSessions: ((sessions: SessionInfo[]) => void) | null = null;

  constructor(private readonly actions: SessionListActions) {
    this.filterInput = h('input', { type: 'search', placeholder: 'Filter sessions', oninput: () => this.render() });
    this.state = h('div', { class: 'list-state' });
    this.list = h('ul', { class: 'session-list' });
    this.details = h('div', { class: 'session-details' });
    this.element = h('div', { class: 'sessions' }, this.filterInput, this.state, this.list, this.details);
  }

  start(): void {
    void this.refresh();
  }

  // Marks the sessions shown in the panes.
  setCurrent(ids: string[]): void {
    this.current = ids;
    if (ids[0] && ids[0] !== this.detailsFor) this.detailsFor = ids[0];
    this.render();
    void this.renderDetails();
  }

  async refresh(): Promise<void> {
    if (this.timer) clearTimeout(this.timer);
    try {
      const page = await api.sessions(200);
      this.sessions = page.sessions.sort((a, b) => Number(b.running) - Number(a.running) || b.created_at - a.created_at);
      this.setReachable(true, '');
      this.render();
      void this.renderDetails();
      this.onSessions?.(this.sessions);
    } catch (e) {
      const err = e as ApiError;
      this.setReachable(false, err.message);
      if (err.status === 401 || err.status === 403) this.state.textContent = 'This server needs a viewer token: open the page with ?token=…';
    }
    this.timer = setTimeout(() => void this.refresh(), kRefreshMs);
  }

  private setReachable(reachable: boolean, detail: string): void {
    if (reachable !== this.reachable) {
      this.reachable = reachable;
      this.onReachability?.(reachable, detail);
    }
    this.state.textContent = reachable ? '' : `Server unreachable (${detail}); retrying…`;
    this.element.classList.toggle('unreachable', !reachable);
  }

  private render(): void {
    const q = this.filterInput.value.trim().toLowerCase();
    const rows = this.sessions.filter((s) => !q || `${s.name} ${s.id} ${s.robot_id} ${s.source}`.toLowerCase().includes(q));
    if (this.sessions.length === 0 && this.reachable) this.state.textContent = 'No sessions yet. Start pslam-agent, or replay a log.';
    this.list.replaceChildren(
      ...rows.map((s) => {
        const live = s.running;
        const metrics = evaluationSummary(s.metrics);
        const predict = s.settings?.predict === false ? 'RBPF' : 'P-SLAM';
        return h(
          'li',
          {
            class: `session-row${this.current.includes(s.id) ? ' current' : ''}`,
            'data-session': s.id,
            onclick: () => this.actions.open(s.id),
          },
          h(
            'div',
            { class: 'session-line' },
            h('span', { class: `live-dot ${live ? 'on' : ''}`, title: live ? 'running' : s.status }),
            h('span', { class: 'session-name', title: s.id }, s.name || s.id),
            h('span', { class: `badge status-${s.status}` }, live ? 'live' : s.status),
          ),
          h(
            'div',
            { class: 'session-meta' },
            // A running session's scan count here would lag the live one in its pane (it is the
            // last checkpoint's): only a stored session's, which is final, is shown.
            `${s.source}${s.replay_of ? ' of ' + shortId(s.replay_of) : ''} · ${predict} · ${formatNumber(s.settings?.particles)} particles · ${live ? '' : `${formatNumber(s.scans)} scans · `}${formatAge(s.created_at)}`,
          ),
          metrics ? h('div', { class: 'session-meta metrics', 'data-metrics': '' }, metrics) : null,
          s.failure ? h('div', { class: 'session-meta failure', title: s.failure }, `failed: ${s.failure}`) : null,
          h(
            'div',
            { class: 'session-actions' },
            h('button', { class: 'small', onclick: (e: Event) => (e.stopPropagation(), this.actions.open(s.id)) }, 'Open'),
            h('button', { class: 'small', 'data-action': 'compare', onclick: (e: Event) => (e.stopPropagation(), this.actions.compare(s.id)) }, 'Compare'),
            h('button', { class: 'small', 'data-action': 'replay', onclick: (e: Event) => (e.stopPropagation(), this.actions.replay(s.id)) }, 'Replay'),
          ),
        );
      }),
    );
  }

  private async renderDetails(): Promise<void> {
    const id = this.detailsFor;
    if (!id) {
      this.details.replaceChildren();
      return;
    }
    let stats: SessionStatistics;
    try {
      stats = await api.stats(id);
    } catch {
      return;
    }
    if (id !== this.detailsFor) return;
    // Scans and filter updates are in the Statistics panel (live); here what only the server knows.
    const p = stats.predictions ?? {};
    const counts = (['pending', 'confirmed', 'refuted', 'expired'] as const)
      .filter((k) => typeof p[k] === 'number' && p[k] > 0)
      .map((k) => `${p[k]} ${k}`)
      .join(', ');
    const rows: [string, string, string][] = [
      ['inputs received / stored', `${formatNumber(stats.ingest?.received_seq)} / ${formatNumber(stats.ingest?.acked_seq)}`, 'messages from the robot (scans and odometry): received / stored and acknowledged'],
      ['predictions', counts || 'none', 'kept structure predictions by status'],
      ...evaluationRows(stats.metrics).map((r): [string, string, string] => [r.label, r.value, r.title]),
    ];
    this.details.replaceChildren(
      h('div', { class: 'details-title' }, 'Session'),
      h('dl', {}, ...rows.flatMap(([k, v, title]) => [h('dt', { title }, k), h('dd', { title, 'data-detail': k }, v)])),
    );
  }
}

function shortId(id: string): string {
  return id.length > 18 ? `${id.slice(0, 8)}…${id.slice(-6)}` : id;
}
