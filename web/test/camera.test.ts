import { describe, expect, it } from 'vitest';
import { Camera, kMaxScale, niceScaleBar } from '../src/render/camera';

describe('Camera', () => {
  const cam = () => {
    const c = new Camera();
    c.setViewport(800, 600);
    c.centerX = 10;
    c.centerY = 5;
    c.scale = 20;
    return c;
  };

  it('maps world to screen with y up and back', () => {
    const c = cam();
    expect(c.worldToScreenX(10)).toBe(400);
    expect(c.worldToScreenY(5)).toBe(300);
    expect(c.worldToScreenY(6)).toBe(280);
    const [x, y] = c.screenToWorld(c.worldToScreenX(3.3), c.worldToScreenY(-7.1));
    expect(x).toBeCloseTo(3.3);
    expect(y).toBeCloseTo(-7.1);
  });

  it('zooms around the pointer', () => {
    const c = cam();
    const before = c.screenToWorld(123, 456);
    c.zoomAt(2.5, 123, 456);
    const after = c.screenToWorld(123, 456);
    expect(after[0]).toBeCloseTo(before[0]);
    expect(after[1]).toBeCloseTo(before[1]);
    expect(c.scale).toBe(50);
    c.zoomAt(1e9, 0, 0);
    expect(c.scale).toBe(kMaxScale);
  });

  it('pans with the drag', () => {
    const c = cam();
    const [wx, wy] = c.screenToWorld(100, 100);
    c.panBy(30, -40);
    const [x, y] = c.screenToWorld(130, 60);
    expect(x).toBeCloseTo(wx);
    expect(y).toBeCloseTo(wy);
  });

  it('fits a box inside the margins', () => {
    const c = cam();
    c.fit({ minX: 0, minY: 0, maxX: 100, maxY: 20 }, 10);
    expect(c.worldToScreenX(0)).toBeGreaterThanOrEqual(10 - 1e-9);
    expect(c.worldToScreenX(100)).toBeLessThanOrEqual(790 + 1e-9);
    const v = c.visibleWorld();
    expect(v.minY).toBeLessThan(0);
    expect(v.maxY).toBeGreaterThan(20);
  });
});

describe('niceScaleBar', () => {
  it('picks 1, 2 or 5 times a power of ten that fits', () => {
    expect(niceScaleBar(40, 120)).toMatchObject({ meters: 2, label: '2 m' });
    expect(niceScaleBar(1000, 120)).toMatchObject({ meters: 0.1, label: '10 cm' });
    expect(niceScaleBar(1, 120)).toMatchObject({ meters: 100, label: '100 m' });
    expect(niceScaleBar(0.05, 120).label).toBe('2 km');
    const b = niceScaleBar(33, 120);
    expect(b.pixels).toBeLessThanOrEqual(120);
  });
});
