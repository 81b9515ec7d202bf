#!/usr/bin/env python3
"""Which ground-truth relations of a log does its own wheel odometry contradict?

Over a fraction of a second wheel odometry is off by millimetres, not decimetres. A relation
between two scans less than --max-gap seconds apart whose translation differs from the odometry's
by more than --min-disagreement metres is therefore doubtful (e.g. a robot that would have moved
0.75 m in 0.48 s), and every trajectory pays for it alike. This lists those relations and, for
each trajectory given, `pslam eval`'s RPE translation mean over all relations, over the doubtful
ones and over the rest, so that a mean can be read against how much of
it such relations make. It also counts the short relations whose forward translation equals the
odometry's to half a millimetre, or differs from it by a whole number of 5 cm steps (to 5 mm):
relations made by correcting odometry on a 5 cm grid carry that grid's rounding. A log whose recorder got odometry wrong (FR079 when backing up, see
docs/loop-closure.md) shows up here as well: read the list before the figures.

Usage: tests/bench/relations_vs_odometry.py LOG.clf LOG.relations [TRAJECTORY...]
       [--max-gap 2.0] [--min-disagreement 0.08] [--list]      Env: PSLAM_BIN (default build/bin/pslam)
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

PSLAM = os.environ.get("PSLAM_BIN", os.path.join(os.path.dirname(__file__), "..", "..", "build", "bin", "pslam"))


def scan_odometry(log_path):
    """Stamp -> (x, y, theta) of the wheel odometry at each FLASER scan (old CARMEN format)."""
    odometry = {}
    with open(log_path) as log:
        for line in log:
            fields = line.split()
            if not fields or fields[0] != "FLASER":
                continue
            n = int(fields[1])
            x, y, theta = map(float, fields[5 + n:8 + n])
            odometry[round(float(fields[8 + n]), 3)] = (x, y, theta)
    return odometry


def rpe(trajectory, relation_lines):
    """pslam eval's RPE translation mean and relation count over the given relation lines."""
    with tempfile.NamedTemporaryFile("w", suffix=".relations") as f:
        f.writelines(relation_lines)
        f.flush()
        out = subprocess.run([PSLAM, "eval", "--json", "--trajectory", trajectory, "--relations", f.name,
                              "--max-missing", "100"], check=True, capture_output=True, text=True).stdout
    result = json.loads(out)
    return result["trans_mean_m"], result["used"]


def relations(path):
    """(t1, t2, x, y, line) of each relation."""
    out = []
    with open(path) as f:
        for line in f:
            fields = line.split()
            if len(fields) >= 8:
                out.append((float(fields[0]), float(fields[1]), float(fields[2]), float(fields[3]), line))
    return out


def between(a, b):
    dx, dy = b[0] - a[0], b[1] - a[1]
    c, s = math.cos(a[2]), math.sin(a[2])
    return (c * dx + s * dy, -s * dx + c * dy)


def lookup(poses, stamp):
    return poses.get(round(stamp, 3))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("log")
    parser.add_argument("relations")
    parser.add_argument("trajectories", nargs="*")
    parser.add_argument("--max-gap", type=float, default=2.0, help="seconds between the two scans (default 2)")
    parser.add_argument("--min-disagreement", type=float, default=0.08, help="metres (default 0.08)")
    parser.add_argument("--list", action="store_true", help="print every doubtful relation")
    args = parser.parse_args()

    odometry = scan_odometry(args.log)
    if not odometry:
        sys.exit(f"{args.log}: no FLASER records")
    all_relations = relations(args.relations)
    doubtful = set()
    short = same = stepped = 0
    for k, (t1, t2, x, y, _) in enumerate(all_relations):
        a, b = lookup(odometry, t1), lookup(odometry, t2)
        if a is None or b is None or t2 - t1 >= args.max_gap:
            continue
        short += 1
        ox, oy = between(a, b)
        steps = (ox - x) / 0.05
        if abs(ox - x) < 0.0005:
            same += 1
        elif abs(steps - round(steps)) * 0.05 < 0.005:
            stepped += 1
        if math.hypot(ox - x, oy - y) > args.min_disagreement:
            doubtful.add(k)
            if args.list:
                print(f"  {t1:.3f} -> {t2:.3f}: relation {math.hypot(x, y):.3f} m, odometry {math.hypot(ox, oy):.3f} m, "
                      f"apart by {math.hypot(ox - x, oy - y):.3f} m")
    print(f"{args.relations}: {len(all_relations)} relations, {short} under {args.max_gap:g} s; "
          f"{len(doubtful)} of those disagree with the wheel odometry by more than {args.min_disagreement:g} m")
    if short:
        print(f"  forward translation equal to the odometry's: {same} ({100 * same / short:.0f} %); "
              f"off by whole 5 cm steps: {stepped} ({100 * stepped / short:.0f} %; {100 * 0.2 * (short - same) / short:.0f} % "
              f"expected by chance)")

    doubtful_lines = [r[4] for k, r in enumerate(all_relations) if k in doubtful]
    other_lines = [r[4] for k, r in enumerate(all_relations) if k not in doubtful]
    for path in args.trajectories:
        mean, used = rpe(path, [r[4] for r in all_relations])
        doubtful_mean, doubtful_used = rpe(path, doubtful_lines) if doubtful_lines else (float("nan"), 0)
        other_mean, other_used = rpe(path, other_lines)
        share = 100 * doubtful_mean * doubtful_used / (mean * used) if doubtful_used else 0.0
        print(f"{path}: RPE translation mean {mean:.4f} m over {used}; doubtful {doubtful_mean:.4f} m over "
              f"{doubtful_used} ({share:.1f} % of the sum); the rest {other_mean:.4f} m over {other_used}")


if __name__ == "__main__":
    main()
