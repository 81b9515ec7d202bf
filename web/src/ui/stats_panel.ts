// Statistics of the focused session: the latest numbers and small time-series plots (uPlot) of
// scan rate, N_eff, predictions and latency; plus the viewer's own frame and tile-update times.
// A warning line heads the panel while the filter looks degraded or lost.
import uPlot from 'uplot';
import 'uplot/dist/uPlot.min.css';
import type { EngineStats } from '../net/protocol';
import type { StatsStore } from '../state/stats_store';
import { h, formatNumber } from './dom';
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
      { key: 'predictions', label: 'made', color: '#8b93a1', dash: [4, 3] },
      { key: 'hypotheses', label: 'hypotheses', color: '#ffb020' },
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

export class StatsPanel {
  readonly element: HTMLElement;
  private view: SessionView | null = null;
  private readonly warning: HTMLElement;
  private readonly numbers: HTMLElement;
  private readonly plots: { spec: PlotSpec; plot: uPlot | null; host: HTMLElement }[];
  private timer: ReturnType<typeof setInterval>;
  private renderedVersion = -1;
  private countsAt = 0;
  private cellCounts = { known: 0, free: 0, occupied: 0 };

  constructor() {
    this.warning = h('div', { class: 'tracking-warning', role: 'alert', hidden: true });
    this.numbers = h('div', { class: 'stat-grid' });
    this.plots = kPlots.map((spec) => ({ spec, plot: null, host: h('div', { class: 'plot', 'data-plot': spec.title }) }));
    this.element = h('div', { class: 'stats-panel' }, this.warning, this.numbers, ...this.plots.map((p) => p.host));
    this.timer = setInterval(() => this.refresh(false), kRefreshMs);
  }

  setView(view: SessionView | null): void {
    this.view = view;
    this.renderedVersion = -1;
    this.countsAt = 0;
    this.refresh(true);
  }

  dispose(): void {
    clearInterval(this.timer);
    for (const p of this.plots) p.plot?.destroy();
  }

  private refresh(force: boolean): void {
    const view = this.view;
    if (!view || (view.paused && !force)) return;
    const c = view.client;
    const s = c.stats;
    this.renderNumbers(view);
    if (!force && s.version === this.renderedVersion) return;
    this.renderedVersion = s.version;
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
      ['scans', formatNumber(st.scans)],
      ['filter updates', formatNumber(st.updates)],
      ['resamplings', formatNumber(st.resamplings)],
      ['particles', formatNumber(st.particles)],
      ['N_eff', formatNumber(st.neff, 1)],
      ['scan rate', `${formatNumber(st.scan_rate_hz, 1)} Hz`],
      ['latency', `${formatNumber(st.latency_ms_mean, 1)} / ${formatNumber(st.latency_ms_max, 0)} ms`, 'input received to processed, mean / max'],
      ['filter step', `${formatNumber(st.step_ms_mean, 1)} ms`],
      ['queued', formatNumber(st.queued)],
      ['predictions', `${formatNumber(st.predictions_made)} made, ${formatNumber(st.targets)} targets`, 'structure predictions finished / exploration targets set'],
      ['hypotheses', `${counts.total} (${counts.confirmed ?? 0} confirmed)`],
      ['prediction time', `${formatNumber(st.prediction_ms_mean, 0)} / ${formatNumber(st.prediction_ms_max, 0)} ms`, 'mean / max'],
      ['updates w/ predictions', formatNumber(st.updates_using_predictions), 'filter updates whose weights used hypotheses (S2)'],
      ['mapped area', `${formatNumber(area, 1)} m²`],
      ['path', `${formatNumber(c.robot.trajectory.distance(), 1)} m`],
      ['render', `${formatNumber(frame.drawMeanMs, 2)} ms / frame`, `time to issue a frame's drawing (the browser rasterises after): p95 ${frame.drawP95Ms.toFixed(2)} ms, max ${frame.drawMaxMs.toFixed(2)} ms`],
      ['tile update', `${formatNumber(tileMean, 3)} ms`, 'decode + store, mean of recent tiles (upload is in the frame time)'],
    ];
    if (st.rebuilding) items.unshift(['state', 'rebuilding after restart']);
    this.numbers.replaceChildren(
      ...items.map(([k, v, title]) => h('div', { class: 'stat', title: title ?? '' }, h('span', { class: 'k' }, k), h('span', { class: 'v', 'data-stat': k }, v))),
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
