// Layer toggles with their legend, and the colouring of hypotheses (by Psi or by status).
import type { HypothesisColoring } from '../render/hypothesis_layer';
import { css, kStatusColors, viridis } from '../render/palette';
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

  private renderHypothesisLegend(): void {
    const el = this.hypothesisLegend;
    el.replaceChildren();
    if (this.coloring === 'psi') {
      el.append(h('span', {}, 'Ψ 0'), gradient(), h('span', {}, '1'));
    } else {
      for (const [status, color] of Object.entries(kStatusColors)) el.append(swatch(css(color)), `${status} `);
    }
  }
}
