// The statistics rows of a session's mode and, in localize mode, of its localization: whether
// the robot is localized on the site's map and how spread the heaviest particle cluster is.
import type { EngineStats } from '../net/protocol';

export interface StatRow {
  label: string;
  value: string;
  title?: string;
}

export function localizationRows(st: EngineStats): StatRow[] {
  if (!st.mode) return [];
  const rows: StatRow[] = [{ label: 'mode', value: st.mode === 'localize' ? 'localize on a site map' : st.mode }];
  const l = st.localization;
  if (st.mode !== 'localize' || !l) return rows;
  const spread: string[] = [];
  if (typeof l.position_std_m === 'number') spread.push(`± ${l.position_std_m.toFixed(2)} m`);
  if (typeof l.heading_std_rad === 'number') spread.push(`± ${((l.heading_std_rad * 180) / Math.PI).toFixed(1)}°`);
  rows.push({
    label: 'localized',
    value: `${l.localized ? 'yes' : 'no'}${spread.length ? ` (${spread.join(', ')})` : ''}`,
    title: 'localized: the heaviest particle cluster holds at least 80 % of the weight within 0.15 m and 5°; its spread in brackets',
  });
  if (typeof l.cluster_weight === 'number') {
    rows.push({ label: 'best cluster', value: `${Math.round(l.cluster_weight * 100)} % of ${l.clusters ?? '?'} clusters`, title: 'weight of the heaviest particle cluster' });
  }
  return rows;
}
