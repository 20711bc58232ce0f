#!/usr/bin/env python3
"""arch_includes.py - the folders of src/ include in one direction only.

Reads the layer order from docs/architecture.md (the fenced block after "Layers, lowest
first") and every #include "FOLDER/FILE" line of src/, cli/ and python/'s C sources; fails,
naming the file and line, when a file includes a folder above its own, when the doc's list
misses a folder of src/, or when cli/ includes a private header other than the ones the doc
allows. Usage: arch_includes.py [REPO]   (default: the folder above this script's)."""
import os
import re
import sys

root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
doc = open(os.path.join(root, "docs", "architecture.md"), encoding="utf-8").read()
m = re.search(r"Layers, lowest first[^\n]*\n+```[^\n]*\n(.*?)```", doc, re.S)
if not m:
    sys.exit("docs/architecture.md: no fenced block after 'Layers, lowest first'")
order = []
for line in m.group(1).splitlines():
    line = line.split("#")[0].strip()
    if line:
        order.append(line.split()[0].rstrip("/"))
rank = {d: i for i, d in enumerate(order)}
m = re.search(r"cli/ may include[^\n]*\n+```[^\n]*\n(.*?)```", doc, re.S)
cli_allowed = set(l.strip() for l in m.group(1).splitlines() if l.strip()) if m else set()

errors = []
src = os.path.join(root, "src")
folders = sorted(d for d in os.listdir(src) if os.path.isdir(os.path.join(src, d)))
for d in folders:
    if d not in rank:
        errors.append(f"docs/architecture.md: folder src/{d}/ is not in the layer list")
inc = re.compile(r'^\s*#\s*include\s+"([^"]+)"')
checked = 0


def includes(path):
    with open(path, encoding="utf-8", errors="replace") as f:
        for no, line in enumerate(f, 1):
            mm = inc.match(line)
            if mm:
                yield no, mm.group(1)


for d in folders:
    for name in sorted(os.listdir(os.path.join(src, d))):
        if not name.endswith((".c", ".h", ".cpp", ".cu")):
            continue
        path = os.path.join(src, d, name)
        for no, target in includes(path):
            checked += 1
            if "/" not in target:
                continue
            top = target.split("/")[0]
            if top not in rank:
                errors.append(f"src/{d}/{name}:{no}: includes {target}: folder '{top}' is in no layer")
            elif d in rank and rank[top] > rank[d]:
                errors.append(f"src/{d}/{name}:{no}: includes {target}: {top}/ is above {d}/ "
                              f"(docs/architecture.md)")
cli = os.path.join(root, "cli")
for name in sorted(os.listdir(cli)):
    if not name.endswith((".c", ".h")):
        continue
    for no, target in includes(os.path.join(cli, name)):
        checked += 1
        if "/" in target and target not in cli_allowed:
            errors.append(f"cli/{name}:{no}: includes {target}: cli/ uses include/brume.h and the "
                          f"internal headers docs/architecture.md allows")
for e in errors:
    print(e)
print(f"{checked} includes checked, {len(errors)} climb or stray")
sys.exit(1 if errors else 0)
