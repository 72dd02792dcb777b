#!/usr/bin/env python3
"""Fails if the #include "..." lines form a cycle.

usage: include_cycles.py [SOURCE_DIR] [--concepts-everywhere]

Two checks over host/, shaders/, tests/ and bench/:
  - headers (.h, .glsl): no header may include itself through others;
  - concepts under host/render/ and host/methods/ (the registry and the methods): a header and
    its source count as one (pmc_hi.h and pmc_hi.cpp), so methods/pmc_hi/pmc_hi.h including
    render/methods.h while methods.cpp includes pmc_hi.h is a cycle too: the registry depends
    on every method, so no method may depend on the registry.
--concepts-everywhere applies the second check to every folder (informational: image/ and vk/
hold such pairs of concepts that use each other).

An include is resolved as the compilers do: beside the including file, then under the include
roots (host/ and shaders/, tests/testing/ for the tests); one that resolves to no file (a system
header written with quotes) is skipped."""
import os
import re
import sys

INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)
SOURCES = (".h", ".hpp", ".cpp", ".glsl", ".comp")
HEADERS = (".h", ".hpp", ".glsl")
CONCEPT_FOLDERS = ("host/render/", "host/methods/")


def find_cycles(graph):
    """Every cycle closed by a back edge of a depth-first search over `graph`."""
    cycles, state = [], {}
    for start in sorted(graph):
        if state.get(start):
            continue
        state[start] = "open"
        path, stack = [start], [(start, iter(graph[start]))]
        while stack:
            node, edges = stack[-1]
            nxt = next(edges, None)
            if nxt is None:
                state[node] = "done"
                stack.pop()
                path.pop()
            elif state.get(nxt) == "open":
                cycles.append(path[path.index(nxt):] + [nxt])
            elif not state.get(nxt):
                state[nxt] = "open"
                path.append(nxt)
                stack.append((nxt, iter(graph.get(nxt, []))))
    return cycles


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    everywhere = "--concepts-everywhere" in sys.argv
    root = os.path.abspath(args[0] if args else os.path.join(os.path.dirname(__file__), ".."))
    roots = [os.path.join(root, d) for d in ("host", "shaders", "tests/testing")]

    # file -> the files it includes, as paths relative to the root
    includes = {}
    for top in ("host", "shaders", "tests", "bench"):
        for dirpath, _, names in os.walk(os.path.join(root, top)):
            for name in sorted(n for n in names if n.endswith(SOURCES)):
                f = os.path.join(dirpath, name)
                targets = []
                with open(f, encoding="utf-8") as text:
                    for inc in INCLUDE.findall(text.read()):
                        for base in [os.path.dirname(f)] + roots:
                            path = os.path.normpath(os.path.join(base, inc))
                            if os.path.isfile(path):
                                targets.append(os.path.relpath(path, root))
                                break
                includes[os.path.relpath(f, root)] = targets

    headers = {f: [t for t in ts if t.endswith(HEADERS)] for f, ts in includes.items()
               if f.endswith(HEADERS)}

    def concept(path):
        return os.path.splitext(path)[0]

    def in_scope(path):
        return everywhere or path.startswith(CONCEPT_FOLDERS)

    concepts = {}
    for f, ts in includes.items():
        if in_scope(f):
            node = concepts.setdefault(concept(f), [])
            node += [concept(t) for t in ts if in_scope(t) and concept(t) != concept(f)]

    cycles = [("header", c) for c in find_cycles(headers)]
    cycles += [("concept", c) for c in find_cycles(concepts)]
    for kind, cycle in cycles:
        print(f"{kind} include cycle: " + " -> ".join(cycle))
    if cycles:
        return 1
    print(f"no include cycles ({len(includes)} files; {len(headers)} headers; "
          f"{len(concepts)} concepts in {'every folder' if everywhere else ' and '.join(CONCEPT_FOLDERS)})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
