// The REST API of pslam-server (schema/openapi.yaml): thin typed wrappers over fetch. Errors come
// back as ApiError with the server's code and message.

export interface SessionInfo {
  id: string;
  name: string;
  robot_id: string;
  source: string;
  status: string;
  created_at: number;
  updated_at: number;
  closed_at: number | null;
  laser: Record<string, unknown>;
  settings: Record<string, unknown> & { particles?: number; predict?: boolean; seed?: number; resolution_meters?: number };
  last_seq: number;
  processed_seq: number;
  scans: number;
  metrics: Record<string, unknown>;
  replay_of: string | null;
  failure?: string | null; // why a failed session failed
  running: boolean;
}

export interface SessionStatistics {
  session_id: string;
  status: string;
  running: boolean;
  filter: Record<string, number | boolean>;
  ingest: { received_seq: number; acked_seq: number };
  // Counts by status and mean_hit_ratio; the statuses are the predictor's (see hypothesis_store).
  predictions: Record<string, number>;
  metrics: Record<string, unknown>;
}

export interface ReplayRequest {
  session?: string;
  log?: string;
  relations?: string;
  reference_map?: string;
  name?: string;
  speed?: number;
  settings?: Record<string, unknown>;
}

export class ApiError extends Error {
  constructor(
    readonly status: number,
    readonly code: string,
    message: string,
  ) {
    super(message);
  }
}

// A hypothesis is streamed live before the server's next checkpoint stores it, so reading it over
// REST may answer 404 for a moment; so may a server that is restarting (0) or failing (5xx).
export function mayAppearLater(e: unknown): boolean {
  return e instanceof ApiError && (e.status === 404 || e.status === 0 || e.status >= 500);
}

const kTokenKey = 'pslam.token';

// The viewer token: from ?token= on the page URL (then remembered for the tab), else none.
export function currentToken(): string | null {
  const fromUrl = new URLSearchParams(location.search).get('token');
  if (fromUrl) {
    sessionStorage.setItem(kTokenKey, fromUrl);
    return fromUrl;
  }
  return sessionStorage.getItem(kTokenKey);
}

export function setToken(token: string | null): void {
  if (token) sessionStorage.setItem(kTokenKey, token);
  else sessionStorage.removeItem(kTokenKey);
}

export function apiUrl(path: string): string {
  return new URL(path, location.origin).toString();
}

// The live WebSocket URL of a session, with the token as a query parameter (browsers cannot set
// headers on a WebSocket upgrade).
export function liveUrl(sessionId: string): string {
  const u = new URL(`/api/sessions/${encodeURIComponent(sessionId)}/live`, location.origin);
  u.protocol = location.protocol === 'https:' ? 'wss:' : 'ws:';
  const token = currentToken();
  if (token) u.searchParams.set('token', token);
  return u.toString();
}

async function request<T>(method: string, path: string, body?: unknown, signal?: AbortSignal): Promise<T> {
  const headers: Record<string, string> = { Accept: 'application/json' };
  const token = currentToken();
  if (token) headers.Authorization = `Bearer ${token}`;
  if (body !== undefined) headers['Content-Type'] = 'application/json';
  let res: Response;
  try {
    res = await fetch(apiUrl(path), { method, headers, body: body === undefined ? undefined : JSON.stringify(body), signal });
  } catch (e) {
    if ((e as Error).name === 'AbortError') throw e;
    throw new ApiError(0, 'network', 'the server is not reachable');
  }
  if (res.status === 204) return undefined as T;
  const text = await res.text();
  let json: unknown = null;
  try {
    json = text ? JSON.parse(text) : null;
  } catch {
    throw new ApiError(res.status, 'bad_response', `${method} ${path}: not JSON (HTTP ${res.status})`);
  }
  if (!res.ok) {
    const err = (json as { error?: { code?: string; message?: string } } | null)?.error;
    throw new ApiError(res.status, err?.code ?? 'http_error', err?.message ?? `HTTP ${res.status}`);
  }
  return json as T;
}

// Downloads a binary resource (exports) with the token.
export async function fetchBlob(path: string): Promise<Blob> {
  const headers: Record<string, string> = {};
  const token = currentToken();
  if (token) headers.Authorization = `Bearer ${token}`;
  const res = await fetch(apiUrl(path), { headers });
  if (!res.ok) throw new ApiError(res.status, 'http_error', `${path}: HTTP ${res.status}`);
  return res.blob();
}

const sid = (id: string) => encodeURIComponent(id);

// A file of the server's replay directory (GET /api/replays/files), named as a replay request names it.
export interface ReplayFile {
  name: string;
  bytes: number;
  kind: 'log' | 'relations' | 'reference_map';
}

// A site (a building, a floor) and one of its map versions (GET /api/sites, /api/sites/{id}/maps).
export interface Site {
  id: string;
  name: string;
  created_at?: number;
  versions?: number;
  latest_version?: number | null;
}

export interface SiteMap {
  site_id: string;
  version: number;
  created_at?: number;
  source?: 'session' | 'import';
  session_id?: string | null;
  note?: string;
  resolution?: number;
  image?: { width?: number; height?: number; origin?: number[] };
}

export const siteMapFileUrl = (site: string, version: number, file: 'map.pgm' | 'map.yaml') =>
  `/api/sites/${sid(site)}/maps/${version}/${file}`;

export const api = {
  health: () => request<{ status: string; running_sessions: number; viewers: number; agents: number }>('GET', '/api/health'),
  version: () => request<{ server: string; version: string; live_protocol: number }>('GET', '/api/version'),
  sessions: (limit = 200) =>
    request<{ sessions: SessionInfo[]; total: number }>('GET', `/api/sessions?limit=${limit}`),
  session: (id: string) => request<SessionInfo>('GET', `/api/sessions/${sid(id)}`),
  stats: (id: string) => request<SessionStatistics>('GET', `/api/sessions/${sid(id)}/stats`),
  hypothesis: (id: string, hid: number, signal?: AbortSignal) =>
    request<{ id: number; cells: [number, number, number][] }>('GET', `/api/sessions/${sid(id)}/hypotheses/${hid}`, undefined, signal),
  hypotheses: (id: string, limit: number, offset: number) =>
    request<{ hypotheses: Record<string, unknown>[]; total: number }>('GET', `/api/sessions/${sid(id)}/hypotheses?limit=${limit}&offset=${offset}`),
  startReplay: (body: ReplayRequest) => request<SessionInfo>('POST', '/api/replays', body),
  replayFiles: () => request<{ files: ReplayFile[] }>('GET', '/api/replays/files'),
  closeSession: (id: string) => request<SessionInfo>('POST', `/api/sessions/${sid(id)}/close`),
  setInitialPose: (id: string, pose: { x: number; y: number; theta: number }) =>
    request<{ session_id: string; initial_pose: Record<string, number> }>('POST', `/api/sessions/${sid(id)}/initial_pose`, pose),
  sites: (limit = 200) => request<{ sites: Site[]; total: number }>('GET', `/api/sites?limit=${limit}`),
  siteMaps: (site: string) => request<{ site_id: string; maps: SiteMap[] }>('GET', `/api/sites/${sid(site)}/maps`),
};
