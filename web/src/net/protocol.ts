// The live view protocol of pslam-server (schema/ws/live.md), version 1: JSON text messages for
// state and binary frames for the map tiles, the laser scan and the particles. Everything that arrives is checked here, at the
// boundary; a message that fails is reported as a value (shown in the UI), never thrown.
import { unzlibSync } from 'fflate';

export type Pose = { x: number; y: number; theta: number };
export type XY = [number, number];
// [x, y, theta, t]: a trajectory pose, metres, radians, Unix seconds.
export type TrajectoryPose = [number, number, number, number];
// [x, y, theta, weight]
export type ParticlePose = [number, number, number, number];

// A structure prediction as the server describes it (without its cells, which come from REST).
export interface Hypothesis {
  id: number;
  time: number;
  target_cell: XY;
  reference_cell: XY;
  // The site map the reference came from; absent or null: the session's own map.
  reference_map?: { site: string; version: number } | null;
  theta: number;
  translation: XY;
  psi: number;
  area: number;
  cell_count: number;
  status: string;
  hit_ratio: number;
  psi_observed: number | null;
}

export interface ExplorationTarget {
  x: number;
  y: number;
  path: XY[];
  pose: Pose | null;
}

// Engine statistics (EngineStatsToJson); every field optional so an older or newer server works.
export interface EngineStats {
  processed_seq?: number;
  scans?: number;
  updates?: number;
  resamplings?: number;
  particles?: number;
  neff?: number;
  scan_rate_hz?: number;
  latency_ms_mean?: number;
  latency_ms_max?: number;
  step_ms_mean?: number;
  queued?: number;
  rebuilding?: boolean;
  // Whether the filter looks lost: 'ok', 'degraded' or 'lost', and why when not ok.
  tracking?: string;
  tracking_reason?: string;
  // P-SLAM
  targets?: number;
  predictions_made?: number;
  hypotheses?: number;
  prediction_ms_mean?: number;
  prediction_ms_max?: number;
  updates_using_predictions?: number;
  // Exploration (sessions with a robot): 'exploring', 'verifying', 'waiting_for_verification',
  // 'complete' or 'blocked' ('' before the first plan), why, and the areas mapped and predicted.
  exploration?: string;
  exploration_reason?: string;
  mapped_m2?: number;
  predicted_m2?: number;
  predicted_frontiers?: number;
  // 'map', 'localize', or an extend session's phase: 'extend_localize' then 'extend_map'; while
  // localizing, whether the robot is localized on the site's map.
  mode?: string;
  localization?: LocalizationStats;
}

// The heaviest particle cluster of a localize session and its spread (localized: at least 80 %
// of the weight within 0.15 m and 5 degrees).
export interface LocalizationStats {
  localized?: boolean;
  cluster_weight?: number;
  position_std_m?: number;
  heading_std_rad?: number;
  clusters?: number;
  injected?: number;
  // Global localization: 'searching' the map for the place, 'look_alike' while another place
  // explains the last metres as well; empty once tracking.
  place?: string;
}

export interface SnapshotMessage {
  type: 'snapshot';
  session_id: string;
  status: string;
  resolution: number;
  tile_size: number;
  tile_count: number;
  pose: Pose | null;
  trajectory: { first_index: number; poses: TrajectoryPose[] };
  particles: ParticlePose[];
  hypotheses: Hypothesis[];
  frontiers: XY[];
  target: ExplorationTarget | null;
  stats: EngineStats;
  scan?: ScanMessage | null;
}
export interface PoseMessage extends Pose {
  type: 'pose';
}
export interface ParticlesMessage {
  type: 'particles';
  poses: ParticlePose[];
}
export interface StatsMessage {
  type: 'stats';
  stats: EngineStats;
}
export interface ExplorationMessage {
  type: 'exploration';
  frontiers: XY[];
  target: ExplorationTarget | null;
}
export interface TrajectoryMessage {
  type: 'trajectory';
  first_index: number;
  poses: TrajectoryPose[];
}
export interface HypothesisMessage {
  type: 'hypothesis';
  event: 'added' | 'updated' | 'removed';
  hypothesis: Hypothesis | { id: number };
}
export interface SessionMessage {
  type: 'session';
  session_id: string;
  status: string;
}
export interface ErrorMessage {
  type: 'error';
  code: string;
  message: string;
}
// The current laser scan in the map frame: the sensor pose and the ranges (null: no return).
export interface ScanMessage {
  type: 'scan';
  seq?: number; // of the scan's input (binary frames)
  pose: Pose;
  angle_min: number;
  angle_increment: number;
  max_range?: number;
  ranges: (number | null)[];
}

