import { describe, expect, it } from 'vitest';
import { fileStem, renameYamlImage } from '../src/ui/export';
import { replayRequest, type ReplayForm } from '../src/ui/replay_dialog';
import { parseRoute, routeFor } from '../src/ui/route';

describe('routes', () => {
  it('round-trip one and two sessions', () => {
    expect(parseRoute(routeFor(['s-1']))).toEqual(['s-1']);
    expect(parseRoute(routeFor(['a b', 'c/d']))).toEqual(['a b', 'c/d']);
    expect(parseRoute('#/')).toEqual([]);
    expect(parseRoute('#/compare/only-one')).toEqual([]);
  });
});

describe('exports', () => {
  it('points the map_server YAML at the saved PGM', () => {
    const yaml = 'image: map.pgm\nresolution: 0.050000\norigin: [-1.0, -2.0, 0.0]\n';
    expect(renameYamlImage(yaml, 'office_run.pgm')).toBe('image: office_run.pgm\nresolution: 0.050000\norigin: [-1.0, -2.0, 0.0]\n');
    expect(renameYamlImage('resolution: 0.05\n', 'm.pgm')).toBe('image: m.pgm\nresolution: 0.05\n');
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
