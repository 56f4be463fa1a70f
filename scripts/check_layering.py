#!/usr/bin/env python3
"""The include rules of issue 22, checked over the sources (a CTest test runs this).

1. The clouds' simulation (modules/clouds/weather, modules/clouds/gameplay) reaches nothing of the GPU:
   no file there includes, directly or through the project's headers, modules/clouds/render/,
   engine/gpu/, engine/render/graph/ or a Vulkan header.
2. The folders of modules/clouds form no cycle: an include from folder A into folder B and one from B
   (or from what B includes) back into A is a back-edge. The module's root (clouds_module.*) counts as
   a folder of its own.

Prints each violation with the include chain and exits 1; exits 0 when the tree is clean.
"""
import os
import re
import sys

ROOT = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), ".."))
INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]', re.M)
SIMULATION = ("modules/clouds/weather/", "modules/clouds/gameplay/")
FORBIDDEN = ("modules/clouds/render/", "engine/gpu/", "engine/render/graph/")


def includes(path, cache={}):
    if path not in cache:
        out = []
        with open(os.path.join(ROOT, path), encoding="utf-8", errors="replace") as f:
            for kind, name in INCLUDE.findall(f.read()):
                if kind == "<":
                    out.append(("system", name))
                elif os.path.isfile(os.path.join(ROOT, name)):
                    out.append(("project", name))
        cache[path] = out
    return cache[path]


def sources(prefix):
    for d, _, files in os.walk(os.path.join(ROOT, prefix)):
        for f in files:
            if f.endswith((".h", ".cpp")):
                yield os.path.relpath(os.path.join(d, f), ROOT)


def first_forbidden(path):
    """A chain from `path` to a forbidden include (None when there is none), breadth first."""
    seen, queue = {path}, [(path, [path])]
    while queue:
        p, chain = queue.pop(0)
        for kind, name in includes(p):
            if kind == "system":
                if name.startswith("vulkan/") or name == "vulkan.h":
                    return chain + ["<" + name + ">"]
                continue
            if name.startswith(FORBIDDEN):
                return chain + [name]
            if name not in seen:
                seen.add(name)
                queue.append((name, chain + [name]))
    return None


def clouds_folder(path):
    rest = path[len("modules/clouds/"):]
    return rest.split("/")[0] if "/" in rest else "(root)"


def main():
    problems = []
    for prefix in SIMULATION:
        for path in sources(prefix):
            chain = first_forbidden(path)
            if chain:
                problems.append("simulation reaches the GPU: " + " -> ".join(chain))
    edges = {}
    for path in sources("modules/clouds/"):
        a = clouds_folder(path)
        for kind, name in includes(path):
            if kind == "project" and name.startswith("modules/clouds/"):
                b = clouds_folder(name)
                if a != b:
                    edges.setdefault(a, {}).setdefault(b, (path, name))
    # A cycle in the folder graph: for each edge a -> b, is a reachable from b?
    def reach(start, goal):
        seen, stack = {start}, [(start, [])]
        while stack:
            n, via = stack.pop()
            for m, why in edges.get(n, {}).items():
                if m == goal:
                    return via + [why]
                if m not in seen:
                    seen.add(m)
                    stack.append((m, via + [why]))
        return None
    for a, outs in sorted(edges.items()):
        for b, why in sorted(outs.items()):
            back = reach(b, a)
            if back:
                problems.append("modules/clouds folders %s <-> %s: %s includes %s, and back: %s" % (
                    a, b, why[0], why[1], "; ".join("%s includes %s" % w for w in back)))
    for p in problems:
        print(p)
    print("layering: %d problem(s)" % len(problems))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
