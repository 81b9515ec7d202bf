// Layer toggles with their legend, and the colouring of hypotheses (by Psi or by status).
import type { HypothesisColoring } from '../render/hypothesis_layer';
import { cellAlpha } from '../render/hypothesis_layer';
import { css, kPsiSteps, kStatusColors, psiColor, psiStepLabel, viridis } from '../render/palette';
import { h } from './dom';
import { kLayerIds, type LayerId } from './session_view';

const kLayerInfo: Record<LayerId, { label: string; legend: () => HTMLElement }> = {
  map: {
    label: 'Built map',
    legend: () =>
      h('span', { class: 'legend' }, swatch('rgb(226,230,236)'), 'free ', swatch('rgb(6,8,12)', 'border'), 'occupied ', swatch('#2a2e37', 'border'), 'unknown'),
  },
  hypotheses: { label: 'Predicted structure', legend: () => h('span', { class: 'legend' }) },
  exploration: {
    label: 'Frontiers, target, path',
    legend: () => h('span', { class: 'legend' }, swatch('rgb(0,220,255)', 'dot'), 'frontier ', swatch('rgb(236,72,255)'), 'target & path'),
  },
  trajectory: { label: 'Trajectory', legend: () => h('span', { class: 'legend' }, swatch('rgb(255,196,0)', 'line'), 'estimated path') },
  particles: { label: 'Particle cloud', legend: () => h('span', { class: 'legend' }, gradient(), 'by weight') },
  scan: { label: 'Laser scan', legend: () => h('span', { class: 'legend' }, swatch('rgb(255,60,60)', 'dot'), 'returns') },
  robot: { label: 'Robot & footprint', legend: () => h('span', { class: 'legend' }, swatch('rgba(255,92,64,0.6)'), 'Pioneer 3-DX') },
};

function swatch(color: string, kind = ''): HTMLElement {
  return h('i', { class: `swatch ${kind}`, style: { background: color } });
}

function gradient(): HTMLElement {
  const stops = [0, 0.25, 0.5, 0.75, 1].map((t) => css(viridis(t))).join(',');
  return h('i', { class: 'swatch gradient', style: { background: `linear-gradient(90deg, ${stops})` } });
}

export class LayerPanel {
  readonly element: HTMLElement;
  private readonly hypothesisLegend: HTMLElement;

  constructor(
    visibility: Record<string, boolean>,
    private coloring: HypothesisColoring,
    private readonly onToggle: (id: LayerId, visible: boolean) => void,
    private readonly onColoring: (c: HypothesisColoring) => void,
  ) {
    this.hypothesisLegend = h('div', { class: 'legend hypothesis-legend' });
    const rows = kLayerIds.map((id) => {
      const info = kLayerInfo[id];
      const input = h('input', {
        type: 'checkbox',
        checked: visibility[id] !== false,
        'data-layer': id,
        onchange: (e: Event) => this.onToggle(id, (e.target as HTMLInputElement).checked),
      });
      const legend = id === 'hypotheses' ? this.hypothesisLegend : info.legend();
      return h('label', { class: 'layer-row' }, input, h('span', { class: 'layer-name' }, info.label), legend);
    });
    const coloringSelect = h(
      'select',
      {
        'data-control': 'hypothesis-coloring',
        onchange: (e: Event) => {
          this.coloring = (e.target as HTMLSelectElement).value as HypothesisColoring;
          this.renderHypothesisLegend();
          this.onColoring(this.coloring);
        },
      },
      h('option', { value: 'psi', selected: coloring === 'psi' }, 'Colour predictions by Ψ'),
      h('option', { value: 'status', selected: coloring === 'status' }, 'Colour predictions by status'),
    );
    this.element = h('div', { class: 'layer-panel' }, ...rows, coloringSelect);
    this.renderHypothesisLegend();
  }

  // What each mark of a prediction means, then the colour scale in use.
  private renderHypothesisLegend(): void {
    const el = this.hypothesisLegend;
    const sample = psiColor(0.9);
    const marks = h(
      'div',
      { class: 'legend', 'data-legend': 'prediction-marks' },
      swatch(css(sample, cellAlpha(true, false) / 255), 'border'),
      'predicted wall ',
      swatch(css(sample, cellAlpha(false, false) / 255), 'border'),
      'predicted free ',
      h('i', { class: 'swatch diamond', style: { background: css(sample) } }),
      'target (click to select) ',
      swatch(css(sample, cellAlpha(true, true) / 255), 'border'),
      'faint: refuted or expired',
    );
    let scale: HTMLElement;
    if (this.coloring === 'psi') {
      scale = h(
        'div',
        { class: 'legend psi-scale', 'data-legend': 'psi', title: 'Ψ: similarity of the registration the prediction was copied from (eq. 5), in steps of 0.05' },
        h('span', {}, 'Ψ'),
        ...Array.from({ length: kPsiSteps }, (_, i) =>
          h('span', { class: 'psi-step' }, h('i', { class: 'swatch', style: { background: css(psiColor(i === 0 ? 0 : 0.7 + (i - 1) * 0.05 + 0.01)) } }), psiStepLabel(i)),
        ),
      );
    } else {
      scale = h('div', { class: 'legend', 'data-legend': 'status' }, ...Object.entries(kStatusColors).flatMap(([status, color]) => [swatch(css(color)), `${status} `]));
    }
    el.replaceChildren(marks, scale);
  }
}
