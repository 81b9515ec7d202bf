// Starts a replay on the server (POST /api/replays): a stored session or a CARMEN log from the
// server's replay directory, at a chosen speed and with chosen filter settings. Optionally starts
// the same data twice, without and with prediction (plain RBPF vs P-SLAM), to compare side by side.
import { api, ApiError, type ReplayFile, type ReplayRequest, type SessionInfo } from '../net/api';
import { h } from './dom';

export const kSpeeds: [string, number][] = [
  ['as fast as possible', 0],
  ['1× real time', 1],
  ['2×', 2],
  ['5×', 5],
  ['10×', 10],
  ['50×', 50],
];

export interface ReplayForm {
  source: 'session' | 'log';
  session: string;
  log: string;
  relations: string;
  referenceMap: string;
  name: string;
  speed: number;
  particles: number | null;
  predict: boolean;
  seed: number | null;
  resolution: number | null;
}

// The request body for a form; 'predict' overrides the form's setting (for the comparison pair).
export function replayRequest(f: ReplayForm, predict = f.predict): ReplayRequest {
  const settings: Record<string, unknown> = { predict };
  if (f.particles !== null) settings.particles = f.particles;
  if (f.seed !== null) settings.seed = f.seed;
  if (f.resolution !== null) settings.resolution_meters = f.resolution;
  const body: ReplayRequest = { speed: f.speed, settings };
  if (f.source === 'session') body.session = f.session;
  else {
    body.log = f.log;
    if (f.relations) body.relations = f.relations;
    if (f.referenceMap) body.reference_map = f.referenceMap;
  }
  if (f.name) body.name = f.name;
  return body;
}

// "intel/intel.clf (14.2 MB)"
export function fileLabel(f: ReplayFile): string {
  const mb = f.bytes / (1024 * 1024);
  const size = mb >= 1 ? `${mb.toFixed(1)} MB` : `${Math.max(1, Math.round(f.bytes / 1024))} KB`;
  return `${f.name} (${size})`;
}

// Options for one kind of file; optional kinds start with "none".
export function fileOptions(files: ReplayFile[], kind: ReplayFile['kind'], none: string | null): HTMLOptionElement[] {
  const options = files.filter((f) => f.kind === kind).map((f) => h('option', { value: f.name }, fileLabel(f)));
  return none === null ? options : [h('option', { value: '' }, none), ...options];
}

export class ReplayDialog {
  readonly element: HTMLDialogElement;
  private readonly sessionSelect: HTMLSelectElement;
  private readonly logSelect: HTMLSelectElement;
  private readonly relationsSelect: HTMLSelectElement;
  private readonly referenceSelect: HTMLSelectElement;
  private readonly filesNote: HTMLElement;
  private readonly error: HTMLElement;
  private readonly form: HTMLFormElement;

  constructor(private readonly onStarted: (sessions: SessionInfo[]) => void) {
    this.sessionSelect = h('select', { name: 'session' });
    // The server's replay directory, listed when the dialog opens: names exactly as a request gives them.
    this.logSelect = h('select', { name: 'log', 'aria-label': 'log file' });
    this.relationsSelect = h('select', { name: 'relations', 'aria-label': 'relations file for RPE' });
    this.referenceSelect = h('select', { name: 'reference_map', 'aria-label': 'reference map for KL' });
    this.filesNote = h('small', { class: 'files-note' });
    this.error = h('div', { class: 'form-error', role: 'alert' });
    const field = (label: string, input: HTMLElement, hint = '') =>
      h('label', { class: 'field' }, h('span', {}, label), input, hint ? h('small', {}, hint) : null);
    this.form = h(
      'form',
      { method: 'dialog', onsubmit: (e: Event) => this.submit(e) },
      h('h2', {}, 'Start a replay'),
      h(
        'fieldset',
        { class: 'source' },
        h('legend', {}, 'Data'),
        h('label', { class: 'radio' }, h('input', { type: 'radio', name: 'source', value: 'session', checked: true }), 'Stored session'),
        this.sessionSelect,
        h('label', { class: 'radio' }, h('input', { type: 'radio', name: 'source', value: 'log' }), 'Log on the server'),
        this.logSelect,
        this.relationsSelect,
        this.referenceSelect,
        this.filesNote,
      ),
      h(
        'fieldset',
        {},
        h('legend', {}, 'Settings'),
        field('Name', h('input', { name: 'name', placeholder: 'replay of …' })),
        field('Speed', h('select', { name: 'speed' }, ...kSpeeds.map(([label, v]) => h('option', { value: String(v) }, label)))),
        field('Particles', h('input', { name: 'particles', type: 'number', min: 1, max: 1000, placeholder: 'server default' })),
        field('Seed', h('input', { name: 'seed', type: 'number', min: 0, placeholder: 'server default' })),
        field('Resolution (m)', h('input', { name: 'resolution', type: 'number', min: 0.01, max: 1, step: 0.01, placeholder: '0.05' })),
        h('label', { class: 'check' }, h('input', { type: 'checkbox', name: 'predict', checked: true }), 'Structure prediction (P-SLAM)'),
        h('label', { class: 'check' }, h('input', { type: 'checkbox', name: 'compare' }), 'Also run the other setting and compare side by side (RBPF vs P-SLAM)'),
      ),
      this.error,
      h(
        'div',
        { class: 'dialog-buttons' },
        h('button', { type: 'button', onclick: () => this.element.close() }, 'Cancel'),
        h('button', { type: 'submit', class: 'primary', 'data-action': 'start-replay' }, 'Start replay'),
      ),
    );
    this.element = h('dialog', { class: 'replay-dialog' }, this.form);
  }