export type LiveMessage =
  | SnapshotMessage
  | PoseMessage
  | ParticlesMessage
  | StatsMessage
  | ExplorationMessage
  | TrajectoryMessage
  | HypothesisMessage
  | SessionMessage
  | ErrorMessage
  | ScanMessage;

export type Decoded<T> = { ok: true; value: T } | { ok: false; error: string };

const ok = <T>(value: T): Decoded<T> => ({ ok: true, value });
const fail = <T>(error: string): Decoded<T> => ({ ok: false, error });

const isObject = (v: unknown): v is Record<string, unknown> => typeof v === 'object' && v !== null && !Array.isArray(v);
const isNumber = (v: unknown): v is number => typeof v === 'number' && Number.isFinite(v);
const isNumberArray = (v: unknown, n: number): boolean =>
  Array.isArray(v) && v.length >= n && v.slice(0, n).every((x) => typeof x === 'number');

function checkPose(v: unknown): v is Pose {
  return isObject(v) && isNumber(v.x) && isNumber(v.y) && isNumber(v.theta);
}

function checkRows(v: unknown, width: number, what: string): string | null {
  if (!Array.isArray(v)) return `${what} must be an array`;
  for (let i = 0; i < v.length; i++) {
    if (!isNumberArray(v[i], width)) return `${what}[${i}] must hold ${width} numbers`;
  }
  return null;
}

function checkHypothesis(v: unknown): string | null {
  if (!isObject(v)) return 'hypothesis must be an object';
  if (!isNumber(v.id)) return 'hypothesis.id must be a number';
  if (!isNumberArray(v.target_cell, 2)) return 'hypothesis.target_cell must be [x, y]';
  for (const k of ['psi', 'area', 'hit_ratio', 'cell_count'] as const) {
    if (v[k] !== undefined && v[k] !== null && typeof v[k] !== 'number') return `hypothesis.${k} must be a number`;
  }
  if (typeof v.status !== 'string') return 'hypothesis.status must be a string';
  return null;
}

function checkTarget(v: unknown): string | null {
  if (v === null || v === undefined) return null;
  if (!isObject(v) || !isNumber(v.x) || !isNumber(v.y)) return 'target must be {x, y, path}';
  if (v.path !== undefined) return checkRows(v.path, 2, 'target.path');
  return null;
}

// Normalises a hypothesis: missing numbers become 0 (older servers), psi_observed NaN becomes null.
function normaliseHypothesis(v: Record<string, unknown>): Hypothesis {
  const num = (x: unknown) => (typeof x === 'number' && Number.isFinite(x) ? x : 0);
  return {
    id: v.id as number,
    time: num(v.time),
    target_cell: v.target_cell as XY,
    reference_cell: isNumberArray(v.reference_cell, 2) ? (v.reference_cell as XY) : [0, 0],
    reference_map:
      isObject(v.reference_map) && typeof v.reference_map.site === 'string' && typeof v.reference_map.version === 'number'
        ? { site: v.reference_map.site, version: v.reference_map.version }
        : null,
    theta: num(v.theta),
    translation: isNumberArray(v.translation, 2) ? (v.translation as XY) : [0, 0],
    psi: num(v.psi),
    area: num(v.area),
    cell_count: num(v.cell_count),
    status: v.status as string,
    hit_ratio: num(v.hit_ratio),
    psi_observed: typeof v.psi_observed === 'number' && Number.isFinite(v.psi_observed) ? v.psi_observed : null,
  };
}

