import { afterEach, describe, expect, it, vi } from 'vitest';
import type { Hypothesis } from '../src/net/protocol';
import { HypothesisStore, packCells } from '../src/state/hypothesis_store';
import { fileStem, hypothesesJson, renameYamlImage } from '../src/ui/export';
import type { SessionView } from '../src/ui/session_view';
import { snapshotMessage } from './fixtures/live';
import { replayRequest, type ReplayForm } from '../src/ui/replay_dialog';
import { parseRoute, routeFor } from '../src/ui/route';
import { trackingWarning } from '../src/ui/tracking';
import { areaText, explorationNotice } from '../src/ui/exploration_banner';
import { localizationRows } from '../src/ui/localization';
import { poseFromDrag } from '../src/render/pose_tool';

describe('routes', () => {
  it('round-trip one and two sessions', () => {
    expect(parseRoute(routeFor(['s-1']))).toEqual(['s-1']);
    expect(parseRoute(routeFor(['a b', 'c/d']))).toEqual(['a b', 'c/d']);
    expect(parseRoute('#/')).toEqual([]);
    expect(parseRoute('#/compare/only-one')).toEqual([]);
  });
});

describe('exploration banner', () => {
  it('says nothing while exploring or for a server that does not report exploration', () => {
    expect(explorationNotice({})).toBeNull();
    expect(explorationNotice({ exploration: 'exploring', mapped_m2: 10 })).toBeNull();
  });

  it('names the end with the mapped and predicted shares', () => {
    const n = explorationNotice({ exploration: 'complete', mapped_m2: 450, predicted_m2: 50 });
    expect(n?.level).toBe('done');
    expect(n?.text).toBe('Exploration complete · 450 m² mapped (90 %), 50 m² predicted (10 %)');
    expect(areaText({})).toBe('');
  });

  it('warns when the robot waits or is blocked, with the reason', () => {
    const w = explorationNotice({ exploration: 'waiting_for_verification', exploration_reason: '3 frontiers left', mapped_m2: 1 });
    expect(w?.level).toBe('warn');
    expect(w?.text).toContain('3 frontiers left');
    expect(explorationNotice({ exploration: 'blocked' })?.level).toBe('warn');
    expect(explorationNotice({ exploration: 'verifying' })?.level).toBe('info');
  });
});

describe('tracking warning', () => {
  it('says nothing while the filter looks fine, or when the server does not say', () => {
    expect(trackingWarning({ tracking: 'ok', tracking_reason: '' })).toBeNull();
    expect(trackingWarning({ scans: 10 })).toBeNull();
  });

  it('names the state and the reason when the filter looks degraded or lost', () => {
    expect(trackingWarning({ tracking: 'lost', tracking_reason: 'tracking score 0.015 over the last 10 scans' })).toEqual({
      level: 'lost',
      text: 'Filter likely lost: tracking score 0.015 over the last 10 scans',
    });
    expect(trackingWarning({ tracking: 'degraded' })).toEqual({ level: 'degraded', text: 'Filter tracking degraded' });
  });
});

describe('exports', () => {
  it('points the map_server YAML at the saved PGM', () => {
    const yaml = 'image: map.pgm\nresolution: 0.050000\norigin: [-1.0, -2.0, 0.0]\n';
    expect(renameYamlImage(yaml, 'office_run.pgm')).toBe('image: office_run.pgm\nresolution: 0.050000\norigin: [-1.0, -2.0, 0.0]\n');
    expect(renameYamlImage('resolution: 0.05\n', 'm.pgm')).toBe('image: m.pgm\nresolution: 0.05\n');
  });

  afterEach(() => {
    vi.useRealTimers();
    vi.unstubAllGlobals();
  });

  it('waits for the cells of a hypothesis the server has not stored yet', async () => {
    const store = new HypothesisStore();
    const template = snapshotMessage.hypotheses[0] as unknown as Hypothesis;
    store.applyEvent('added', { ...template, id: 1, cell_count: 1 });
    store.setCells(1, packCells([[5, 6, 0.9]]));
    store.applyEvent('added', { ...template, id: 2, cell_count: 2 });
    const requested: string[] = [];
    vi.stubGlobal('location', new URL('http://127.0.0.1:8080/'));
    vi.stubGlobal('sessionStorage', { getItem: () => null, setItem: () => undefined });
    vi.stubGlobal('fetch', async (url: string) => {
      requested.push(url);
      if (requested.length < 3) return new Response(JSON.stringify({ error: { code: 'not_found', message: 'no hypothesis 2' } }), { status: 404 });
      return new Response(JSON.stringify({ id: 2, cells: [[7, 8, 0.1], [7, 9, 0.95]] }), { status: 200 });
    });
    vi.useFakeTimers();
    const view = { sessionId: 's-1', name: 'live', client: { hypotheses: store, map: { resolution: 0.05 } } };
    const done = hypothesesJson(view as unknown as SessionView);
    await vi.advanceTimersByTimeAsync(3500);
    const json = (await done) as { hypotheses: { id: number; cells: number[][] }[] };
    expect(requested).toEqual(Array(3).fill('http://127.0.0.1:8080/api/sessions/s-1/hypotheses/2'));
    expect(json.hypotheses.map((h) => [h.id, h.cells])).toEqual([
      [1, [[5, 6, 0.9]]],
      [2, [[7, 8, 0.1], [7, 9, 0.95]]],
    ]);
  });

  it('gives up on a hypothesis the server says is not there for good', async () => {
    const store = new HypothesisStore();
    store.applyEvent('added', { ...(snapshotMessage.hypotheses[0] as unknown as Hypothesis), id: 3, cell_count: 1 });
    vi.stubGlobal('location', new URL('http://127.0.0.1:8080/'));
    vi.stubGlobal('sessionStorage', { getItem: () => null, setItem: () => undefined });
    vi.stubGlobal('fetch', async () => new Response(JSON.stringify({ error: { code: 'forbidden', message: 'token' } }), { status: 403 }));
    const view = { sessionId: 's-1', name: 'live', client: { hypotheses: store, map: { resolution: 0.05 } } };
    await expect(hypothesesJson(view as unknown as SessionView)).rejects.toThrow('token');
  });

  it('makes safe file names', () => {
    expect(fileStem('replay of intel/intel.clf')).toBe('replay_of_intel_intel.clf');
    expect(fileStem('///')).toBe('map');
  });
});

