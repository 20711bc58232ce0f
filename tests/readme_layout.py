#!/usr/bin/env python3
"""readme_layout.py - README's "Layout" section matches the tree.

Reads the section from "## Layout" to the next "## " heading and fails, naming the text,
when:
- a folder in the table's first column (`name/`) does not exist at the top of the tree, or a
  top-level folder of the tree is not named there;
- a folder the `src/` row names (`name/`) is not a folder of src/, or a folder of src/ is
  not named in that row;
- any other path the section names (`scripts/debian-packages.txt`, docs/architecture.md)
  does not exist.
The tree's top-level folders are those git tracks when the source is a git checkout, else
the folders present that are not a build tree (a CMakeCache.txt in them); hidden ones (.ci/)
are left out.
Usage: readme_layout.py [REPO]   (default: the folder above this script's)."""
import os
import re
import subprocess
import sys

root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
text = open(os.path.join(root, "README.md"), encoding="utf-8").read()
m = re.search(r"^## Layout[^\n]*\n(.*?)(?=^## |\Z)", text, re.S | re.M)
if not m:
    sys.exit("README.md: no '## Layout' section")
section = m.group(1)
errors = []


def top_folders():
    try:
        out = subprocess.run(["git", "-C", root, "ls-files"], capture_output=True, text=True, check=True).stdout
        names = {p.split("/")[0] for p in out.splitlines() if "/" in p}
        if names:
            return {n for n in names if not n.startswith(".") and os.path.isdir(os.path.join(root, n))}
    except (OSError, subprocess.CalledProcessError):
        pass
    return {n for n in os.listdir(root) if not n.startswith(".") and os.path.isdir(os.path.join(root, n))
            and not os.path.exists(os.path.join(root, n, "CMakeCache.txt"))}


named_top, named_src = set(), set()
src_row = None
for line in section.splitlines():
    cells = [c.strip() for c in line.strip().strip("|").split("|")] if line.startswith("|") else []
    if len(cells) < 2 or set(cells[0]) <= set("- "):
        continue
    for name in re.findall(r"`([^`]+)/`", cells[0]):
        named_top.add(name)
        if not os.path.isdir(os.path.join(root, name)):
            errors.append(f"README.md, Layout: the folder `{name}/` does not exist")
    if cells[0] == "`src/`":
        src_row = cells[1]
if src_row is None:
    errors.append("README.md, Layout: no row for `src/`")
else:
    for name in re.findall(r"`([\w.-]+)/`", src_row):
        named_src.add(name)
        if not os.path.isdir(os.path.join(root, "src", name)):
            errors.append(f"README.md, Layout: the folder `src/{name}/` does not exist")
    for name in sorted(os.listdir(os.path.join(root, "src"))):
        if os.path.isdir(os.path.join(root, "src", name)) and name not in named_src:
            errors.append(f"README.md, Layout: the folder src/{name}/ is not named in the `src/` row")
for name in sorted(top_folders() - named_top):
    errors.append(f"README.md, Layout: the folder {name}/ is not named in the table")

# any other path: a name with a slash and a file extension, or a folder the src/ row does not
# cover (inside backquotes or not)
for path in sorted(set(re.findall(r"(?<![\w/.-])((?:[\w.-]+/)+[\w.-]+\.[a-z]+)\b", section))):
    if not os.path.exists(os.path.join(root, path)):
        errors.append(f"README.md, Layout: {path} does not exist")

for e in errors:
    print(e)
print(f"README.md, Layout: {len(named_top)} folders and {len(named_src)} folders of src/ checked, "
      f"{len(errors)} problem(s)")
sys.exit(1 if errors else 0)
