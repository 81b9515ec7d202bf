import { describe, expect, it } from 'vitest';
import type { Hypothesis } from '../src/net/protocol';
import { predictedCellBox } from '../src/render/hypothesis_layer';
import { kPsiSteps, psiColor, psiStep } from '../src/render/palette';
import { HypothesisStore, packCells } from '../src/state/hypothesis_store';
import { formatElapsed } from '../src/ui/dom';
import { evaluationRows, evaluationSummary } from '../src/ui/evaluation';
import { fitBox } from '../src/ui/fit_box';
import { formatHitRatio } from '../src/ui/hypothesis_panel';
import { snapshotMessage } from './fixtures/live';

const distance = (a: number[], b: number[]) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);

describe('psi colour scale', () => {
  it('has a visibly different colour for every 0.05 step from 0.7 to 1', () => {
    const values = [0.72, 0.77, 0.82, 0.87, 0.92, 0.97];
    for (let i = 1; i < values.length; i++) {
      expect(distance(psiColor(values[i - 1]), psiColor(values[i])), `${values[i - 1]} vs ${values[i]}`).toBeGreaterThan(40);
    }
    expect(distance(psiColor(0.75), psiColor(0.9))).toBeGreaterThan(100);
  });

  it('puts a value on a step boundary into the upper step, and everything below 0.7 in one', () => {
    expect(psiStep(0.75)).toBe(2);
    expect(psiStep(0.7)).toBe(1);
    expect(psiStep(0.69)).toBe(0);
    expect(psiStep(0.1)).toBe(0);
    expect(psiStep(1)).toBe(kPsiSteps - 1);
    expect(psiStep(Number.NaN)).toBe(0);
  });
});

describe('evaluation metrics', () => {
  const metrics = {
    rpe: { used: 166, missing: 2818, trans_mean_m: 0.016973, trans_std_m: 0.010179, rot_mean_deg: 0.27115, rot_std_deg: 0.21046, trans_max_m: 0.0524, rot_max_deg: 0.93 },
    kl: { nats: 1.23456, cells: 12345 },
  };

  it('shows RPE as mean ± std, the relations used and KL, as numbers', () => {
    const rows = Object.fromEntries(evaluationRows(metrics).map((r) => [r.label, r.value]));
    expect(rows['RPE translation']).toBe('0.017 ± 0.010 m');
    expect(rows['RPE rotation']).toBe('0.27 ± 0.21 °');
    expect(rows['relations used']).toBe('166 (2,818 without a pose)');
    expect(rows['map KL']).toBe('1.235 nats');
    expect(evaluationSummary(metrics)).toBe('RPE 0.017 ± 0.010 m, 0.27 ± 0.21 ° · KL 1.235 nats');
  });

  it('shows nothing without metrics, and an error as text', () => {
    expect(evaluationRows({})).toEqual([]);
    expect(evaluationRows(null)).toEqual([]);
    expect(evaluationSummary({})).toBe('');
    expect(evaluationRows({ error: 'no file' })[0]).toMatchObject({ label: 'evaluation error', value: 'no file' });
  });
});

describe('fit', () => {
  it('covers the map and the predicted regions beyond it', () => {
    const store = new HypothesisStore();
    store.applySnapshot(snapshotMessage.hypotheses as unknown as Hypothesis[]);
    const id = [...store.entries.keys()][0];
    store.setCells(id, packCells([[300, 10, 0.95], [320, -40, 0.12]]));
    const box = fitBox({ minX: 0, minY: 0, maxX: 10, maxY: 5 }, predictedCellBox(store), 0.05, null)!;
    expect(box).toEqual({ minX: 0, minY: -2, maxX: 16.05, maxY: 5 });
  });

  it('falls back on the map alone, then on the robot', () => {
    expect(fitBox({ minX: 1, minY: 2, maxX: 3, maxY: 4 }, null, 0.05, { x: 0, y: 0 })).toEqual({ minX: 1, minY: 2, maxX: 3, maxY: 4 });
    expect(fitBox(null, null, 0.05, { x: 1, y: 1 })).toEqual({ minX: -4, minY: -4, maxX: 6, maxY: 6 });
    expect(fitBox(null, null, 0.05, null)).toBeNull();
  });
});

describe('times and hit ratios as shown', () => {
  it('shows an input time as time into the run (a simulator runs faster than the clock)', () => {
    expect(formatElapsed(1000 + 125, 1000)).toBe('2:05 into the run');
    expect(formatElapsed(1000 + 3725, 1000)).toBe('1:02:05 into the run');
    expect(formatElapsed(0, 1000)).toBe('–');
    expect(formatElapsed(1000, null)).toBe('–');
  });

  it('shows a hit ratio of 0 (no hit measured) as a dash, not as 0 %', () => {
    expect(formatHitRatio(0)).toBe('–');
    expect(formatHitRatio(0.734)).toBe('73 %');
  });
});
