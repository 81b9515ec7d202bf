// One session seen live: the socket, the stores it feeds, and the REST look-ups the live stream
// leaves out (the cells of each hypothesis). No DOM: views subscribe through onChange.
import { api, liveUrl, mayAppearLater } from './api';
import { LiveConnection, type ConnectionState } from './connection';
import { decodeTileFrame, type LiveMessage } from './protocol';
import { HypothesisStore, packCells } from '../state/hypothesis_store';
import { MapStore } from '../state/map_store';
import { RobotStore } from '../state/robot_store';
import { StatsStore } from '../state/stats_store';

const kMaxErrors = 20;
// Messages held while paused; beyond this the backlog is dropped and a fresh snapshot is asked
// for on resume (by reconnecting), so a long pause costs bounded memory.
const kMaxPausedMessages = 20000;
const kCellFetchConcurrency = 3;
// Cells not readable yet (see mayAppearLater): retry a few times, 1 s, 2 s, 4 s ... apart.
const kCellFetchAttempts = 6;
const kCellRetryMs = 1000;

export interface ClientEvent {
  kind: 'snapshot' | 'tile' | 'state' | 'robot' | 'hypotheses' | 'stats' | 'status' | 'error';
}

export class SessionClient {
  readonly map = new MapStore();
  readonly robot = new RobotStore();
  readonly hypotheses = new HypothesisStore();
  readonly stats = new StatsStore();
  status = 'unknown';
  connectionState: ConnectionState = 'stopped';
  connectionDetail = '';
  snapshots = 0;
  readonly errors: { time: number; message: string }[] = [];
  // Decode + store time of recent tiles, milliseconds.
  readonly tileTimes: number[] = [];
  private readonly connection: LiveConnection;
  private scratch = new Uint8Array(64 * 64);
  private stopped = false;
  private cellFetches = 0;
  private readonly cellAttempts = new Map<number, number>();
  private readonly retryTimers = new Set<ReturnType<typeof setTimeout>>();
  private abort = new AbortController();
  private readonly listeners = new Set<(e: ClientEvent) => void>();
  private paused = false;
  private backlog: ({ text: LiveMessage } | { tile: ArrayBuffer | Uint8Array })[] = [];
  private backlogOverflow = false;

  // 'fetchCells': look up the cells of new hypotheses over REST (off for offline fixtures).
  constructor(
    readonly sessionId: string,
    now: () => number = () => Date.now() / 1000,
    private readonly fetchCells = true,
  ) {
    this.now = now;
    this.connection = new LiveConnection(() => liveUrl(sessionId), {
      onMessage: (m) => (this.paused ? this.hold({ text: m }) : this.handle(m)),
      onTile: (frame) => (this.paused ? this.hold({ tile: frame }) : this.handleTile(frame)),
      onInvalid: (e) => this.error(`invalid message: ${e}`),
      onState: (state, detail) => {
        this.connectionState = state;
        this.connectionDetail = detail;
        this.emit({ kind: 'state' });
      },
    });
  }

  private readonly now: () => number;

  get counters() {
    return this.connection.counters;
  }

  subscribe(listener: (e: ClientEvent) => void): () => void {
    this.listeners.add(listener);
    return () => this.listeners.delete(listener);
  }

  start(): void {
    this.stopped = false;
    this.connection.start();
  }

  stop(): void {
    this.stopped = true;
    for (const t of this.retryTimers) clearTimeout(t);
    this.retryTimers.clear();
    this.connection.stop();
    this.abort.abort();
    this.abort = new AbortController();
    this.listeners.clear();
  }

  reconnectNow(): void {
    this.connection.reconnectNow();
  }

  get isPaused(): boolean {
    return this.paused;
  }

  // Freezes the stores at this instant: what arrives is held, in order, and applied on resume.
  pause(): void {
    this.paused = true;
  }

  resume(): void {
    if (!this.paused) return;
    this.paused = false;
    const backlog = this.backlog;
    this.backlog = [];
    if (this.backlogOverflow) {
      this.backlogOverflow = false;
      // Too much was missed to replay: start over from a snapshot.
      this.connection.restart();
      return;
    }
    for (const m of backlog) {
      if ('text' in m) this.handle(m.text);
      else this.handleTile(m.tile);
    }
  }

  // Messages held while paused (for the UI).
  get held(): number {
    return this.backlog.length;
  }

