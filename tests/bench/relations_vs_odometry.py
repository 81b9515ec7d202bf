#!/usr/bin/env python3
"""Which ground-truth relations of a log does its own wheel odometry contradict?

Over a fraction of a second wheel odometry is off by millimetres, not decimetres. A relation
between two scans less than --max-gap seconds apart whose translation differs from the odometry's
by more than --min-disagreement metres is therefore doubtful (e.g. a robot that would have moved
0.75 m in 0.48 s), and every trajectory pays for it alike. This lists those relations and, for
each trajectory given, the RPE translation mean over all relations, over the doubtful ones and
over the rest (the same formula as `pslam eval`), so that a mean can be read against how much of
it such relations make. It also counts the short relations whose forward translation equals the
odometry's to half a millimetre, or differs from it by a whole number of 5 cm steps (to 5 mm):
relations made by correcting odometry on a 5 cm grid carry that grid's rounding. A log whose recorder got odometry wrong (FR079 when backing up, see
docs/loop-closure.md) shows up here as well: read the list before the figures.

Usage: tests/bench/relations_vs_odometry.py LOG.clf LOG.relations [TRAJECTORY...]
       [--max-gap 2.0] [--min-disagreement 0.08] [--list]
"""
import argparse
import math
import sys


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


def trajectory(path):
    poses = {}
    with open(path) as f:
        for line in f:
            fields = line.split()
            if len(fields) >= 4 and not line.startswith("#"):
                poses[round(float(fields[0]), 3)] = tuple(map(float, fields[1:4]))
    return poses


def relations(path):
    out = []
    with open(path) as f:
        for line in f:
            fields = line.split()
            if len(fields) >= 8:
                out.append((float(fields[0]), float(fields[1]), float(fields[2]), float(fields[3])))
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
    for k, (t1, t2, x, y) in enumerate(all_relations):
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

    for path in args.trajectories:
        poses = trajectory(path)
        errors, doubtful_errors, other_errors = [], [], []
        for k, (t1, t2, x, y) in enumerate(all_relations):
            a, b = lookup(poses, t1), lookup(poses, t2)
            if a is None or b is None:
                continue
            ex, ey = between(a, b)
            e = math.hypot(ex - x, ey - y)
            errors.append(e)
            (doubtful_errors if k in doubtful else other_errors).append(e)
        if not errors:
            print(f"{path}: no relation matched a pose")
            continue
        mean = lambda v: sum(v) / len(v) if v else float("nan")
        print(f"{path}: RPE translation mean {mean(errors):.4f} m over {len(errors)}; "
              f"doubtful {mean(doubtful_errors):.4f} m over {len(doubtful_errors)} "
              f"({100 * sum(doubtful_errors) / sum(errors):.1f} % of the sum); "
              f"the rest {mean(other_errors):.4f} m over {len(other_errors)}")


if __name__ == "__main__":
    main()
