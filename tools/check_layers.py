#!/usr/bin/env python3
"""Checks that every #include in the source tree follows the layers of
docs/architecture.md: a room may include only itself and the rooms below it.

  tools/check_layers.py            check; list every include that points up or across
  tools/check_layers.py --dot F    also write the room-level include graph (Graphviz DOT)
  tools/check_layers.py --table    print which room includes which, with counts

Exit status: 0 when every include is allowed, 1 when any is not, 2 on usage errors.
"""
import argparse
import collections
import os
import re
import sys

# Each room and the rooms it stands on directly; what a room may include is
# everything reachable downwards from it. Longest path prefix wins.
BELOW = {
    "codec/base": [],
    "codec": ["codec/base"],
    "container": ["codec"],
    "player/decoder": ["container"],
    "player/render": ["player/playback"],
    "player/playback": ["player/decoder"],  # the loop drives the C API; the policy alone sees numbers
    "player/export": ["player/decoder"],
    "player/web": ["player/playback"],  # the decoder library and the fetch policy in WebAssembly
    "encoder/io": ["codec/base"],
    "encoder/body": ["container", "encoder/io"],
    "encoder/import": ["encoder/body"],
    "encoder/capture": ["container", "encoder/io"],
    "encoder/track": ["encoder/capture", "encoder/body"],
    "encoder/shape": ["encoder/track"],
    "encoder/atlas": ["encoder/body"],
    "encoder/encode": ["encoder/shape", "encoder/atlas", "encoder/import"],
    "conformance/lib": ["player/decoder", "encoder/io"],
    "conformance/sample": ["container", "encoder/io"],
    "conformance/generator": ["conformance/lib", "conformance/sample"],
    "tools/synth": ["encoder/encode", "player/render", "conformance/sample"],
    "tools/play": ["player/render", "player/playback", "encoder/io"],
    "tools/web": ["conformance/lib"],  # the conformance decoder built for Node too
    "tools/fvv": ["tools/synth", "tools/play", "conformance/generator", "player/export"],
    "tests": ["tools/fvv", "fuzz"],  # the robustness tests share fuzz/decode_all
    "bench": ["tools/fvv"],
    "fuzz": ["tools/fvv"],
}
# The public C API (include/fvv/): the status codes and types are everyone's;
# the decoder's header from the decoder library up, the encoder's from the
# encoder session up.
PUBLIC = {
    "fvv/fvv_types.h": "codec/base",
    "fvv/fvv_decoder.h": "player/decoder",
    "fvv/fvv_decoder.hpp": "player/decoder",
    "fvv/fvv_export.h": "player/export",
    "fvv/fvv_encoder.h": "encoder/encode",
    "fvv/fvv_encoder.hpp": "encoder/encode",
}
SOURCE_DIRS = ["codec", "container", "player", "encoder", "conformance", "tools", "tests",
               "bench", "fuzz", "include"]
EXTENSIONS = (".h", ".hpp", ".cc", ".c")
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def closure():
    allowed = {}
    for room in BELOW:
        seen, stack = {room}, [room]
        while stack:
            for lower in BELOW[stack.pop()]:
                if lower not in seen:
                    seen.add(lower)
                    stack.append(lower)
        allowed[room] = seen
    return allowed


def room_of(path):
    """The room of a repository path (longest prefix), or None outside the rooms."""
    if path.startswith("include/"):
        return "include"
    best = None
    for room in BELOW:
        if path == room or path.startswith(room + "/"):
            if best is None or len(room) > len(best):
                best = room
    return best


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--root", default=os.path.join(os.path.dirname(__file__), ".."))
    parser.add_argument("--dot", metavar="FILE", help="write the room graph as Graphviz DOT")
    parser.add_argument("--table", action="store_true", help="print the room-level includes")
    args = parser.parse_args()
    root = os.path.abspath(args.root)
    allowed = closure()
    edges = collections.Counter()
    violations, unknown, files = [], [], 0
    for top in SOURCE_DIRS:
        for dirpath, dirnames, filenames in os.walk(os.path.join(root, top)):
            # Data, and the npm packages tools/web installs (not ours).
            dirnames[:] = [d for d in dirnames
                           if d not in ("cases", "corpus", "regressions", "node_modules")]
            for name in sorted(filenames):
                if not name.endswith(EXTENSIONS):
                    continue
                rel = os.path.relpath(os.path.join(dirpath, name), root)
                src = room_of(rel)
                if src is None:
                    unknown.append(f"{rel}: in no room (add it to BELOW in tools/check_layers.py)")
                    continue
                files += 1
                with open(os.path.join(root, rel), encoding="utf-8") as f:
                    text = f.read()
                for line_no, inc in ((text.count("\n", 0, m.start()) + 1, m.group(1))
                                     for m in INCLUDE.finditer(text)):
                    if inc in PUBLIC:
                        dst = PUBLIC[inc]
                        label = "include"
                    else:
                        dst = room_of(inc)
                        label = dst
                        if dst is None:
                            if inc.split("/")[0] not in SOURCE_DIRS:
                                continue  # a third-party header included with quotes
                            if os.path.exists(os.path.join(dirpath, inc)):
                                continue  # a file beside it
                            unknown.append(f"{rel}:{line_no}: includes {inc}, in no room")
                            continue
                    if src == "include":
                        continue  # public headers include each other only
                    if label != src:
                        edges[(src, label)] += 1
                    if dst not in allowed[src]:
                        violations.append(f"{rel}:{line_no}: {src} includes {inc} ({dst})")
    if args.table:
        for (src, dst), n in sorted(edges.items()):
            print(f"{src:24} -> {dst:24} {n}")
    if args.dot:
        with open(args.dot, "w", encoding="utf-8") as f:
            f.write("digraph fvv_layers {\n  rankdir=BT;\n  node [shape=box];\n")
            for (src, dst), n in sorted(edges.items()):
                f.write(f'  "{src}" -> "{dst}" [label="{n}"];\n')
            f.write("}\n")
    for v in unknown + violations:
        print(v, file=sys.stderr)
    if unknown or violations:
        print(f"check_layers: {len(violations)} include(s) against the layers, "
              f"{len(unknown)} outside any room (docs/architecture.md)", file=sys.stderr)
        return 1
    print(f"check_layers: {files} files, {sum(edges.values())} includes across rooms, "
          "none against the layers")
    return 0


if __name__ == "__main__":
    sys.exit(main())
