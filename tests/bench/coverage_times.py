#!/usr/bin/env python3
"""When each run of an exploration pair reached each share of the floor.

Usage: tests/bench/coverage_times.py RUN.json...   (the JSON files explore_bench.sh --keep DIR keeps)

Per pair: the simulated seconds full coverage and skip predicted took to map or predict 50, 75, 90
and 95 % of the reachable floor, and equal coverage (full coverage's final share less the
tolerance). Last, over all timed pairs, each run's time to each level as a share of full
coverage's time to equal coverage: where the skip runs gain, and where they give it back.
"""
import json
import sys

LEVELS = (0.5, 0.75, 0.9, 0.95)


def time_to(run, fraction):
    for t, c in zip(run["coverage_time_s"], run["coverage_fraction"]):
        if c >= fraction:
            return t
    return None


def fmt(v):
    return "-" if v is None else "%.0f" % v


def main(paths):
    if not paths:
        sys.exit(__doc__.strip())
    names = ["%d %%" % (100 * level) for level in LEVELS] + ["equal"]
    header = " / ".join(names)
    print("| world | full: s to %s | skip: s to %s |" % (header, header))
    print("| --- | --- | --- |")
    shares = {"full": [], "skip": []}  # per run: one list per timed pair, a share per level
    for path in sorted(paths):
        data = json.load(open(path))
        for pair in data["pairs"]:
            full, skip = pair["full"], pair["skip"]
            if "coverage_time_s" not in full:
                sys.exit("%s has no coverage trace: run it with a newer pslam" % path)
            # Time to equal coverage as the experiment itself timed it.
            times = {run: [time_to(r, level) for level in LEVELS] + [pair["%s_time_to_equal_s" % run]]
                     for run, r in (("full", full), ("skip", skip))}
            print("| %s, seed %d | %s | %s |" % (full["world"], full["seed"], " / ".join(map(fmt, times["full"])),
                                                  " / ".join(map(fmt, times["skip"]))))
            full_equal = times["full"][-1]
            if pair["time_limit_hit"] or pair["full_incomplete"] or not full_equal:
                continue  # not timed, as in the experiment's own figures
            for run in shares:
                shares[run].append([None if t is None else t / full_equal for t in times[run]])
    print()
    print("Time to each level as a share of full coverage's time to equal coverage, mean over %d timed pairs "
          "(in brackets: runs that never got there):" % len(shares["full"]))
    print()
    print("| run | %s |" % " | ".join(names))
    print("|" + " --- |" * (len(names) + 1))
    for run, pairs in shares.items():
        cells = []
        for i in range(len(names)):
            reached = [p[i] for p in pairs if p[i] is not None]
            never = len(pairs) - len(reached)
            cells.append(("%.2f" % (sum(reached) / len(reached)) if reached else "-") + (" (%d)" % never if never else ""))
        print("| %s | %s |" % (run, " | ".join(cells)))


if __name__ == "__main__":
    main(sys.argv[1:])
