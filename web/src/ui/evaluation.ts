// A session's evaluation metrics (the server computes them when a replay with relations or a
// reference map ends: schema/openapi.yaml, SessionStatistics.metrics) as numbers a reader wants:
// RPE mean ± std for translation and rotation, the relations used, and the map's KL divergence.
import { formatNumber } from './dom';

export interface EvaluationRow {
  label: string;
  value: string;
  title: string;
}

type Json = Record<string, unknown>;

const num = (v: unknown): number | undefined => (typeof v === 'number' && Number.isFinite(v) ? v : undefined);
const isObject = (v: unknown): v is Json => typeof v === 'object' && v !== null && !Array.isArray(v);
const meanStd = (mean: unknown, std: unknown, digits: number, unit: string) =>
  num(mean) === undefined ? '–' : `${num(mean)!.toFixed(digits)} ± ${num(std) === undefined ? '–' : num(std)!.toFixed(digits)} ${unit}`;

export function evaluationRows(metrics: Json | null | undefined): EvaluationRow[] {
  if (!isObject(metrics)) return [];
  const rows: EvaluationRow[] = [];
  const rpe = metrics.rpe;
  if (isObject(rpe)) {
    rows.push({
      label: 'RPE translation',
      value: meanStd(rpe.trans_mean_m, rpe.trans_std_m, 3, 'm'),
      title: `relative pose error against the relations file, translation: mean ± standard deviation; max ${formatNumber(num(rpe.trans_max_m), 3)} m`,
    });
    rows.push({
      label: 'RPE rotation',
      value: meanStd(rpe.rot_mean_deg, rpe.rot_std_deg, 2, '°'),
      title: `relative pose error against the relations file, rotation: mean ± standard deviation; max ${formatNumber(num(rpe.rot_max_deg), 2)}°`,
    });
    const missing = num(rpe.missing) ?? 0;
    rows.push({
      label: 'relations used',
      value: `${formatNumber(num(rpe.used))}${missing > 0 ? ` (${formatNumber(missing)} without a pose)` : ''}`,
      title: 'relations whose two times both have a pose of the run within the tolerance; the others fall outside the part of the log that was run, or between its scans',
    });
  }
  const kl = metrics.kl;
  if (isObject(kl)) {
    rows.push({
      label: 'map KL',
      value: `${formatNumber(num(kl.nats), 3)} nats`,
      title: `KL divergence of the built map from the reference map, over the ${formatNumber(num(kl.cells))} cells both know (lower is closer)`,
    });
  }
  if (typeof metrics.error === 'string') rows.push({ label: 'evaluation error', value: metrics.error, title: 'the server could not compute the metrics' });
  // Metrics this viewer does not know yet: numbers as they are, anything else left out.
  for (const [k, v] of Object.entries(metrics)) {
    if (k === 'rpe' || k === 'kl' || k === 'error') continue;
    if (num(v) !== undefined) rows.push({ label: k, value: formatNumber(v, 4), title: '' });
  }
  return rows;
}

// One short line for the session list: 'RPE 0.017 ± 0.010 m, 0.27 ± 0.21° · KL 1.234 nats'.
export function evaluationSummary(metrics: Json | null | undefined): string {
  if (!isObject(metrics)) return '';
  const parts: string[] = [];
  if (isObject(metrics.rpe)) {
    const r = metrics.rpe;
    parts.push(`RPE ${meanStd(r.trans_mean_m, r.trans_std_m, 3, 'm')}, ${meanStd(r.rot_mean_deg, r.rot_std_deg, 2, '°')}`);
  }
  if (isObject(metrics.kl)) parts.push(`KL ${formatNumber(num(metrics.kl.nats), 3)} nats`);
  if (typeof metrics.error === 'string') parts.push('evaluation failed');
  return parts.join(' · ');
}
