#!/usr/bin/env python3
"""Another floor of the same plan: a world file (map_server YAML + PGM with '# start:') with some
rooms changed. Furniture (occupied blobs not joined to the walls) is removed from a share of the
rooms and new blocks are placed where a block and a margin the robot can pass around it are all
free, so every place stays reachable. Deterministic per --seed.

    floor_variant.py IN.yaml OUT_PREFIX [--seed S] [--remove F] [--add N]
"""
import argparse
import random
import re
import sys
from collections import deque

FREE, OCC = 254, 0
RES_MARGIN_M = 1.0    # free margin kept around an added block (robot gap 0.9 m)
BLOCK_M = (0.8, 1.6)  # side lengths of an added block


def read_pgm(path):
    data = open(path, 'rb').read()
    tokens, i = [], 0
    while len(tokens) < 4:
        while data[i:i + 1].isspace():
            i += 1
        if data[i:i + 1] == b'#':
            while data[i:i + 1] != b'\n':
                i += 1
            continue
        j = i
        while not data[j:j + 1].isspace():
            j += 1
        tokens.append(data[i:j])
        i = j
    if tokens[0] != b'P5':
        sys.exit('only P5 PGM images')
    w, h = int(tokens[1]), int(tokens[2])
    return w, h, bytearray(data[i + 1:i + 1 + w * h])


def components(w, h, px, value):
    """4-connected components of cells equal to 'value', as lists of indices."""
    seen, out = bytearray(w * h), []
    for s in range(w * h):
        if px[s] != value or seen[s]:
            continue
        comp, q = [], deque([s])
        seen[s] = 1
        while q:
            c = q.popleft()
            comp.append(c)
            x, y = c % w, c // w
            for n in ((c - 1) if x > 0 else -1, (c + 1) if x < w - 1 else -1, c - w, c + w):
                if 0 <= n < w * h and px[n] == value and not seen[n]:
                    seen[n] = 1
                    q.append(n)
        out.append(comp)
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('yaml')
    ap.add_argument('out_prefix')
    ap.add_argument('--seed', type=int, default=1)
    ap.add_argument('--remove', type=float, default=0.5, help='share of furniture blobs removed')
    ap.add_argument('--add', type=int, default=12, help='blocks added')
    a = ap.parse_args()
    text = open(a.yaml).read()
    image = re.search(r'^image:\s*(\S+)', text, re.M).group(1)
    res = float(re.search(r'^resolution:\s*(\S+)', text, re.M).group(1))
    base = a.yaml.rsplit('/', 1)[0] + '/' if '/' in a.yaml else ''
    w, h, px = read_pgm(image if image.startswith('/') else base + image)
    rng = random.Random(a.seed)

    blobs = components(w, h, px, OCC)
    walls = max(blobs, key=len)  # the walls are one connected structure
    furniture = [b for b in blobs if b is not walls]
    removed = rng.sample(furniture, int(len(furniture) * a.remove))
    for blob in removed:
        for c in blob:
            px[c] = FREE

    margin = int(round(RES_MARGIN_M / res))
    added, tries = 0, 0
    while added < a.add and tries < 20000:
        tries += 1
        bw, bh = (int(round(rng.uniform(*BLOCK_M) / res)) for _ in range(2))
        x0, y0 = rng.randrange(margin, w - bw - margin), rng.randrange(margin, h - bh - margin)
        if all(px[y * w + x] == FREE for y in range(y0 - margin, y0 + bh + margin)
               for x in range(x0 - margin, x0 + bw + margin)):
            for y in range(y0, y0 + bh):
                px[y * w + x0:y * w + x0 + bw] = bytes([OCC]) * bw
            added += 1

    name = a.out_prefix.rsplit('/', 1)[-1]
    open(a.out_prefix + '.pgm', 'wb').write(b'P5\n%d %d\n255\n' % (w, h) + bytes(px))
    text = re.sub(r'^image:.*$', 'image: ' + name + '.pgm', text, count=1, flags=re.M)
    text = re.sub(r'^# world: (.*)$', r'# world: \1; variant seed %d: %d of %d furniture blobs removed, %d blocks added'
                  % (a.seed, len(removed), len(furniture), added), text, count=1, flags=re.M)
    open(a.out_prefix + '.yaml', 'w').write(text)
    print('%s: removed %d of %d furniture blobs, added %d blocks' % (a.out_prefix, len(removed), len(furniture), added))


if __name__ == '__main__':
    main()
