// The statistics rows of a session's mode and, while it localizes (localize mode, or an extend
// session before it maps), of its localization: whether the robot is localized on the site's map
// and how spread the heaviest particle cluster is.
import type { EngineStats } from '../net/protocol';

export interface StatRow {
  label: string;
  value: string;
  title?: string;
}

const MODE_LABELS: Record<string, string> = {
  localize: 'localize on a site map',
  extend_localize: 'extend a site map: localizing on it',
  extend_map: 'extend a site map: mapping on from it',
};

// Whether the session localizes on a site's map now (and so takes a pose).
export function isLocalizing(mode: string | undefined): boolean {
  return mode === 'localize' || mode === 'extend_localize';
}

export function localizationRows(st: EngineStats): StatRow[] {
  if (!st.mode) return [];
  const rows: StatRow[] = [{ label: 'mode', value: MODE_LABELS[st.mode] ?? st.mode }];
  const l = st.localization;
  if (!isLocalizing(st.mode) || !l) return rows;
  const spread: string[] = [];
  if (typeof l.position_std_m === 'number') spread.push(`± ${l.position_std_m.toFixed(2)} m`);
  if (typeof l.heading_std_rad === 'number') spread.push(`± ${((l.heading_std_rad * 180) / Math.PI).toFixed(1)}°`);
  rows.push({
    label: 'localized',
    value: `${l.localized ? 'yes' : 'no'}${spread.length ? ` (${spread.join(', ')})` : ''}`,
    title: 'localized: the heaviest particle cluster holds at least 80 % of the weight within 0.15 m and 5°; its spread in brackets',
  });
  if (l.place === 'searching' || l.place === 'look_alike') {
    rows.push({
      label: 'place',
      value: l.place === 'searching' ? 'searching the map' : 'look-alike places: drive on',
      title: 'global localization: the scans of the last metres are searched for over the whole map; where another place explains them as well, the robot must see more before it is localized',
    });
  }
  if (typeof l.cluster_weight === 'number') {
    rows.push({ label: 'best cluster', value: `${Math.round(l.cluster_weight * 100)} % of ${l.clusters ?? '?'} clusters`, title: 'weight of the heaviest particle cluster' });
  }
  return rows;
}