function normaliseTarget(v: unknown): ExplorationTarget | null {
  if (!isObject(v)) return null;
  return {
    x: v.x as number,
    y: v.y as number,
    path: Array.isArray(v.path) ? (v.path as XY[]) : [],
    pose: checkPose(v.pose) ? v.pose : null,
  };
}

function decodeScan(m: Record<string, unknown>): Decoded<ScanMessage> {
  if (!checkPose(m.pose)) return fail('scan.pose must be {x, y, theta}');
  if (!isNumber(m.angle_min) || !isNumber(m.angle_increment)) return fail('scan needs angle_min and angle_increment');
  if (!Array.isArray(m.ranges) || m.ranges.length > 100000) return fail('scan.ranges must be an array');
  return ok({
    type: 'scan',
    pose: m.pose,
    angle_min: m.angle_min,
    angle_increment: m.angle_increment,
    max_range: isNumber(m.max_range) ? m.max_range : undefined,
    ranges: m.ranges.map((r) => (typeof r === 'number' && Number.isFinite(r) ? r : null)),
  });
}

// Checks a parsed text message. Unknown types are an error the caller may choose to ignore.
export function decodeLiveMessage(raw: unknown): Decoded<LiveMessage> {
  if (!isObject(raw) || typeof raw.type !== 'string') return fail('message without a type');
  const m = raw;
  switch (m.type) {
    case 'snapshot': {
      if (typeof m.session_id !== 'string') return fail('snapshot.session_id must be a string');
      if (!isNumber(m.resolution) || m.resolution <= 0) return fail('snapshot.resolution must be positive');
      if (!isNumber(m.tile_size) || m.tile_size < 1 || m.tile_size > 1024) return fail('snapshot.tile_size out of range');
      if (!isNumber(m.tile_count) || m.tile_count < 0) return fail('snapshot.tile_count must be a count');
      if (m.pose !== null && m.pose !== undefined && !checkPose(m.pose)) return fail('snapshot.pose must be a pose');
      const traj = isObject(m.trajectory) ? m.trajectory : { first_index: 0, poses: [] };
      const trajError = checkRows(traj.poses ?? [], 3, 'snapshot.trajectory.poses');
      if (trajError) return fail(trajError);
      const particleError = checkRows(m.particles ?? [], 3, 'snapshot.particles');
      if (particleError) return fail(particleError);
      const frontierError = checkRows(m.frontiers ?? [], 2, 'snapshot.frontiers');
      if (frontierError) return fail(frontierError);
      const targetError = checkTarget(m.target);
      if (targetError) return fail(targetError);
      const hypotheses = Array.isArray(m.hypotheses) ? m.hypotheses : [];
      for (const h of hypotheses) {
        const e = checkHypothesis(h);
        if (e) return fail(`snapshot: ${e}`);
      }
      let scan: ScanMessage | null = null;
      if (isObject(m.scan)) {
        const s = decodeScan(m.scan);
        if (s.ok) scan = s.value;
      }
      return ok({
        type: 'snapshot',
        session_id: m.session_id,
        status: typeof m.status === 'string' ? m.status : 'active',
        resolution: m.resolution,
        tile_size: m.tile_size,
        tile_count: m.tile_count,
        pose: checkPose(m.pose) ? m.pose : null,
        trajectory: {
          first_index: isNumber(traj.first_index) ? traj.first_index : 0,
          poses: (traj.poses ?? []) as TrajectoryPose[],
        },
        particles: (m.particles ?? []) as ParticlePose[],
        hypotheses: hypotheses.map((h) => normaliseHypothesis(h as Record<string, unknown>)),
        frontiers: (m.frontiers ?? []) as XY[],
        target: normaliseTarget(m.target),
        stats: isObject(m.stats) ? (m.stats as EngineStats) : {},
        scan,
      });
    }
    case 'pose':
      if (!checkPose(m)) return fail('pose needs x, y and theta');
      return ok({ type: 'pose', x: m.x, y: m.y, theta: m.theta });
    case 'stats':
      if (!isObject(m.stats)) return fail('stats.stats must be an object');
      return ok({ type: 'stats', stats: m.stats as EngineStats });
    case 'exploration': {
      const e = checkRows(m.frontiers ?? [], 2, 'exploration.frontiers') ?? checkTarget(m.target);
      if (e) return fail(e);
      return ok({ type: 'exploration', frontiers: (m.frontiers ?? []) as XY[], target: normaliseTarget(m.target) });
    }
    case 'trajectory': {
      if (!isNumber(m.first_index) || m.first_index < 0) return fail('trajectory.first_index must be a count');
      const e = checkRows(m.poses, 3, 'trajectory.poses');
      return e ? fail(e) : ok({ type: 'trajectory', first_index: m.first_index, poses: m.poses as TrajectoryPose[] });
    }
    case 'hypothesis': {
      if (m.event !== 'added' && m.event !== 'updated' && m.event !== 'removed') {
        return fail('hypothesis.event must be added, updated or removed');
      }
      if (!isObject(m.hypothesis) || !isNumber(m.hypothesis.id)) return fail('hypothesis.hypothesis.id missing');
      if (m.event === 'removed') return ok({ type: 'hypothesis', event: 'removed', hypothesis: { id: m.hypothesis.id } });
      const e = checkHypothesis(m.hypothesis);
      if (e) return fail(e);
      return ok({ type: 'hypothesis', event: m.event, hypothesis: normaliseHypothesis(m.hypothesis) });
    }
    case 'session':
      if (typeof m.status !== 'string') return fail('session.status must be a string');
      return ok({ type: 'session', session_id: String(m.session_id ?? ''), status: m.status });
    case 'error':
      return ok({ type: 'error', code: String(m.code ?? 'error'), message: String(m.message ?? '') });
    default:
      return fail(`unknown message type '${String(m.type).slice(0, 40)}'`);
  }
}

