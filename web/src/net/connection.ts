// The live WebSocket of one session: connects, reconnects with capped exponential backoff and
// jitter after any loss (a server restart, a network drop), and resubscribes simply by opening the
// socket again: the server answers every new subscriber with a full snapshot. Messages are decoded
// and checked here; invalid ones are reported, never thrown.
import { binaryKind, decodeLiveMessage, decodeParticleFrame, decodeScanFrame, type Decoded, type LiveMessage } from './protocol';

export type ConnectionState = 'connecting' | 'open' | 'reconnecting' | 'stopped' | 'failed';

export interface ConnectionHandlers {
  onMessage(message: LiveMessage): void;
  onTile(frame: ArrayBuffer): void;
  onInvalid(error: string): void;
  onState(state: ConnectionState, detail: string): void;
}

export interface ConnectionCounters {
  messages: number;
  tiles: number;
  bytes: number;
  invalid: number;
  reconnects: number;
}

export const kBackoffInitialMs = 500;
export const kBackoffMaxMs = 10000;

// The delay before reconnect attempt 'attempt' (0-based): doubling from 0.5 s, at most 10 s,
// with +-20 % jitter so that many viewers do not return at the same instant.
export function backoffDelay(attempt: number, random: () => number = Math.random): number {
  const base = Math.min(kBackoffMaxMs, kBackoffInitialMs * 2 ** Math.min(attempt, 20));
  return Math.round(base * (0.8 + 0.4 * random()));
}

type SocketFactory = (url: string) => WebSocket;

export class LiveConnection {
  state: ConnectionState = 'stopped';
  readonly counters: ConnectionCounters = { messages: 0, tiles: 0, bytes: 0, invalid: 0, reconnects: 0 };
  private socket: WebSocket | null = null;
  private attempt = 0;
  private timer: ReturnType<typeof setTimeout> | null = null;
  private stopped = true;
  private hadOpen = false;

  constructor(
    private readonly url: () => string,
    private readonly handlers: ConnectionHandlers,
    private readonly makeSocket: SocketFactory = (u) => new WebSocket(u),
  ) {}

  start(): void {
    this.stopped = false;
    this.attempt = 0;
    this.open();
  }

  stop(): void {
    this.stopped = true;
    if (this.timer) clearTimeout(this.timer);
    this.timer = null;
    const s = this.socket;
    this.socket = null;
    if (s) {
      s.onopen = s.onclose = s.onerror = s.onmessage = null;
      s.close(1000, 'viewer closed');
    }
    this.setState('stopped', '');
  }

  // Closes the socket and opens a new one at once (for a fresh snapshot).
  restart(): void {
    if (this.stopped) return;
    const s = this.socket;
    this.socket = null;
    if (s) {
      s.onopen = s.onclose = s.onerror = s.onmessage = null;
      s.close(1000, 'resubscribing');
    }
    if (this.timer) clearTimeout(this.timer);
    this.timer = null;
    this.open();
  }

  // Reconnects now (the user pressed "retry", or the page became visible).
  reconnectNow(): void {
    if (this.stopped || this.state === 'open' || this.state === 'connecting') return;
    if (this.timer) clearTimeout(this.timer);
    this.timer = null;
    this.open();
  }

  private open(): void {
    this.setState(this.hadOpen ? 'reconnecting' : 'connecting', this.hadOpen ? 'resubscribing' : '');
    let s: WebSocket;
    try {
      s = this.makeSocket(this.url());
    } catch (e) {
      this.scheduleReconnect(`cannot open: ${(e as Error).message}`);
      return;
    }
    s.binaryType = 'arraybuffer';
    this.socket = s;
    s.onopen = () => {
      this.hadOpen = true;
      this.setState('open', '');
    };
    s.onmessage = (ev: MessageEvent) => this.receive(ev.data);
    s.onerror = () => {
      /* a close event follows with the details */
    };
    s.onclose = (ev: CloseEvent) => {
      if (this.socket !== s) return;
      this.socket = null;
      if (this.stopped) return;
      // 1008: the server refused (unknown session or a token it does not accept): retrying will
      // not help until the user does something.
      if (ev.code === 1008) {
        this.setState('failed', ev.reason || 'refused by the server');
        return;
      }
      this.scheduleReconnect(ev.reason || (ev.code === 1006 ? 'connection lost' : `closed (${ev.code})`));
    };
  }

  private receive(data: unknown): void {
    // Any message proves the link works: the next loss starts the backoff from the beginning.
    this.attempt = 0;
    if (data instanceof ArrayBuffer) {
      this.counters.bytes += data.byteLength;
      const kind = binaryKind(data);
      if (kind === 'tile') {
        this.counters.tiles++;
        this.handlers.onTile(data);
        return;
      }
      this.counters.messages++;
      if (kind === 'unknown') return this.invalid('a binary frame of unknown kind');
      this.deliver(kind === 'scan' ? decodeScanFrame(data) : decodeParticleFrame(data));
      return;
    }
    if (typeof data !== 'string') return;
    this.counters.messages++;
    this.counters.bytes += data.length;
    let raw: unknown;
    try {
      raw = JSON.parse(data);
    } catch {
      this.invalid('a message that is not JSON');
      return;
    }
    this.deliver(decodeLiveMessage(raw));
  }

  private invalid(error: string): void {
    this.counters.invalid++;
    this.handlers.onInvalid(error);
  }

  private deliver(decoded: Decoded<LiveMessage>): void {
    if (decoded.ok) this.handlers.onMessage(decoded.value);
    else this.invalid(decoded.error);
  }

  private scheduleReconnect(reason: string): void {
    const delay = backoffDelay(this.attempt++);
    this.counters.reconnects++;
    this.setState('reconnecting', `${reason}; retrying in ${(delay / 1000).toFixed(1)} s`);
    this.timer = setTimeout(() => {
      this.timer = null;
      if (!this.stopped) this.open();
    }, delay);
  }

  private setState(state: ConnectionState, detail: string): void {
    this.state = state;
    this.handlers.onState(state, detail);
  }
}
