#!/usr/bin/env python3
"""Summarises valerant_eval grids for docs/whole_level.md: one markdown row per grid
folder (a folder per option setting), with the mean reachable floor observed, the mean
in-solid committed frames (results.csv's penetrations), how many runs leave their spawn
(results.csv's first_translation_step: a translation committed within the first 5
exploration steps, stalls counted) and the mean wall time of a run.

    scripts/whole_level_table.py [--spawns K] NAME=GRID_DIR [NAME=GRID_DIR ...]

--spawns K keeps the runs of spawns 0 to K-1 only (to compare grids of different sizes).

Exit status 0 done, 1 a grid folder or one of its files is missing or malformed."""
import csv
import sys

LEAVE_WITHIN_STEPS = 5  # kSpawnDepartureSteps of include/valerant/eval/spawn_departure.h


def leaves_spawn(row):
    if not row["first_translation_step"]:
        raise ValueError(f"{row['map']} spawn {row['spawn']}: no first_translation_step (a report from before it)")
    return 1 <= int(row["first_translation_step"]) <= LEAVE_WITHIN_STEPS


def summary(grid, spawns):
    with open(f"{grid}/results.csv") as f:
        rows = [r for r in csv.DictReader(f) if r["ok"] == "1" and (spawns is None or int(r["spawn"]) < spawns)]
    if not rows:
        raise ValueError(f"{grid}/results.csv: no finished run")
    left = sum(leaves_spawn(r) for r in rows)
    mean = lambda key: sum(float(r[key]) for r in rows) / len(rows)
    return (len(rows), mean("observed_reachable_percent"), mean("penetrations"), left, mean("wall_seconds"))


def main(argv):
    args, spawns = argv[1:], None
    if len(args) >= 2 and args[0] == "--spawns":
        if not args[1].isdigit() or int(args[1]) < 1:
            print(f"whole_level_table.py: --spawns {args[1]}: expected a whole number of at least 1", file=sys.stderr)
            return 1
        args, spawns = args[2:], int(args[1])
    if not args or any("=" not in a for a in args):
        print(__doc__, file=sys.stderr)
        return 1
    print("| setting | runs | reachable floor observed | in-solid committed frames | leave spawn (translation in 5 steps) | wall s / run |")
    print("|---|---|---|---|---|---|")
    for arg in args:
        name, grid = arg.split("=", 1)
        try:
            runs, observed, in_solid, left, wall = summary(grid, spawns)
        except (OSError, ValueError, KeyError) as e:
            print(f"whole_level_table.py: {grid}: {e}", file=sys.stderr)
            return 1
        print(f"| {name} | {runs} | {observed:.1f} % | {in_solid:.2f} | {left} / {runs} | {wall:.0f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
