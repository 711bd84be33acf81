#!/usr/bin/python3
"""The table of docs/inside_brush.md: how often two signals fire on the turns in place
of valerant_eval grids, split by the engine's truth (a turn whose first frame is in
solid started inside; one with no frame in solid is clear).

  /usr/bin/python3 docs/inside_brush/turn_signals.py GRID_DIR [GRID_DIR ...]

Signals, read from each run's decisions.jsonl:
- start_occupied: committed points inside the body cylinder at the turn's start;
- contact: eq. 6's count at the last frame of the last committed translation
  (body_counts[-1] of the chosen verdict; 0 after a rewind, which restores a state
  from before it, an approximation of the Episode's own bookkeeping)."""
import glob
import json
import os
import sys


def turns(grid_dirs):
    out = []
    for d in grid_dirs:
        for path in sorted(glob.glob(os.path.join(d, 'runs', '*', 'decisions.jsonl'))):
            contact = 0
            for line in open(path):
                step = json.loads(line)
                for v in step['verdicts']:
                    mask = v.get('truth_in_solid_mask', '')
                    if v['rotation_only'] and mask:
                        out.append({'inside': mask[0] == '1', 'clear': '1' not in mask, 'contact': contact,
                                    'start_occupied': v['start_occupied'],
                                    'chosen': v['candidate'] == step['chosen']})
                if step['rewind']:
                    contact = 0
                elif step['chosen']:
                    c = next(v for v in step['verdicts'] if v['candidate'] == step['chosen'])
                    if not c['rotation_only']:
                        contact = c['body_counts'][-1] if c.get('body_counts') else 0
    return out


def main():
    rows = turns(sys.argv[1:])
    inside = [r for r in rows if r['inside']]
    clear = [r for r in rows if r['clear']]
    print(f'turns {len(rows)}: started inside {len(inside)}, clear {len(clear)} '
          f'(committed {sum(r["chosen"] for r in clear)})')
    print('| signal | turns started inside | clear turns | clear turns committed |')
    print('|---|---|---|---|')

    def line(name, fires):
        print(f'| {name} | {sum(map(fires, inside))} of {len(inside)} | {sum(map(fires, clear))} of {len(clear)} '
              f'| {sum(fires(r) and r["chosen"] for r in clear)} of {sum(r["chosen"] for r in clear)} |')
    for n in (1, 10, 100):
        line(f'start_occupied >= {n}', lambda r, n=n: r['start_occupied'] >= n)
    for n in (1, 5, 10):
        line(f'contact >= {n}', lambda r, n=n: r['contact'] >= n)


if __name__ == '__main__':
    main()
