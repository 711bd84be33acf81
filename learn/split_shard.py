#!/usr/bin/env python3
"""Splits a valerant_dataset shard into parts small enough for one call to the GPU
host (a call carries 64 MiB with the working tree), cutting only between sequences.

  split_shard.py SHARD --parts N --out-dir DIR    # writes DIR/<name>-<i>.zip, i = 0..N-1

The images are copied byte for byte; frames.csv is renumbered and meta.json keeps
every field, its maps narrowed to each part's. Each part loads with
shards.load_shards like any shard."""
import argparse
import csv
import io
import json
import os
import sys
import zipfile


from valerant_learn.shards import FRAME_COLUMNS, depth_name, load_shards, rgb_name


def sequence_starts(maps, sequences):
    """Row indices where a new (map, sequence) begins, with 0 and len at the ends."""
    starts = [0] + [i for i in range(1, len(maps)) if (maps[i], sequences[i]) != (maps[i - 1], sequences[i - 1])]
    return starts + [len(maps)]


def cut_points(starts, parts):
    """`parts`+1 row indices from `starts` (sorted, first 0, last N) nearest the equal
    split, strictly increasing; ValueError when there are fewer sequences than parts."""
    if len(starts) - 1 < parts:
        raise ValueError("%d sequences cannot make %d parts" % (len(starts) - 1, parts))
    total, cuts = starts[-1], [0]
    for k in range(1, parts):
        target = total * k / parts
        allowed = [s for s in starts[1:-1] if s > cuts[-1] and len([t for t in starts if t > s]) >= parts - k]
        cuts.append(min(allowed, key=lambda s: abs(s - target)))
    return cuts + [total]


def write_part(source, path, meta, rows, first, last):
    text = io.StringIO()
    writer = csv.writer(text, lineterminator="\n")
    writer.writerow(FRAME_COLUMNS)
    for new, row in enumerate(rows[first:last]):
        writer.writerow([new] + row[1:])
    part_meta = dict(meta, maps=sorted({row[1] for row in rows[first:last]}))
    temporary = path + ".partial"
    with zipfile.ZipFile(temporary, "w", zipfile.ZIP_DEFLATED) as archive:
        archive.writestr("meta.json", json.dumps(part_meta, indent=1))
        archive.writestr("frames.csv", text.getvalue())
        for new, old in enumerate(range(first, last)):
            archive.writestr(rgb_name(new), source.read(rgb_name(old)), zipfile.ZIP_STORED)
            archive.writestr(depth_name(new), source.read(depth_name(old)), zipfile.ZIP_STORED)
    os.replace(temporary, path)


def split_shard(path, parts, out_dir):
    """Writes the parts; returns their paths. Raises ValueError on a bad shard."""
    load_shards([path])  # checks every entry before anything is written
    with zipfile.ZipFile(path) as source:
        meta = json.loads(source.read("meta.json"))
        rows = list(csv.reader(io.StringIO(source.read("frames.csv").decode())))[1:]
        starts = sequence_starts([row[1] for row in rows], [row[3] for row in rows])
        cuts = cut_points(starts, parts)
        os.makedirs(out_dir, exist_ok=True)
        stem = os.path.splitext(os.path.basename(path))[0]
        written = []
        for k in range(parts):
            written.append(os.path.join(out_dir, "%s-%d.zip" % (stem, k)))
            write_part(source, written[-1], meta, rows, cuts[k], cuts[k + 1])
    return written


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("shard")
    parser.add_argument("--parts", type=int, required=True)
    parser.add_argument("--out-dir", required=True)
    args = parser.parse_args(argv)
    if args.parts < 1:
        parser.error("--parts must be at least 1")
    try:
        for path in split_shard(args.shard, args.parts, args.out_dir):
            print("%s: %.1f MiB" % (path, os.path.getsize(path) / 2 ** 20))
    except ValueError as error:
        sys.exit("split_shard: error: %s" % error)
    return 0


if __name__ == "__main__":
    sys.exit(main())