  private hold(m: { text: LiveMessage } | { tile: ArrayBuffer | Uint8Array }): void {
    if (this.backlogOverflow) return;
    // A new snapshot supersedes everything held before it.
    if ('text' in m && m.text.type === 'snapshot') this.backlog = [];
    this.backlog.push(m);
    if (this.backlog.length > kMaxPausedMessages) {
      this.backlog = [];
      this.backlogOverflow = true;
    }
  }

  // Applies one message to the stores. Public so tests and the benchmark can feed messages.
  handle(m: LiveMessage): void {
    switch (m.type) {
      case 'snapshot':
        this.snapshots++;
        this.status = m.status;
        this.map.applySnapshot(m.resolution, m.tile_size, m.tile_count);
        this.robot.applySnapshot(m);
        this.hypotheses.applySnapshot(m.hypotheses);
        this.stats.markGap(this.now());
        this.stats.setLatest(m.stats);
        this.fetchMissingCells();
        this.emit({ kind: 'snapshot' });
        return;
      case 'pose':
        this.robot.applyPose(m);
        break;
      case 'trajectory':
        this.robot.applyTrajectory(m.first_index, m.poses);
        break;
      case 'particles':
        this.robot.applyParticles(m.poses);
        break;
      case 'exploration':
        this.robot.applyExploration(m.frontiers, m.target);
        break;
      case 'scan':
        this.robot.applyScan(m);
        break;
      case 'stats':
        this.stats.add(this.now(), m.stats, this.hypotheses.entries.size);
        this.emit({ kind: 'stats' });
        return;
      case 'hypothesis':
        this.hypotheses.applyEvent(m.event, m.hypothesis);
        if (m.event === 'added') this.fetchMissingCells();
        this.emit({ kind: 'hypotheses' });
        return;
      case 'session':
        this.status = m.status;
        this.emit({ kind: 'status' });
        return;
      case 'error':
        this.error(`${m.code}: ${m.message}`);
        return;
    }
    this.emit({ kind: 'robot' });
  }

  handleTile(frame: ArrayBuffer | Uint8Array): void {
    const start = performance.now();
    const size = this.map.tileSize;
    if (this.scratch.length !== size * size) this.scratch = new Uint8Array(size * size);
    const tile = decodeTileFrame(frame, this.scratch);
    if (!tile.ok) {
      this.error(tile.error);
      return;
    }
    const problem = this.map.applyTile(tile.value);
    if (problem) {
      this.error(problem);
      return;
    }
    this.tileTimes.push(performance.now() - start);
    if (this.tileTimes.length > 500) this.tileTimes.splice(0, 250);
    this.emit({ kind: 'tile' });
  }

  private fetchMissingCells(): void {
    if (this.stopped || !this.fetchCells) return;
    const missing = this.hypotheses.missingCells();
    // Newest first: the operator looks at what was just predicted.
    missing.sort((a, b) => b - a);
    for (const id of missing) {
      if (this.cellFetches >= kCellFetchConcurrency) return;
      this.hypotheses.markLoading(id);
      this.cellFetches++;
      api
        .hypothesis(this.sessionId, id, this.abort.signal)
        .then((h) => this.hypotheses.setCells(id, packCells(Array.isArray(h.cells) ? h.cells : [])))
        .catch((e: Error) => {
          if (e.name === 'AbortError') return;
          const attempts = (this.cellAttempts.get(id) ?? 0) + 1;
          this.cellAttempts.set(id, attempts);
          const retry = mayAppearLater(e) && attempts < kCellFetchAttempts;
          if (retry) {
            this.hypotheses.markRetry(id, true);
            const timer = setTimeout(() => {
              this.retryTimers.delete(timer);
              this.hypotheses.markRetry(id, false);
              this.fetchMissingCells();
            }, kCellRetryMs * 2 ** (attempts - 1));
            this.retryTimers.add(timer);
            return;
          }
          this.hypotheses.setCells(id, null);
          this.error(`hypothesis ${id}: ${e.message}`);
        })
        .finally(() => {
          this.cellFetches--;
          this.emit({ kind: 'hypotheses' });
          this.fetchMissingCells();
        });
    }
  }

  private error(message: string): void {
    this.errors.push({ time: Date.now(), message });
    if (this.errors.length > kMaxErrors) this.errors.shift();
    this.emit({ kind: 'error' });
  }

  private emit(e: ClientEvent): void {
    for (const l of this.listeners) l(e);
  }
}