// Binary map tile frame, little-endian:
//   0 'PSTL' | 4 i32 tx | 8 i32 ty | 12 u16 size | 14 u8 encoding | 15 u8 reserved | 16 u64 revision
//   24.. zlib stream of size*size bytes, row-major, row 0 at the lowest y.
// Encoding 1: one byte per cell, occupancy in percent 0..100, 255 unknown.
export const kTileHeaderBytes = 24;
export const kEncodingPercent = 1;
export const kUnknownCell = 255;

export interface Tile {
  tx: number;
  ty: number;
  size: number;
  revision: number;
  cells: Uint8Array;
}

// Decodes one tile frame. 'scratch' (size*size bytes) may be passed to avoid an allocation per
// tile; the returned cells then alias it.
export function decodeTileFrame(frame: ArrayBuffer | Uint8Array, scratch?: Uint8Array): Decoded<Tile> {
  const bytes = frame instanceof Uint8Array ? frame : new Uint8Array(frame);
  if (bytes.length < kTileHeaderBytes) return fail('tile frame shorter than its header');
  if (bytes[0] !== 0x50 || bytes[1] !== 0x53 || bytes[2] !== 0x54 || bytes[3] !== 0x4c) return fail('tile frame without PSTL magic');
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  const tx = view.getInt32(4, true);
  const ty = view.getInt32(8, true);
  const size = view.getUint16(12, true);
  const encoding = view.getUint8(14);
  // The revision is a u64; tiles never reach 2^53 revisions, so a double holds it exactly.
  const revision = view.getUint32(16, true) + view.getUint32(20, true) * 2 ** 32;
  if (encoding !== kEncodingPercent) return fail(`tile (${tx}, ${ty}): unknown encoding ${encoding}`);
  if (size < 1 || size > 1024) return fail(`tile (${tx}, ${ty}): size ${size} out of range`);
  const n = size * size;
  if (bytes.length < kTileHeaderBytes + 6) return fail(`tile (${tx}, ${ty}): payload too short for a zlib stream`);
  const out = scratch && scratch.length === n ? scratch : new Uint8Array(n);
  let cells: Uint8Array;
  try {
    cells = unzlibSync(bytes.subarray(kTileHeaderBytes), { out });
  } catch (e) {
    return fail(`tile (${tx}, ${ty}): corrupt payload (${(e as Error).message})`);
  }
  // fflate returns a shorter view when the stream is short, or a new array when it is longer.
  if (cells.length !== n) return fail(`tile (${tx}, ${ty}): ${cells.length} cells, expected ${n}`);
  // fflate does not check the stream's Adler-32 (and truncates a stream longer than 'out'): check it
  // here, so a corrupt or oversized tile is reported rather than drawn.
  const expected = view.getUint32(bytes.length - 4, false);
  if (adler32(cells) !== expected) return fail(`tile (${tx}, ${ty}): checksum mismatch`);
  return ok({ tx, ty, size, revision, cells });
}

