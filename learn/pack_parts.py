#!/usr/bin/env python3
"""Packs shard folders into parts that each fit one call to the GPU host.

A call carries the working tree and the folders named in `carry`, 64 MiB in all, so
the data of one call must stay under 64 MiB less the working tree. Every shard larger
than a third of the limit is first cut at sequence boundaries (split_shard.py) into
the fewest pieces of at most a third of it, so that parts fill well; then the pieces
go, largest first, into the first part with room (first-fit decreasing), each under
OUT/pNN/<its folder's name>/ as a hard link (the bytes are stored once).
learn/gpu_train.sh stages OUT/pNN with `DATA=OUT/pNN`, one call a part.

  pack_parts.py --limit-mib 30 --out data/depth_parts data/train_a data/train_b ... data/eval

Folder names must be train_* or eval (what gpu_train.sh stages); prints one line a part."""
import argparse
import glob
import math
import os
import shutil
import sys

from split_shard import split_shard

MIB = 2 ** 20


def first_fit_decreasing(sizes, limit):
    """Bins of indices into `sizes` (each at most `limit`), filled largest first,
    each item into the first bin with room. ValueError for an item over the limit."""
    bins, loads = [], []
    for index in sorted(range(len(sizes)), key=lambda i: -sizes[i]):
        if sizes[index] > limit:
            raise ValueError("an item of %d bytes exceeds the limit of %d" % (sizes[index], limit))
        for slot, load in enumerate(loads):
            if load + sizes[index] <= limit:
                bins[slot].append(index)
                loads[slot] += sizes[index]
                break
        else:
            bins.append([index])
            loads.append(sizes[index])
    return bins


def pieces_of(folder, piece_limit, work_dir):
    """The folder's shards, those over piece_limit cut into enough parts (in work_dir)."""
    pieces = []
    for shard in sorted(glob.glob(os.path.join(folder, "*.zip"))):
        parts = math.ceil(os.path.getsize(shard) / piece_limit)
        pieces += [shard] if parts == 1 else split_shard(shard, parts, work_dir)
    if not pieces:
        raise ValueError("%s holds no shard (*.zip)" % folder)
    return pieces


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("folders", nargs="+", help="shard folders named train_* or eval")
    parser.add_argument("--limit-mib", type=float, required=True, help="most MiB of data in one part")
    parser.add_argument("--out", required=True, help="folder of the parts (replaced)")
    args = parser.parse_args(argv)
    if not args.limit_mib > 0:
        parser.error("--limit-mib must be positive")
    limit = int(args.limit_mib * MIB)
    try:
        names = [os.path.basename(os.path.normpath(folder)) for folder in args.folders]
        for folder, name in zip(args.folders, names):
            if not os.path.isdir(folder):
                raise ValueError("%s is not a folder" % folder)
            if name != "eval" and not name.startswith("train_"):
                raise ValueError("%s: gpu_train.sh stages only folders named train_* or eval" % folder)
        if len(set(names)) != len(names):
            raise ValueError("two folders share a name: %s" % ", ".join(names))
        shutil.rmtree(args.out, ignore_errors=True)
        pieces = []  # (folder name, path)
        for folder, name in zip(args.folders, names):
            work_dir = os.path.join(args.out, "pieces", name)  # the cut shards; the parts link to them
            pieces += [(name, path) for path in pieces_of(folder, limit // 3, work_dir)]
        bins = first_fit_decreasing([os.path.getsize(path) for _, path in pieces], limit)
        for number, members in enumerate(bins, 1):
            part = os.path.join(args.out, "p%02d" % number)
            for index in members:
                name, path = pieces[index]
                os.makedirs(os.path.join(part, name), exist_ok=True)
                os.link(path, os.path.join(part, name, os.path.basename(path)))
            print("%s: %d shards, %.1f MiB" % (part, len(members),
                                                sum(os.path.getsize(pieces[i][1]) for i in members) / MIB))
    except (ValueError, OSError) as error:
        sys.exit("pack_parts: error: %s" % error)
    return 0


if __name__ == "__main__":
    sys.exit(main())
