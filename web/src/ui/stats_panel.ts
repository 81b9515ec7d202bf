// Statistics of one pane's session: the latest numbers, the evaluation metrics (RPE, KL) when the
// server has computed them, and small time-series plots (uPlot) of scan rate, N_eff, predictions
// and latency; plus the viewer's own frame and tile-update times. A warning line heads the panel
// while the filter looks degraded or lost. A stored session shows no rates or latency (they would
// be the last ones of its run) and no plots (they are drawn from live updates only).
import uPlot from 'uplot';
import 'uplot/dist/uPlot.min.css';
import { api } from '../net/api';
import type { EngineStats } from '../net/protocol';
import type { StatsStore } from '../state/stats_store';
import { h, formatNumber } from './dom';
import { evaluationRows } from './evaluation';
import { localizationRows } from './localization';
import type { SessionView } from './session_view';
import { trackingWarning } from './tracking';

interface PlotSpec {
  title: string;
  series: { key: keyof StatsStore['series']; label: string; color: string; dash?: number[] }[];
  unit: string;
}

const kPlots: PlotSpec[] = [
  { title: 'Scan rate', unit: 'Hz', series: [{ key: 'scan_rate_hz', label: 'scans/s', color: '#4aa8ff' }] },
  { title: 'N_eff', unit: '', series: [{ key: 'neff', label: 'N_eff', color: '#3cc86e' }] },
  {
    title: 'Predictions',
    unit: '',
    series: [
      { key: 'predictions', label: 'predictor runs', color: '#8b93a1', dash: [4, 3] },
      { key: 'hypotheses', label: 'predictions', color: '#ffb020' },
    ],
  },
  {
    title: 'Latency',
    unit: 'ms',
    series: [
      { key: 'latency_ms_mean', label: 'mean', color: '#ec48ff' },
      { key: 'latency_ms_max', label: 'max', color: '#ff6b6b', dash: [4, 3] },
    ],
  },
  { title: 'Prediction time', unit: 'ms', series: [{ key: 'prediction_ms_mean', label: 'mean', color: '#3cc8c8' }] },
];

const kRefreshMs = 500;
// The evaluation metrics come from REST; a replay's appear when it ends.
const kMetricsRefreshMs = 5000;

// Numbers that describe a running session only.
const kLiveOnly = new Set(['scan rate', 'latency', 'queued']);

export class StatsPanel {
  readonly element: HTMLElement;
  private readonly warning: HTMLElement;
  private readonly numbers: HTMLElement;
  private readonly evaluation: HTMLElement;
  private readonly noLiveData: HTMLElement;
  private readonly plots: { spec: PlotSpec; plot: uPlot | null; host: HTMLElement }[];
  private timer: ReturnType<typeof setInterval>;
  private metricsTimer: ReturnType<typeof setInterval>;
  private renderedVersion = -1;
  private countsAt = 0;
  private cellCounts = { known: 0, free: 0, occupied: 0 };
  private metrics: Record<string, unknown> = {};

  constructor(private readonly view: SessionView) {
    this.warning = h('div', { class: 'tracking-warning', role: 'alert', hidden: true });
    this.numbers = h('div', { class: 'stat-grid' });
    this.evaluation = h('div', { class: 'stat-grid evaluation', 'data-section': 'evaluation', hidden: true });
    this.noLiveData = h('div', { class: 'no-live-data', hidden: true }, 'No live data: the plots show what arrives while the session runs and this page is open.');
    this.plots = kPlots.map((spec) => ({ spec, plot: null, host: h('div', { class: 'plot', 'data-plot': spec.title }) }));
    this.element = h('div', { class: 'stats-panel', 'data-session': view.sessionId }, this.warning, this.evaluation, this.numbers, this.noLiveData, ...this.plots.map((p) => p.host));
    this.timer = setInterval(() => this.refresh(false), kRefreshMs);
    this.metricsTimer = setInterval(() => void this.fetchMetrics(), kMetricsRefreshMs);
    void this.fetchMetrics();
    this.refresh(true);
  }

  dispose(): void {
    clearInterval(this.timer);
    clearInterval(this.metricsTimer);
    for (const p of this.plots) p.plot?.destroy();
  }

  private async fetchMetrics(): Promise<void> {
    try {
      const stats = await api.stats(this.view.sessionId);
      this.metrics = stats.metrics ?? {};
      this.renderEvaluation();
    } catch {
      // The server may be away for a moment; the next refresh tries again.
    }
  }

  private renderEvaluation(): void {
    const rows = evaluationRows(this.metrics);
    this.evaluation.hidden = rows.length === 0;
    this.evaluation.replaceChildren(
      ...rows.map((r) => h('div', { class: 'stat wide', title: r.title }, h('span', { class: 'k' }, r.label), h('span', { class: 'v', 'data-stat': r.label }, r.value))),
    );
  }

