// The list of structure predictions of one pane's session: Psi, area, status, hit ratio; sortable,
// filterable by status; a click focuses the hypothesis on the map.
import type { HypothesisSortKey } from '../state/hypothesis_store';
import { kHypothesisStatuses } from '../state/hypothesis_store';
import { css, psiColor, statusColor } from '../render/palette';
import { formatElapsed, h } from './dom';
import type { SessionView } from './session_view';

// What the server's hit_ratio is (PSlam::JudgeHypotheses, eq. 23): measured by the filter, not by
// the judgement that confirms or refutes a prediction, so a confirmed one can have none.
export const kHitRatioHelp =
  'hit ratio (eq. 23): of the scan endpoints that fell in predicted, not yet mapped cells, the share a predicted wall ' +
  'explained, as the filter measured it while this region came into view (a moving average). "–": no hit was measured: ' +
  'the region was mapped before enough endpoints fell in it, or the filter does not weigh predictions. ' +
  'Confirmed / refuted is judged separately, from the mapped cells (Ψ observed).';

// The hit ratio as shown: the server reports 0 both for "never measured" and "no hit".
export function formatHitRatio(hitRatio: number): string {
  return hitRatio > 0 ? `${Math.round(hitRatio * 100)} %` : '–';
}

const kColumns: { key: HypothesisSortKey; label: string; title: string }[] = [
  { key: 'id', label: '#', title: 'hypothesis id' },
  { key: 'psi', label: 'Ψ', title: 'similarity of the registration (eq. 5)' },
  { key: 'area', label: 'm²', title: 'predicted area' },
  { key: 'status', label: 'status', title: 'pending until later scans confirm or refute it; expired if never checked' },
  { key: 'hit_ratio', label: 'hit', title: kHitRatioHelp },
];

const kMaxRows = 300;

export class HypothesisPanel {
  readonly element: HTMLElement;
  private sort: HypothesisSortKey = 'id';
  private descending = true;
  private status: string | null = null;
  private readonly body: HTMLElement;
  private readonly summary: HTMLElement;
  private readonly head: HTMLElement;
  private readonly details: HTMLElement;
  private renderedVersion = -1;
  private scheduled = false;

  constructor(private readonly view: SessionView) {
    this.summary = h('div', { class: 'hyp-summary' });
    const filter = h(
      'select',
      {
        'data-control': 'hypothesis-filter',
        onchange: (e: Event) => {
          const v = (e.target as HTMLSelectElement).value;
          this.status = v === '' ? null : v;
          this.render(true);
        },
      },
      h('option', { value: '' }, 'all statuses'),
      ...kHypothesisStatuses.map((s) => h('option', { value: s }, s)),
    );
    this.head = h('tr', {});
    this.body = h('tbody', {});
    this.details = h('div', { class: 'hyp-details' });
    this.element = h(
      'div',
      { class: 'hypothesis-panel', 'data-session': view.sessionId },
      h('div', { class: 'row' }, this.summary, filter),
      h('div', { class: 'table-scroll' }, h('table', { class: 'hyp-table' }, h('thead', {}, this.head), this.body)),
      h('div', { class: 'hint', title: kHitRatioHelp }, 'hit: share of scan endpoints in predicted space that a predicted wall explained, as the filter measured it; – none measured.'),
      this.details,
    );
    this.renderHead();
    this.render(true);
  }

  // Re-renders at most a few times a second (hypothesis events can come in bursts).
  update(): void {
    if (this.scheduled) return;
    this.scheduled = true;
    setTimeout(() => {
      this.scheduled = false;
      this.render(false);
    }, 250);
  }

  private renderHead(): void {
    this.head.replaceChildren(
      ...kColumns.map((c) =>
        h(
          'th',
          {
            title: c.title,
            class: this.sort === c.key ? 'sorted' : '',
            onclick: () => {
              if (this.sort === c.key) this.descending = !this.descending;
              else {
                this.sort = c.key;
                this.descending = c.key !== 'status';
              }
              this.renderHead();
              this.render(true);
            },
          },
          c.label,
          this.sort === c.key ? (this.descending ? ' ▾' : ' ▴') : '',
        ),
      ),
    );
  }

