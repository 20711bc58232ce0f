#!/usr/bin/env python3
"""arch_links.py - the layers of src/ hold at link level, and no folder's files form a circle.

Reads the layer order from docs/architecture.md (the fenced block after "Layers, lowest
first", as tests/arch_includes.py does) and, with `nm`, the symbols every object of the
library (BUILD/CMakeFiles/brume_objects.dir/**.o) defines and uses. Fails, naming both
objects and the symbol:
  - when an object uses a symbol defined in a layer above its own (an upward call the
    include check cannot see: a function declared by hand, or reached through a header of
    its own folder); ALLOWED below would list exceptions (there are none);
  - when files of one folder depend on each other in a circle, a file being a stem (x.c and
    x.h together, and x_impl.h, x's private layout, with them), a dependency being an #include "folder/y.h" of a file of the same folder
    or a symbol of another object of that folder. The circles are the strongly connected
    components with more than one file; each is printed with the edges that close it.
Prints the two figures (upward references, circles) either way.
Usage: arch_links.py BUILD_DIR [REPO]   or   arch_links.py --self-test"""
import os
import re
import subprocess
import sys

# upward references allowed by name, (object, object): none (the GPU renders passes through
# render/pass.h and knows nothing of the job)
ALLOWED = set()
# objects the build generates, outside src/: their layer
GENERATED = {"default_scene.c": "scene", "gpu_ptx.c": "gpu"}


def layer_order(root):
    doc = open(os.path.join(root, "docs", "architecture.md"), encoding="utf-8").read()
    m = re.search(r"Layers, lowest first[^\n]*\n+```[^\n]*\n(.*?)```", doc, re.S)
    if not m:
        sys.exit("docs/architecture.md: no fenced block after 'Layers, lowest first'")
    order = [l.split("#")[0].split()[0].rstrip("/") for l in m.group(1).splitlines() if l.split("#")[0].strip()]
    return {d: i for i, d in enumerate(order)}


def read_objects(build, root):
    """{'core/bvh.c': (defined set, used set)} for the library's objects (those of sources
    that still exist: a renamed file's old object may linger in the build), from one nm run."""
    top = os.path.join(build, "CMakeFiles", "brume_objects.dir")
    names = {}
    for d, _, files in os.walk(top):
        for f in files:
            if not f.endswith(".o"):
                continue
            rel = os.path.relpath(os.path.join(d, f), top)[:-2]
            if rel.startswith("src/"):
                rel = rel[4:]
                if not os.path.exists(os.path.join(root, "src", rel)):
                    continue
            else:
                rel = os.path.basename(rel)
            names[os.path.join(d, f)] = rel
    objs = {rel: (set(), set()) for rel in names.values()}
    if not names:
        return objs
    out = subprocess.run(["nm", "-P", "-A"] + sorted(names), capture_output=True, text=True, check=True).stdout
    for line in out.splitlines():
        path, _, rest = line.partition(": ")
        parts = rest.split()
        if path not in names or len(parts) < 2:
            continue
        defined, used = objs[names[path]]
        if parts[1] == "U":
            used.add(parts[0])
        elif parts[1] in "TDBRCVWGS":
            defined.add(parts[0])
    return objs


def stem(name):
    """x.c, x.h and x_impl.h are one file of the graph: x."""
    base = os.path.splitext(name)[0]
    return base[:-5] if base.endswith("_impl") else base


def layer_of(obj):
    return GENERATED.get(obj, obj.split("/")[0])


def upward(objs, rank):
    owner = {}
    for o, (defined, _) in objs.items():
        for s in defined:
            owner.setdefault(s, o)
    found = []
    for o, (_, used) in sorted(objs.items()):
        for s in sorted(used):
            d = owner.get(s)
            if not d or (o, d) in ALLOWED:
                continue
            lo, ld = layer_of(o), layer_of(d)
            if lo in rank and ld in rank and rank[ld] > rank[lo]:
                found.append(f"{o} uses {s}, defined in {d}: {ld}/ is above {lo}/ (docs/architecture.md)")
    return found, owner


