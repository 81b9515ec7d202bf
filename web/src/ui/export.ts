// Exports of the focused session: the map as PNG and as map_server PGM + YAML (rendered by the
// server from the full-precision grid), the current view as PNG, and the hypotheses with their
// predicted cells as JSON.
import { api, fetchBlob, mayAppearLater } from '../net/api';
import { packCells, type HypothesisCells } from '../state/hypothesis_store';
import { download } from './dom';
import type { SessionView } from './session_view';

// map_server's YAML names its image; point it at the PGM as saved here.
export function renameYamlImage(yaml: string, image: string): string {
  return /^image:.*$/m.test(yaml) ? yaml.replace(/^image:.*$/m, `image: ${image}`) : `image: ${image}\n${yaml}`;
}

export function fileStem(name: string): string {
  return name.replace(/[^A-Za-z0-9._-]+/g, '_').replace(/^_+|_+$/g, '').slice(0, 80) || 'map';
}

const kExportConcurrency = 4;
const kStoredAttempts = 5;
const kStoredRetryMs = 1000;

const base = (view: SessionView) => `/api/sessions/${encodeURIComponent(view.sessionId)}`;

export async function exportMapPng(view: SessionView): Promise<void> {
  download(await fetchBlob(`${base(view)}/map.png`), `${fileStem(view.name)}.png`);
}

export async function exportMapPgm(view: SessionView): Promise<void> {
  const stem = fileStem(view.name);
  const [pgm, yaml] = await Promise.all([fetchBlob(`${base(view)}/map.pgm`), fetchBlob(`${base(view)}/map.yaml`)]);
  download(pgm, `${stem}.pgm`);
  download(new Blob([renameYamlImage(await yaml.text(), `${stem}.pgm`)], { type: 'application/yaml' }), `${stem}.yaml`);
}

export async function exportViewPng(view: SessionView): Promise<void> {
  view.viewer.drawNow();
  const blob = await new Promise<Blob | null>((resolve) => view.viewer.canvas.toBlob(resolve, 'image/png'));
  if (blob) download(blob, `${fileStem(view.name)}-view.png`);
}

// A hypothesis's cells over REST, waiting (1 s, 2 s, 4 s apart) for one the viewer was streamed
// before the server stored it.
async function storedCells(view: SessionView, hid: number): Promise<HypothesisCells> {
  for (let attempt = 0; ; attempt++) {
    try {
      return packCells((await api.hypothesis(view.sessionId, hid)).cells ?? []);
    } catch (e) {
      if (!mayAppearLater(e) || attempt >= kStoredAttempts - 1) throw e;
      await new Promise((resolve) => setTimeout(resolve, kStoredRetryMs * 2 ** attempt));
    }
  }
}

// Every hypothesis of the session with its cells ([x, y, occupancy], grid indices), fetching the
// cells the viewer has not loaded yet, a few at a time.
export async function hypothesesJson(view: SessionView): Promise<object> {
  const entries = [...view.client.hypotheses.entries.values()];
  const cells = entries.map((e) => e.cells);
  const missing = entries.flatMap((e, i) => (!e.cells && e.h.cell_count > 0 ? [i] : []));
  const fetchNext = async (): Promise<void> => {
    for (let i = missing.shift(); i !== undefined; i = missing.shift()) cells[i] = await storedCells(view, entries[i].h.id);
  };
  await Promise.all(Array.from({ length: kExportConcurrency }, fetchNext));
  const out = entries.map((e, i) => {
    const c = cells[i];
    const list: [number, number, number][] = [];
    if (c) for (let k = 0; k < c.xs.length; k++) list.push([c.xs[k], c.ys[k], Math.round(c.occupancy[k] * 1000) / 1000]);
    return { ...e.h, cells: list };
  });
  out.sort((a, b) => a.id - b.id);
  return {
    session_id: view.sessionId,
    name: view.name,
    resolution: view.client.map.resolution,
    exported_at: new Date().toISOString(),
    cell_frame: 'grid indices: cell (x, y) covers [x*resolution, (x+1)*resolution) in the map frame',
    hypotheses: out,
  };
}

export async function exportHypotheses(view: SessionView): Promise<void> {
  const json = await hypothesesJson(view);
  download(new Blob([JSON.stringify(json, null, 1)], { type: 'application/json' }), `${fileStem(view.name)}-hypotheses.json`);
}
