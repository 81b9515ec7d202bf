// The pane's exploration banner: where exploration stands (EngineStats.exploration), with the
// mapped and the predicted share of the area, so an operator sees when the robot is done, waits for
// a choice, or is blocked. Hidden while the robot simply explores, and for a server that does not say.
import type { EngineStats } from '../net/protocol';
import { h } from './dom';

export interface ExplorationNotice {
  state: string;
  level: 'info' | 'done' | 'warn';
  text: string;
}

const kTitles: Record<string, [ExplorationNotice['level'], string]> = {
  verifying: ['info', 'Verifying predictions'],
  waiting_for_verification: ['warn', 'Waiting: only predicted regions are left'],
  complete: ['done', 'Exploration complete'],
  blocked: ['warn', 'Exploration blocked'],
};

// "412 m² mapped (93 %), 31 m² predicted (7 %)": shares of mapped + predicted.
export function areaText(st: EngineStats): string {
  const mapped = st.mapped_m2 ?? 0;
  const predicted = st.predicted_m2 ?? 0;
  const total = mapped + predicted;
  if (total <= 0) return '';
  const share = (v: number) => `${Math.round((100 * v) / total)} %`;
  return `${Math.round(mapped)} m² mapped (${share(mapped)}), ${Math.round(predicted)} m² predicted (${share(predicted)})`;
}

export function explorationNotice(st: EngineStats): ExplorationNotice | null {
  const state = st.exploration ?? '';
  const title = kTitles[state];
  if (!title) return null;
  const parts = [title[1], areaText(st), st.exploration_reason ?? ''].filter((p) => p !== '');
  return { state, level: title[0], text: parts.join(' · ') };
}

export class ExplorationBanner {
  readonly element = h('div', { class: 'exploration-banner', role: 'status', hidden: true });

  update(st: EngineStats): void {
    const notice = explorationNotice(st);
    this.element.hidden = notice === null;
    this.element.dataset.exploration = st.exploration ?? '';
    if (!notice) return;
    this.element.className = `exploration-banner ${notice.level}`;
    this.element.textContent = notice.text;
  }
}