def file_edges(root, objs, owner):
    """{(folder, stem): {(folder, stem2): reason}} within each folder of src/."""
    edges = {}
    inc = re.compile(r'^\s*#\s*include\s+"([^"/]+)/([^"/]+)"')
    src = os.path.join(root, "src")
    for d in sorted(os.listdir(src)):
        if not os.path.isdir(os.path.join(src, d)):
            continue
        for name in sorted(os.listdir(os.path.join(src, d))):
            if not name.endswith((".c", ".h", ".cpp")):
                continue
            a = (d, stem(name))
            edges.setdefault(a, {})
            with open(os.path.join(src, d, name), encoding="utf-8", errors="replace") as f:
                for no, line in enumerate(f, 1):
                    m = inc.match(line)
                    if m and m.group(1) == d:
                        b = (d, stem(m.group(2)))
                        if b != a:
                            edges[a].setdefault(b, f"src/{d}/{name}:{no} includes {d}/{m.group(2)}")
    for o, (_, used) in sorted(objs.items()):
        if "/" not in o:
            continue
        a = (o.split("/")[0], stem(o.split("/")[1]))
        for s in sorted(used):
            dobj = owner.get(s)
            if not dobj or "/" not in dobj or dobj.split("/")[0] != a[0]:
                continue
            b = (a[0], stem(dobj.split("/")[1]))
            if b != a:
                edges.setdefault(a, {}).setdefault(b, f"{o} uses {s} ({dobj})")
    return edges


def circles(edges):
    """The strongly connected components of more than one node (Tarjan), each sorted."""
    index, low, stack, on, out, counter = {}, {}, [], set(), [], [0]
    nodes = sorted(set(edges) | {b for e in edges.values() for b in e})

    def visit(v):
        work = [(v, iter(sorted(edges.get(v, {}))))]
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        while work:
            u, it = work[-1]
            nxt = next(it, None)
            if nxt is not None:
                if nxt not in index:
                    index[nxt] = low[nxt] = counter[0]
                    counter[0] += 1
                    stack.append(nxt)
                    on.add(nxt)
                    work.append((nxt, iter(sorted(edges.get(nxt, {})))))
                elif nxt in on:
                    low[u] = min(low[u], index[nxt])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[u])
            if low[u] == index[u]:
                comp = []
                while True:
                    w = stack.pop()
                    on.discard(w)
                    comp.append(w)
                    if w == u:
                        break
                if len(comp) > 1:
                    out.append(sorted(comp))

    for v in nodes:
        if v not in index:
            visit(v)
    return sorted(out)


def describe(comp, edges):
    members = set(comp)
    lines = [f"circle in src/{comp[0][0]}/: " + ", ".join(s for _, s in comp)]
    for a in comp:
        for b, why in sorted(edges.get(a, {}).items()):
            if b in members:
                lines.append(f"    {a[1]} -> {b[1]}: {why}")
    return "\n".join(lines)


def check(root, objs):
    rank = layer_order(root)
    up, owner = upward(objs, rank)
    edges = file_edges(root, objs, owner)
    comps = circles(edges)
    for line in up:
        print(line)
    for c in comps:
        print(describe(c, edges))
    print(f"arch_links: {len(objs)} objects, {len(up)} upward symbol references, {len(comps)} file-level circles")
    return len(up), len(comps)


def self_test():
    """The check finds what it is to find, on a made-up tree (so that it can fail)."""
    import tempfile
    with tempfile.TemporaryDirectory() as root:
        os.makedirs(os.path.join(root, "docs"))
        with open(os.path.join(root, "docs", "architecture.md"), "w") as f:
            f.write("Layers, lowest first:\n\n```\ncore\nscene\n```\n")
        for d, name, text in [("core", "a.h", '#include "core/b.h"\n'), ("core", "b.c", ""),
                              ("scene", "s.c", ""), ("core", "c.c", "")]:
            os.makedirs(os.path.join(root, "src", d), exist_ok=True)
            open(os.path.join(root, "src", d, name), "w").write(text)
        objs = {"core/b.c": ({"b_f"}, {"scene_f", "a_f"}), "core/a.c": ({"a_f"}, set()),
                "scene/s.c": ({"scene_f"}, {"b_f"}), "core/c.c": ({"c_f"}, {"b_f"})}
        up, comps = check(root, objs)
        assert (up, comps) == (1, 1), (up, comps)
    print("arch_links: self-test passed (1 upward reference and 1 circle found where they were put)")


if __name__ == "__main__":
    if sys.argv[1:] == ["--self-test"]:
        self_test()
        sys.exit(0)
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    repo = sys.argv[2] if len(sys.argv) > 2 else os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    self_test()
    objs = read_objects(sys.argv[1], repo)
    if not objs:
        sys.exit(f"arch_links: no objects under {sys.argv[1]}/CMakeFiles/brume_objects.dir (build the library first)")
    up, comps = check(repo, objs)
    sys.exit(1 if up or comps else 0)