  open(sessions: SessionInfo[], preselect?: string): void {
    this.error.textContent = '';
    const stored = sessions.filter((s) => s.scans > 0 || s.last_seq > 0);
    this.sessionSelect.replaceChildren(
      ...stored.map((s) => h('option', { value: s.id, selected: s.id === preselect }, `${s.name || s.id} (${s.scans} scans, ${s.status})`)),
    );
    if (stored.length === 0) (this.form.elements.namedItem('source') as RadioNodeList).value = 'log';
    else (this.form.elements.namedItem('source') as RadioNodeList).value = 'session';
    void this.listFiles();
    this.element.showModal();
  }

  private async listFiles(): Promise<void> {
    this.filesNote.textContent = 'Listing the server’s replay directory…';
    let files: ReplayFile[] = [];
    try {
      files = (await api.replayFiles()).files;
      const logs = files.filter((f) => f.kind === 'log').length;
      this.filesNote.textContent = logs ? '' : 'The server’s replay directory holds no logs (.clf, .log).';
    } catch (err) {
      // 403: the server was started without --replay-dir.
      this.filesNote.textContent = (err as ApiError).message;
    }
    this.logSelect.replaceChildren(...fileOptions(files, 'log', null));
    this.relationsSelect.replaceChildren(...fileOptions(files, 'relations', 'no relations file (no RPE)'));
    this.referenceSelect.replaceChildren(...fileOptions(files, 'reference_map', 'no reference map (no KL)'));
    // The relations file beside the chosen log, when there is one (intel/intel.clf -> intel/intel.relations).
    const pickRelations = () => {
      const stem = this.logSelect.value.replace(/\.[^./]*$/, '');
      const match = files.find((f) => f.kind === 'relations' && f.name === `${stem}.relations`);
      this.relationsSelect.value = match ? match.name : '';
    };
    this.logSelect.onchange = pickRelations;
    pickRelations();
  }

  read(): ReplayForm {
    const el = this.form.elements;
    const value = (name: string) => ((el.namedItem(name) as HTMLInputElement | null)?.value ?? '').trim();
    const number = (name: string) => (value(name) === '' ? null : Number(value(name)));
    return {
      source: (el.namedItem('source') as RadioNodeList).value === 'log' ? 'log' : 'session',
      session: this.sessionSelect.value,
      log: value('log'),
      relations: value('relations'),
      referenceMap: value('reference_map'),
      name: value('name'),
      speed: Number(value('speed') || 0),
      particles: number('particles'),
      seed: number('seed'),
      resolution: number('resolution'),
      predict: (el.namedItem('predict') as HTMLInputElement).checked,
    };
  }

  private async submit(e: Event): Promise<void> {
    e.preventDefault();
    const f = this.read();
    const compare = (this.form.elements.namedItem('compare') as HTMLInputElement).checked;
    if (f.source === 'session' && !f.session) return this.fail('Choose a stored session.');
    if (f.source === 'log' && !f.log) return this.fail('Choose a log from the server’s replay directory.');
    this.error.textContent = 'Starting…';
    try {
      const started: SessionInfo[] = [];
      if (compare) {
        // Plain RBPF on the left, P-SLAM on the right, same data and seed.
        const base = { ...f, name: f.name };
        started.push(await api.startReplay(replayRequest({ ...base, name: base.name ? `${base.name} (RBPF)` : '' }, false)));
        started.push(await api.startReplay(replayRequest({ ...base, name: base.name ? `${base.name} (P-SLAM)` : '' }, true)));
      } else {
        started.push(await api.startReplay(replayRequest(f)));
      }
      this.element.close();
      this.onStarted(started);
    } catch (err) {
      this.fail((err as ApiError).message);
    }
  }

  private fail(message: string): void {
    this.error.textContent = message;
  }
}