export function adler32(data: Uint8Array): number {
  let a = 1;
  let b = 0;
  const kMod = 65521;
  // 5552 bytes is the longest run before 'b' can overflow 2^32 (zlib's NMAX).
  for (let start = 0; start < data.length; start += 5552) {
    const end = Math.min(start + 5552, data.length);
    for (let i = start; i < end; i++) {
      a += data[i];
      b += a;
    }
    a %= kMod;
    b %= kMod;
  }
  return ((b << 16) | a) >>> 0;
}

// Encodes a tile frame; used by tests and the benchmark page to produce what the server sends.
export function encodeTileFrame(tile: Tile, zlib: (data: Uint8Array) => Uint8Array): Uint8Array {
  const payload = zlib(tile.cells);
  const out = new Uint8Array(kTileHeaderBytes + payload.length);
  const view = new DataView(out.buffer);
  out.set([0x50, 0x53, 0x54, 0x4c], 0);
  view.setInt32(4, tile.tx, true);
  view.setInt32(8, tile.ty, true);
  view.setUint16(12, tile.size, true);
  view.setUint8(14, kEncodingPercent);
  view.setUint32(16, tile.revision % 2 ** 32, true);
  view.setUint32(20, Math.floor(tile.revision / 2 ** 32), true);
  out.set(payload, kTileHeaderBytes);
  return out;
}

// Which binary frame this is, by its magic.
export type BinaryKind = 'tile' | 'scan' | 'particles' | 'unknown';

export function binaryKind(frame: ArrayBuffer | Uint8Array): BinaryKind {
  const b = frame instanceof Uint8Array ? frame : new Uint8Array(frame);
  if (b.length < 4 || b[0] !== 0x50 || b[1] !== 0x53) return 'unknown'; // 'PS'
  const tag = String.fromCharCode(b[2], b[3]);
  return tag === 'TL' ? 'tile' : tag === 'SC' ? 'scan' : tag === 'PT' ? 'particles' : 'unknown';
}

// Binary scan frame, little-endian:
//   0 'PSSC' | 4 u16 beams | 6 u8 encoding | 7 u8 reserved | 8 i64 seq | 16 f32 x, y, theta (sensor, map
//   frame) | 28 f32 angle_min | 32 f32 angle_increment | 36 f32 max_range | 40 u16 ranges (cm).
// Encoding 1: centimetres, 65535 no return.
export const kScanHeaderBytes = 40;
export const kScanNoReturn = 65535;
export const kParticleHeaderBytes = 8;
export const kMaxParticles = 2000;

const viewOf = (frame: ArrayBuffer | Uint8Array) => {
  const bytes = frame instanceof Uint8Array ? frame : new Uint8Array(frame);
  return { bytes, view: new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength) };
};

