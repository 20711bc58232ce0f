#!/usr/bin/python3
"""long-functions.py - the C functions in src/ longer than a screen (issue 33: "no function
over ~100 lines without a reason in a comment").

    scripts/long-functions.py [--max N] [--strict] [PATH ...]   # PATHs default to src/ and cli/

Lists every function of the .c/.cu/.h files whose body, from its signature's first line to
its closing brace, is over N lines (100), longest first, as "LINES FILE:LINE NAME", marked
"(reason given)" when the comment right above the signature holds a line starting with
"Long:" that says why it stays whole. --strict exits 1 when any long function has no reason.

Functions are found the way the tree writes them (clang-format's style): a signature that
starts in column 0 and a body that ends with a "}" in column 0."""
import argparse
import os
import re
import sys

SIG = re.compile(r'^[A-Za-z_][\w \*]*?\b(\w+)\s*\(')
ATTR = re.compile(r'__attribute__\s*\(\(.*?\)\)\s*')  # not a function's name
SKIP = ('typedef', 'struct', 'enum', 'union', '#', 'extern "C" {')


def functions(path):
    with open(path, encoding='utf-8', errors='replace') as f:
        lines = f.read().split('\n')
    i = 0
    while i < len(lines):
        m = SIG.match(ATTR.sub('', lines[i]))
        if not m or lines[i].startswith(SKIP) or lines[i].rstrip().endswith(';'):
            i += 1
            continue
        # the signature may span lines; a body opens before any ';'
        j = i
        while j < len(lines) and '{' not in lines[j] and not lines[j].rstrip().endswith(';'):
            j += 1
        if j >= len(lines) or '{' not in lines[j]:
            i = j + 1
            continue
        if lines[j].rstrip().endswith('}') and lines[j].count('{') == lines[j].count('}'):
            i = j + 1  # a one-line body
            continue
        k = j + 1
        while k < len(lines) and not lines[k].startswith('}'):
            k += 1
        yield m.group(1), i + 1, k - i + 1, reason(lines, i)
        i = k + 1


def reason(lines, i):
    """True when the comment right above line i has a line starting with 'Long:'."""
    j = i - 1
    while j >= 0 and lines[j].strip() and not lines[j].rstrip().endswith('*/'):
        j -= 1  # a declaration's earlier lines (attributes, a split signature)
    if j < 0 or not lines[j].rstrip().endswith('*/'):
        return False
    while j >= 0:
        text = lines[j].strip().lstrip('/*').strip()
        if text.startswith('Long:'):
            return True
        if lines[j].lstrip().startswith('/*'):
            return False
        j -= 1
    return False


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--max', type=int, default=100)
    ap.add_argument('--strict', action='store_true')
    ap.add_argument('paths', nargs='*')
    a = ap.parse_args()
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    paths = a.paths or [os.path.join(root, 'src'), os.path.join(root, 'cli')]
    files = []
    for p in paths:
        if os.path.isdir(p):
            for d, _, names in os.walk(p):
                files += [os.path.join(d, n) for n in names if n.endswith(('.c', '.cu', '.h'))]
        else:
            files.append(p)
    long_ = []
    for f in sorted(files):
        for name, line, n, why in functions(f):
            if n > a.max:
                long_.append((n, os.path.relpath(f, root), line, name, why))
    long_.sort(key=lambda t: (-t[0], t[1]))
    for n, f, line, name, why in long_:
        print(f'{n:5d} {f}:{line} {name}' + ('  (reason given)' if why else ''))
    bare = [t for t in long_ if not t[4]]
    print(f'{len(long_)} functions over {a.max} lines, {len(bare)} without a reason')
    return 1 if a.strict and bare else 0


if __name__ == '__main__':
    sys.exit(main())