  private refresh(force: boolean): void {
    const view = this.view;
    if (view.paused && !force) return;
    const c = view.client;
    const s = c.stats;
    this.renderNumbers(view);
    if (!force && s.version === this.renderedVersion) return;
    this.renderedVersion = s.version;
    // Plots need at least two live samples; a stored session has none.
    const hasSeries = s.length >= 2;
    this.noLiveData.hidden = hasSeries;
    for (const p of this.plots) p.host.hidden = !hasSeries;
    if (!hasSeries) return;
    const width = Math.max(160, this.element.clientWidth - 8);
    for (const p of this.plots) {
      const data: uPlot.AlignedData = [s.time, ...p.spec.series.map((x) => s.series[x.key])];
      if (!p.plot || Math.abs(p.plot.width - width) > 4) {
        p.plot?.destroy();
        p.host.replaceChildren();
        p.plot = new uPlot(this.options(p.spec, width), data, p.host);
      } else {
        p.plot.setData(data);
      }
    }
  }

  private renderNumbers(view: SessionView): void {
    const c = view.client;
    const st = c.stats.latest;
    this.renderWarning(st);
    const counts = c.hypotheses.counts();
    // Cell counts walk the whole map: at most once every 2 s.
    if (performance.now() - this.countsAt > 2000) {
      this.cellCounts = c.map.cellCounts();
      this.countsAt = performance.now();
    }
    const area = this.cellCounts.known * c.map.resolution * c.map.resolution;
    const frame = view.viewer.frameStats();
    const tiles = c.tileTimes;
    const tileMean = tiles.length ? tiles.reduce((a, b) => a + b, 0) / tiles.length : NaN;
    const items: [string, string, string?][] = [
      ['scans', formatNumber(st.scans), 'laser scans the filter has taken in'],
      ['filter updates', formatNumber(st.updates)],
      ['resamplings', formatNumber(st.resamplings)],
      ['particles', formatNumber(st.particles)],
      ['N_eff', formatNumber(st.neff, 1)],
      ['scan rate', `${formatNumber(st.scan_rate_hz, 1)} Hz`],
      ['latency', `${formatNumber(st.latency_ms_mean, 1)} / ${formatNumber(st.latency_ms_max, 0)} ms`, 'input received to processed, mean / max'],
      ['filter step', `${formatNumber(st.step_ms_mean, 1)} ms`],
      ['queued', formatNumber(st.queued)],
      ['predictor runs', `${formatNumber(st.predictions_made)} for ${formatNumber(st.targets)} targets`, 'structure predictions finished (kept or not) / exploration targets set'],
      ['predictions', `${counts.total} (${counts.confirmed ?? 0} confirmed)`, 'predictions kept (the Predictions panel lists them)'],
      ['prediction time', `${formatNumber(st.prediction_ms_mean, 0)} / ${formatNumber(st.prediction_ms_max, 0)} ms`, 'mean / max'],
      ['updates w/ predictions', formatNumber(st.updates_using_predictions), 'filter updates whose weights used hypotheses (S2)'],
      ['mapped area', `${formatNumber(area, 1)} m²`],
      ['path', `${formatNumber(c.robot.trajectory.distance(), 1)} m`, 'length of the estimated trajectory, without the jitter of a robot standing still (moves under 5 cm)'],
      ['render', `${formatNumber(frame.drawMeanMs, 2)} ms / frame`, `time to issue a frame's drawing (the browser rasterises after): p95 ${frame.drawP95Ms.toFixed(2)} ms, max ${frame.drawMaxMs.toFixed(2)} ms`],
      ['tile update', `${formatNumber(tileMean, 3)} ms`, 'decode + store, mean of recent tiles (upload is in the frame time)'],
    ];
    items.unshift(...localizationRows(st).map((r): [string, string, string?] => [r.label, r.value, r.title]));
    if (st.rebuilding) items.unshift(['state', 'rebuilding after restart']);
    const live = c.status === 'active';
    this.numbers.replaceChildren(
      ...items.filter(([k]) => live || !kLiveOnly.has(k)).map(([k, v, title]) => h('div', { class: 'stat', title: title ?? '' }, h('span', { class: 'k' }, k), h('span', { class: 'v', 'data-stat': k }, v))),
    );
  }

  private renderWarning(st: EngineStats): void {
    const warning = trackingWarning(st);
    this.warning.hidden = !warning;
    this.warning.className = `tracking-warning ${warning?.level ?? ''}`;
    this.warning.dataset.tracking = st.tracking ?? '';
    this.warning.textContent = warning?.text ?? '';
  }

  private options(spec: PlotSpec, width: number): uPlot.Options {
    const axis: uPlot.Axis = {
      stroke: '#8b93a1',
      grid: { stroke: 'rgba(255,255,255,0.06)', width: 1 },
      ticks: { stroke: 'rgba(255,255,255,0.1)', width: 1 },
      font: '10px system-ui, sans-serif',
      size: 36,
    };
    return {
      title: spec.unit ? `${spec.title} (${spec.unit})` : spec.title,
      width,
      height: 110,
      legend: { show: spec.series.length > 1 },
      cursor: { drag: { x: false, y: false } },
      scales: { x: { time: true }, y: { range: (_u, lo, hi) => [Math.min(0, lo), hi > 0 ? hi * 1.1 : 1] } },
      axes: [{ ...axis, size: 24 }, { ...axis }],
      series: [{}, ...spec.series.map((s) => ({ label: s.label, stroke: s.color, width: 1.5, dash: s.dash, spanGaps: false, points: { show: false } }))],
    };
  }
}