describe('replay requests', () => {
  const form: ReplayForm = {
    source: 'session',
    session: 's-1',
    log: '',
    relations: '',
    referenceMap: '',
    name: '',
    speed: 5,
    particles: 20,
    predict: true,
    seed: null,
    resolution: null,
  };

  it('match the server ReplayRequest', () => {
    expect(replayRequest(form)).toEqual({ session: 's-1', speed: 5, settings: { predict: true, particles: 20 } });
    expect(replayRequest(form, false).settings).toEqual({ predict: false, particles: 20 });
    expect(replayRequest({ ...form, source: 'log', log: 'intel.clf', relations: 'intel.relations', name: 'x', seed: 3, resolution: 0.1 })).toEqual({
      log: 'intel.clf',
      relations: 'intel.relations',
      name: 'x',
      speed: 5,
      settings: { predict: true, particles: 20, seed: 3, resolution_meters: 0.1 },
    });
  });
});

describe('localization rows', () => {
  it('say nothing for a server that does not report the mode, and only the mode when mapping', () => {
    expect(localizationRows({})).toEqual([]);
    expect(localizationRows({ mode: 'map' }).map((r) => r.value)).toEqual(['map']);
  });

  it('say whether a localize session is localized, with its spread', () => {
    const rows = localizationRows({ mode: 'localize', localization: { localized: true, position_std_m: 0.034, heading_std_rad: Math.PI / 180, cluster_weight: 0.93, clusters: 2 } });
    expect(rows.find((r) => r.label === 'localized')?.value).toBe('yes (± 0.03 m, ± 1.0°)');
    expect(rows.find((r) => r.label === 'best cluster')?.value).toBe('93 % of 2 clusters');
    expect(localizationRows({ mode: 'localize', localization: { localized: false } })[1].value).toBe('no');
  });

  it('say while global localization still searches the map, and when look-alike places remain', () => {
    const place = (p: string) => localizationRows({ mode: 'localize', localization: { localized: false, place: p } }).find((r) => r.label === 'place')?.value;
    expect(place('searching')).toBe('searching the map');
    expect(place('look_alike')).toBe('look-alike places: drive on');
    expect(place('')).toBeUndefined();
  });

  it('label the phase of an extend session, with the localization only while it localizes', () => {
    const localizing = localizationRows({ mode: 'extend_localize', localization: { localized: false } });
    expect(localizing.map((r) => r.value)).toEqual(['extend a site map: localizing on it', 'no']);
    expect(localizationRows({ mode: 'extend_map' }).map((r) => r.value)).toEqual(['extend a site map: mapping on from it']);
  });
});

describe('set-pose drag', () => {
  it('puts the pose at the press and heads it towards the release', () => {
    const p = poseFromDrag(1, 2, 1, 3);
    expect(p.x).toBe(1);
    expect(p.y).toBe(2);
    expect(p.theta).toBeCloseTo(Math.PI / 2);
    expect(poseFromDrag(0, 0, -1, 0).theta).toBeCloseTo(Math.PI);
    expect(poseFromDrag(4, 5, 4, 5).theta).toBe(0); // a click: heading 0
  });
});