export function decodeScanFrame(frame: ArrayBuffer | Uint8Array): Decoded<ScanMessage> {
  const { bytes, view } = viewOf(frame);
  if (binaryKind(bytes) !== 'scan') return fail('scan frame without PSSC magic');
  if (bytes.length < kScanHeaderBytes) return fail('scan frame shorter than its header');
  const beams = view.getUint16(4, true);
  const encoding = view.getUint8(6);
  if (encoding !== 1) return fail(`scan frame: unknown encoding ${encoding}`);
  if (bytes.length !== kScanHeaderBytes + 2 * beams) return fail(`scan frame: ${bytes.length} bytes for ${beams} beams`);
  const pose = { x: view.getFloat32(16, true), y: view.getFloat32(20, true), theta: view.getFloat32(24, true) };
  const angle_min = view.getFloat32(28, true);
  const angle_increment = view.getFloat32(32, true);
  const max_range = view.getFloat32(36, true);
  if (![pose.x, pose.y, pose.theta, angle_min, angle_increment, max_range].every(Number.isFinite)) {
    return fail('scan frame: pose or angles not finite');
  }
  const ranges: (number | null)[] = new Array(beams);
  for (let i = 0; i < beams; i++) {
    const cm = view.getUint16(kScanHeaderBytes + 2 * i, true);
    ranges[i] = cm === kScanNoReturn ? null : cm / 100;
  }
  return ok({ type: 'scan', seq: Number(view.getBigInt64(8, true)), pose, angle_min, angle_increment, max_range, ranges });
}

// Binary particle frame, little-endian: 0 'PSPT' | 4 u32 count | 8 (f32 x, y, theta, weight) per particle.
export function decodeParticleFrame(frame: ArrayBuffer | Uint8Array): Decoded<ParticlesMessage> {
  const { bytes, view } = viewOf(frame);
  if (binaryKind(bytes) !== 'particles') return fail('particle frame without PSPT magic');
  if (bytes.length < kParticleHeaderBytes) return fail('particle frame shorter than its header');
  const n = view.getUint32(4, true);
  if (n > kMaxParticles) return fail(`particle frame: ${n} particles, at most ${kMaxParticles}`);
  if (bytes.length !== kParticleHeaderBytes + 16 * n) return fail(`particle frame: ${bytes.length} bytes for ${n} particles`);
  const poses: ParticlePose[] = new Array(n);
  for (let i = 0; i < n; i++) {
    const at = kParticleHeaderBytes + 16 * i;
    const p: ParticlePose = [view.getFloat32(at, true), view.getFloat32(at + 4, true), view.getFloat32(at + 8, true), view.getFloat32(at + 12, true)];
    if (!p.every(Number.isFinite)) return fail(`particle frame: particle ${i} not finite`);
    poses[i] = p;
  }
  return ok({ type: 'particles', poses });
}

// Encoders, for tests: the frames as the server's live codec writes them.
export function encodeScanFrame(scan: ScanMessage, seq: number): Uint8Array {
  const out = new Uint8Array(kScanHeaderBytes + 2 * scan.ranges.length);
  const view = new DataView(out.buffer);
  out.set([0x50, 0x53, 0x53, 0x43], 0);
  view.setUint16(4, scan.ranges.length, true);
  view.setUint8(6, 1);
  view.setBigInt64(8, BigInt(seq), true);
  [scan.pose.x, scan.pose.y, scan.pose.theta, scan.angle_min, scan.angle_increment, scan.max_range ?? 0].forEach((v, i) =>
    view.setFloat32(16 + 4 * i, v, true),
  );
  scan.ranges.forEach((r, i) => view.setUint16(kScanHeaderBytes + 2 * i, r === null ? kScanNoReturn : Math.round(r * 100), true));
  return out;
}

export function encodeParticleFrame(poses: ParticlePose[]): Uint8Array {
  const out = new Uint8Array(kParticleHeaderBytes + 16 * poses.length);
  const view = new DataView(out.buffer);
  out.set([0x50, 0x53, 0x50, 0x54], 0);
  view.setUint32(4, poses.length, true);
  poses.forEach((p, i) => p.forEach((v, k) => view.setFloat32(kParticleHeaderBytes + 16 * i + 4 * k, v, true)));
  return out;
}
