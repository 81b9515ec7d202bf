import { describe, expect, it } from 'vitest';
import { buildMapPalette, kDefaultMapColors, packRGBA, paintTile, statusColor, unpackRGBA, viridis } from '../src/render/palette';

describe('map palette', () => {
  const palette = buildMapPalette();

  it('has 256 entries: free at 0, occupied at 100, transparent unknown at 255', () => {
    expect(palette.length).toBe(256);
    expect(unpackRGBA(palette[0])).toEqual(kDefaultMapColors.free);
    expect(unpackRGBA(palette[100])).toEqual(kDefaultMapColors.occupied);
    expect(unpackRGBA(palette[255])[3]).toBe(0);
  });

  it('darkens monotonically with occupancy', () => {
    for (let v = 1; v <= 100; v++) expect(unpackRGBA(palette[v])[0]).toBeLessThanOrEqual(unpackRGBA(palette[v - 1])[0]);
  });

  it('marks values outside the encoding as invalid', () => {
    expect(unpackRGBA(palette[101])).toEqual(kDefaultMapColors.invalid);
    expect(unpackRGBA(palette[254])).toEqual(kDefaultMapColors.invalid);
  });

  it('packs in both byte orders', () => {
    expect(unpackRGBA(packRGBA([1, 2, 3, 4], false), false)).toEqual([1, 2, 3, 4]);
    expect(unpackRGBA(packRGBA([1, 2, 3, 4], true), true)).toEqual([1, 2, 3, 4]);
  });

  it('paints a tile with row 0 (lowest y) at the bottom of the image', () => {
    const size = 4;
    const cells = new Uint8Array(size * size).fill(255);
    cells[0] = 100; // cell (0, 0): bottom-left
    cells[size * size - 1] = 0; // cell (3, 3): top-right
    const out = new Uint32Array(size * size);
    paintTile(cells, size, palette, out);
    expect(out[(size - 1) * size]).toBe(palette[100]);
    expect(out[size - 1]).toBe(palette[0]);
    expect(out[5]).toBe(palette[255]);
  });
});

describe('colour maps', () => {
  it('viridis spans dark purple to yellow and clamps', () => {
    expect(viridis(0)).toEqual([68, 1, 84]);
    expect(viridis(1)).toEqual([253, 231, 37]);
    expect(viridis(-3)).toEqual(viridis(0));
    expect(viridis(Number.NaN)).toEqual(viridis(0));
  });

  it('has a colour per status and a fallback', () => {
    expect(statusColor('confirmed')).not.toEqual(statusColor('refuted'));
    expect(statusColor('unheard-of')).toEqual([200, 200, 200]);
  });
});
