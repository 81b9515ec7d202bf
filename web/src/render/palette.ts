// Colour tables, built once. The map palette turns a cell byte (0..100 percent occupied, 255
// unknown) into a packed RGBA word in one lookup, so uploading a tile is one pass over its cells.

export type RGBA = [number, number, number, number];

// Packs a colour as the Uint32 that a Uint32Array view over ImageData bytes holds on this machine.
export function packRGBA([r, g, b, a]: RGBA, littleEndian = kLittleEndian): number {
  return littleEndian ? ((a << 24) | (b << 16) | (g << 8) | r) >>> 0 : ((r << 24) | (g << 16) | (b << 8) | a) >>> 0;
}

export function unpackRGBA(v: number, littleEndian = kLittleEndian): RGBA {
  return littleEndian
    ? [v & 255, (v >>> 8) & 255, (v >>> 16) & 255, v >>> 24]
    : [v >>> 24, (v >>> 16) & 255, (v >>> 8) & 255, v & 255];
}

export const kLittleEndian = new Uint8Array(new Uint32Array([1]).buffer)[0] === 1;

export interface MapPaletteColors {
  free: RGBA;
  occupied: RGBA;
  unknown: RGBA;
  invalid: RGBA;
}

// Light free space, dark walls, transparent unknown (the viewer's background shows through).
export const kDefaultMapColors: MapPaletteColors = {
  free: [226, 230, 236, 255],
  occupied: [6, 8, 12, 255],
  unknown: [0, 0, 0, 0],
  invalid: [255, 0, 255, 255],
};

// 256 entries: 0..100 blend free -> occupied, 255 unknown, anything else 'invalid' (so a bad value
// is visible rather than silently drawn as a wall).
export function buildMapPalette(colors: MapPaletteColors = kDefaultMapColors, littleEndian = kLittleEndian): Uint32Array {
  const table = new Uint32Array(256);
  const invalid = packRGBA(colors.invalid, littleEndian);
  table.fill(invalid);
  for (let v = 0; v <= 100; v++) {
    const t = v / 100;
    const c = colors.free.map((f, i) => Math.round(f + (colors.occupied[i] - f) * t)) as RGBA;
    table[v] = packRGBA(c, littleEndian);
  }
  table[255] = packRGBA(colors.unknown, littleEndian);
  return table;
}

// Writes a tile's cells (row 0 = lowest y) into 'out' (row 0 = top), through 'palette'.
// 'out' is a Uint32 view of size*size pixels.
export function paintTile(cells: Uint8Array, size: number, palette: Uint32Array, out: Uint32Array): void {
  for (let r = 0; r < size; r++) {
    const src = r * size;
    const dst = (size - 1 - r) * size;
    for (let c = 0; c < size; c++) out[dst + c] = palette[cells[src + c]];
  }
}

// Viridis, sampled at 9 stops: a perceptually even map for Psi in [0, 1].
const kViridis: [number, number, number][] = [
  [68, 1, 84],
  [71, 44, 122],
  [59, 81, 139],
  [44, 113, 142],
  [33, 144, 141],
  [39, 173, 129],
  [92, 200, 99],
  [170, 220, 50],
  [253, 231, 37],
];

export function viridis(t: number): [number, number, number] {
  const x = Math.min(1, Math.max(0, Number.isFinite(t) ? t : 0)) * (kViridis.length - 1);
  const i = Math.min(kViridis.length - 2, Math.floor(x));
  const f = x - i;
  const a = kViridis[i], b = kViridis[i + 1];
  return [Math.round(a[0] + (b[0] - a[0]) * f), Math.round(a[1] + (b[1] - a[1]) * f), Math.round(a[2] + (b[2] - a[2]) * f)];
}

// Psi in steps: hypotheses are accepted from Psi 0.7 (the predictor's default), so that range is
// split into 0.05 steps of clearly different colours, a hue ramp bright enough for the dark
// unexplored background; everything below 0.7 is one muted step.
export const kPsiStepFrom = 0.7;
export const kPsiStep = 0.05;
const kPsiColors: [number, number, number][] = [
  [150, 130, 190], // < 0.70
  [70, 140, 255], // 0.70
  [0, 200, 220], // 0.75
  [60, 200, 110], // 0.80
  [170, 220, 50], // 0.85
  [250, 220, 40], // 0.90
  [255, 140, 40], // 0.95
];
export const kPsiSteps = kPsiColors.length;

export function psiStep(psi: number): number {
  if (!Number.isFinite(psi) || psi < kPsiStepFrom) return 0;
  // The epsilon keeps a value on a boundary (0.75 is 0.7499999... in floating point) in the upper step.
  return Math.min(kPsiSteps - 1, 1 + Math.floor((psi - kPsiStepFrom) / kPsiStep + 1e-9));
}

export function psiColor(psi: number): [number, number, number] {
  return kPsiColors[psiStep(psi)];
}

// The lower edge of each step, for the legend.
export function psiStepLabel(step: number): string {
  return step === 0 ? `< ${kPsiStepFrom}` : (kPsiStepFrom + (step - 1) * kPsiStep).toFixed(2);
}

export const kStatusColors: Record<string, [number, number, number]> = {
  pending: [90, 160, 255],
  confirmed: [60, 200, 110],
  refuted: [240, 70, 70],
  expired: [140, 140, 150],
};

export function statusColor(status: string): [number, number, number] {
  return kStatusColors[status] ?? [200, 200, 200];
}

export const css = ([r, g, b]: [number, number, number], a = 1): string => `rgba(${r},${g},${b},${a})`;
