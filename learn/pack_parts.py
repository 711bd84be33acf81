#!/usr/bin/env python3
"""Packs shard folders into parts that each fit one call to the GPU host.

A call carries the working tree and the folders named in `carry`, 64 MiB in all, so
the data of one call must stay under 64 MiB less the working tree. Without --limit-mib
the limit is 64 MiB less the tracked files (git ls-files) less 4 MiB of headroom for
what later commits add: fixed limits broke once the tree grew from 35 to 40 MiB and
27 MiB parts no longer fitted. Every shard larger
than a third of the limit is first cut at sequence boundaries (split_shard.py) into
the fewest pieces of at most a third of it, so that parts fill well; then the pieces
go, largest first, into the first part with room (first-fit decreasing), each under
OUT/pNN/<its folder's name>/ as a hard link (the bytes are stored once; the cut
pieces' own folder is removed at the end, the links keep their bytes).
learn/gpu_train.sh stages OUT/pNN with `DATA=OUT/pNN`, one call a part.

  pack_parts.py --out data/depth_parts data/train_a data/train_b ... data/eval

Folder names must be train_* or eval (what gpu_train.sh stages); prints one line a part."""
import argparse
import glob
import math
import os
import shutil
import subprocess
import sys

from split_shard import split_shard

MIB = 2 ** 20
CALL_MIB = 64  # what one call to the GPU host carries: the working tree and the data
HEADROOM_MIB = 4  # for files later commits add to the tree


def part_limit_mib(tree_bytes):
    """MiB of data one part may hold beside a working tree of tree_bytes."""
    return CALL_MIB - tree_bytes / MIB - HEADROOM_MIB


def tracked_bytes(repository):
    """Bytes of the files git tracks in the repository (the working tree a call carries)."""
    listing = subprocess.run(["git", "-C", repository, "ls-files", "-z"], check=True, capture_output=True).stdout
    paths = [os.path.join(repository, name) for name in listing.decode().split("\0") if name]
    return sum(os.path.getsize(path) for path in paths if os.path.isfile(path))


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
    parser.add_argument("--limit-mib", type=float,
                        help="most MiB of data in one part (default: %d less the tracked files less %d)"
                             % (CALL_MIB, HEADROOM_MIB))
    parser.add_argument("--out", required=True, help="folder of the parts (replaced)")
    args = parser.parse_args(argv)
    try:
        if args.limit_mib is None:
            tree = tracked_bytes(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
            args.limit_mib = part_limit_mib(tree)
            print("limit %.1f MiB a part: the tracked files are %.1f MiB" % (args.limit_mib, tree / MIB))
        if not args.limit_mib > 0:
            raise ValueError("the limit of a part must be positive, got %.1f MiB" % args.limit_mib)
        limit = int(args.limit_mib * MIB)
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
        shutil.rmtree(os.path.join(args.out, "pieces"), ignore_errors=True)
    except (ValueError, OSError, subprocess.CalledProcessError) as error:
        sys.exit("pack_parts: error: %s" % error)
    return 0


if __name__ == "__main__":
    sys.exit(main())
