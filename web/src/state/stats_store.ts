// Time series of a session's statistics for the small plots: one sample per stats message,
// bounded. Pure data, no DOM.
import type { EngineStats } from '../net/protocol';

export const kSeries = ['scan_rate_hz', 'neff', 'predictions', 'hypotheses', 'latency_ms_mean', 'latency_ms_max', 'prediction_ms_mean', 'queued'] as const;
export type SeriesName = (typeof kSeries)[number];

export class StatsStore {
  version = 0;
  latest: EngineStats = {};
  readonly time: number[] = [];
  // null marks a gap (no data, e.g. while the server was away); plots break the line there.
  readonly series: Record<SeriesName, (number | null)[]> = {
    scan_rate_hz: [],
    neff: [],
    predictions: [],
    hypotheses: [],
    latency_ms_mean: [],
    latency_ms_max: [],
    prediction_ms_mean: [],
    queued: [],
  };

  constructor(readonly capacity = 1200) {}

  // Adds a sample at 'timeSeconds'. 'knownHypotheses' (the viewer's count) stands in for the
  // server's hypothesis count when the server does not report it.
  add(timeSeconds: number, stats: EngineStats, knownHypotheses: number): void {
    this.latest = stats;
    // Equal times would make a plot's x axis ambiguous; keep them increasing.
    const last = this.time.length ? this.time[this.time.length - 1] : -Infinity;
    this.time.push(timeSeconds > last ? timeSeconds : last + 1e-3);
    const value = (v: number | undefined) => (typeof v === 'number' && Number.isFinite(v) ? v : null);
    this.series.scan_rate_hz.push(value(stats.scan_rate_hz));
    this.series.neff.push(value(stats.neff));
    this.series.predictions.push(value(stats.predictions_made));
    this.series.hypotheses.push(value(stats.hypotheses) ?? knownHypotheses);
    this.series.latency_ms_mean.push(value(stats.latency_ms_mean));
    this.series.latency_ms_max.push(value(stats.latency_ms_max));
    this.series.prediction_ms_mean.push(value(stats.prediction_ms_mean));
    this.series.queued.push(value(stats.queued));
    // Trim in batches, so the cost of shifting is paid once per capacity/4 samples.
    if (this.time.length > this.capacity * 1.25) {
      const drop = this.time.length - this.capacity;
      this.time.splice(0, drop);
      for (const name of kSeries) this.series[name].splice(0, drop);
    }
    this.version++;
  }

  // Breaks the plotted lines at 'timeSeconds' (a reconnect: the samples do not follow on).
  markGap(timeSeconds: number): void {
    if (this.time.length === 0) return;
    const last = this.time[this.time.length - 1];
    this.time.push(timeSeconds > last ? timeSeconds : last + 1e-3);
    for (const name of kSeries) this.series[name].push(null);
    this.version++;
  }

  // Keeps 'latest' (a snapshot's statistics) without adding a point to the plots.
  setLatest(stats: EngineStats): void {
    this.latest = stats;
    this.version++;
  }

  get length(): number {
    return this.time.length;
  }

  clear(): void {
    this.time.length = 0;
    for (const name of kSeries) this.series[name].length = 0;
    this.latest = {};
    this.version++;
  }
}
