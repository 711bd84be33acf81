#!/usr/bin/python3
"""Checks the layering of the libraries: a file of layer L (include/valerant/L/..., src/L/...)
may include "valerant/X/..." only for X = L or a layer below L in the order that
cmake/valerant_layers.cmake writes down (passed here with --layers, lowest first).
Nodes (src/nodes), tools (src/tools) and tests sit on top and are not checked.

  check_layers.py --source DIR --layers common,config,... [--xml FILE]
  check_layers.py --source DIR --graph   # prints which folder includes which, and how often

One test case per layer, one for directories that belong to no layer, and one that
runs the check on a made-up tree with a wrong include, so a check that passes
everything fails. Exit status 1 when any case fails.
"""
import argparse
import pathlib
import re
import sys
import tempfile
import xml.etree.ElementTree as ET

INCLUDE = re.compile(r'^\s*#\s*include\s+"valerant/([^/"]+)/[^"]*"')
# Folders of src/ that are programs on top of every layer, not layers.
PROGRAMS = {"nodes", "tools"}


def layer_files(source, layer):
    """Every header and source file of one layer."""
    files = []
    for folder in (source / "include" / "valerant" / layer, source / "src" / layer):
        if folder.is_dir():
            files += [p for p in sorted(folder.rglob("*")) if p.suffix in (".h", ".hpp", ".cpp")]
    return files


def upward_includes(source, layers, layer):
    """'file:line includes valerant/X/... (layer X is above L)' for every include of
    `layer` that names a higher layer or no layer at all."""
    rank = {name: i for i, name in enumerate(layers)}
    problems = []
    for path in layer_files(source, layer):
        for number, line in enumerate(path.read_text(errors="replace").splitlines(), 1):
            match = INCLUDE.match(line)
            if not match:
                continue
            target = match.group(1)
            where = f"{path.relative_to(source)}:{number}"
            if target not in rank:
                problems.append(f"{where} includes {line.strip()[9:]}: '{target}' is no layer")
            elif rank[target] > rank[layer]:
                problems.append(f"{where} includes {line.strip()[9:]}: layer '{target}' is above '{layer}'")
    return problems


def include_graph(source):
    """'A -> B: n' for every folder A of include/valerant and src that includes headers of
    another folder B, n the number of such include lines."""
    counts = {}
    roots = [source / "include" / "valerant", source / "src"]
    for root in roots:
        for path in sorted(root.rglob("*")):
            if path.suffix not in (".h", ".hpp", ".cpp"):
                continue
            folder = path.relative_to(root).parts[0]
            for line in path.read_text(errors="replace").splitlines():
                match = INCLUDE.match(line)
                if match and match.group(1) != folder:
                    counts[(folder, match.group(1))] = counts.get((folder, match.group(1)), 0) + 1
    return [f"{a} -> {b}: {n}" for (a, b), n in sorted(counts.items())]


def stray_folders(source, layers):
    """Library folders that belong to no layer (their files would escape the check)."""
    stray = []
    include_root = source / "include" / "valerant"
    for folder in sorted(p for p in include_root.iterdir() if p.is_dir()):
        if folder.name not in layers:
            stray.append(f"{folder.relative_to(source)} is in no layer")
    for folder in sorted(p for p in (source / "src").iterdir() if p.is_dir()):
        if folder.name not in layers and folder.name not in PROGRAMS:
            stray.append(f"{folder.relative_to(source)} is in no layer")
    return stray


def catches_a_wrong_include():
    """The check itself on a two-layer tree whose lower layer includes the upper one."""
    with tempfile.TemporaryDirectory() as tmp:
        root = pathlib.Path(tmp)
        for layer in ("low", "high"):
            (root / "include" / "valerant" / layer).mkdir(parents=True)
            (root / "src" / layer).mkdir(parents=True)
        (root / "include" / "valerant" / "high" / "up.h").write_text("#pragma once\n")
        (root / "src" / "low" / "down.cpp").write_text('#include "valerant/high/up.h"\n')
        found = upward_includes(root, ["low", "high"], "low")
        if found == ["src/low/down.cpp:1 includes \"valerant/high/up.h\": layer 'high' is above 'low'"]:
            return []
        return [f"a lower layer including a higher one gave {found}"]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--source", required=True, type=pathlib.Path, help="the package's source folder")
    parser.add_argument("--layers", help="the layers, lowest first, comma-separated")
    parser.add_argument("--graph", action="store_true", help="print the include graph instead of checking")
    parser.add_argument("--xml", type=pathlib.Path, help="write JUnit XML here")
    args = parser.parse_args()
    if not (args.source / "include" / "valerant").is_dir():
        parser.error(f"--source '{args.source}': has no include/valerant")
    if args.graph:
        print("\n".join(include_graph(args.source)))
        return 0
    if args.layers is None:
        parser.error("--layers is required unless --graph is given")
    layers = [name for name in args.layers.split(",") if name]
    if not layers or len(set(layers)) != len(layers):
        parser.error(f"--layers '{args.layers}': needs distinct layer names")

    cases = [(f"{layer}_includes_no_higher_layer", upward_includes(args.source, layers, layer)) for layer in layers]
    cases.append(("every_library_folder_is_a_layer", stray_folders(args.source, layers)))
    cases.append(("the_check_catches_a_wrong_include", catches_a_wrong_include()))

    suite = ET.Element("testsuite", name="layers", tests=str(len(cases)),
                       failures=str(sum(1 for _, problems in cases if problems)), errors="0")
    for name, problems in cases:
        case = ET.SubElement(suite, "testcase", classname="layers", name=name)
        if problems:
            failure = ET.SubElement(case, "failure", message=f"{len(problems)} include(s) break the layer order")
            failure.text = "\n".join(problems)
            print(f"FAILED {name}:", *problems, sep="\n  ", file=sys.stderr)
    if args.xml:
        args.xml.parent.mkdir(parents=True, exist_ok=True)
        ET.ElementTree(suite).write(args.xml, encoding="utf-8", xml_declaration=True)
    failed = sum(1 for _, problems in cases if problems)
    print(f"layers {' < '.join(layers)}: {len(cases) - failed} passed, {failed} failed", file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