  // The selected hypothesis in full: the registration that made it and how it fared.
  private renderDetails(view: SessionView): void {
    const store = view.client.hypotheses;
    const e = store.selected !== null ? store.entries.get(store.selected) : undefined;
    if (!e) {
      this.details.replaceChildren();
      return;
    }
    const hy = e.h;
    const res = view.client.map.resolution;
    const items: [string, string][] = [
      ['Ψ (registration)', hy.psi.toFixed(3)],
      // The server reports 0 until the prediction has been judged against observations.
      ['Ψ observed', hy.psi_observed === null || hy.status === 'pending' ? '–' : hy.psi_observed.toFixed(3)],
      ['hit ratio', formatHitRatio(hy.hit_ratio)],
      ['status', hy.status],
      ['area', `${hy.area.toFixed(1)} m² (${hy.cell_count} cells)`],
      ['target', `(${((hy.target_cell[0] + 0.5) * res).toFixed(2)}, ${((hy.target_cell[1] + 0.5) * res).toFixed(2)}) m`],
      ['reference', `(${((hy.reference_cell[0] + 0.5) * res).toFixed(2)}, ${((hy.reference_cell[1] + 0.5) * res).toFixed(2)}) m` +
        (hy.reference_map ? ` in ${hy.reference_map.site} version ${hy.reference_map.version}` : '')],
      ['rotation', `${((hy.theta * 180) / Math.PI).toFixed(1)}°`],
      ['translation', `(${hy.translation[0].toFixed(2)}, ${hy.translation[1].toFixed(2)}) m`],
      // Input times may be simulated (running faster than real time): shown as time into the run.
      ['predicted', formatElapsed(hy.time, view.client.robot.startTime())],
    ];
    this.details.replaceChildren(
      h('div', { class: 'details-title' }, `H${hy.id}`),
      h('dl', {}, ...items.flatMap(([k, v]) => [h('dt', {}, k), h('dd', {}, v)])),
    );
  }

  private render(force: boolean): void {
    const view = this.view;
    const store = view.client.hypotheses;
    if (!force && store.version === this.renderedVersion) return;
    this.renderedVersion = store.version;
    const counts = store.counts();
    this.summary.replaceChildren(
      h('b', {}, String(counts.total)),
      ' predictions · ',
      ...['pending', 'confirmed', 'refuted'].map((s) =>
        h('span', { class: 'count', style: { color: css(statusColor(s)) } }, `${counts[s] ?? 0} ${s} `),
      ),
    );
    const rows = store.list(this.sort, this.descending, this.status).slice(0, kMaxRows);
    this.body.replaceChildren(
      ...rows.map((hy) => {
        const [r, g, b] = psiColor(hy.psi);
        const loading = store.entries.get(hy.id)?.cellsState === 'loading';
        return h(
          'tr',
          {
            class: store.selected === hy.id ? 'selected' : '',
            'data-hypothesis': hy.id,
            onclick: () => {
              view.focusHypothesis(hy.id);
              this.render(true);
            },
          },
          h('td', {}, `H${hy.id}`, loading ? ' …' : ''),
          h('td', {}, h('i', { class: 'swatch', style: { background: `rgb(${r},${g},${b})` } }), hy.psi.toFixed(2)),
          h('td', {}, hy.area.toFixed(1)),
          h('td', {}, h('span', { class: 'status-chip', style: { background: css(statusColor(hy.status), 0.25), color: css(statusColor(hy.status)) } }, hy.status)),
          h('td', { title: kHitRatioHelp }, formatHitRatio(hy.hit_ratio)),
        );
      }),
    );
    this.renderDetails(view);
    if (rows.length === 0) {
      this.body.append(h('tr', {}, h('td', { colSpan: 5, class: 'empty' }, 'No predictions yet: they appear as the robot maps structure that repeats.')));
    }
  }
}
