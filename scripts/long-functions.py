#!/usr/bin/python3
"""long-functions.py - the C functions and source files longer than a reader can hold: no
function over 80 lines and no file over 800, without exceptions.

    scripts/long-functions.py [--max N] [--max-file N] [--strict] [--exclude PATH] [PATH ...]
    # PATHs default to src/, cli/, include/ and tests/

Lists every function of the .c/.cu/.h files whose body, from its signature's first line to
its closing brace, is over --max lines (80), longest first, as "LINES FILE:LINE NAME", then
every .c/.cu/.cpp/.h file over --max-file lines (800) as "LINES FILE". The public header
include/brume.h, the whole API in one place, has no file limit. --exclude leaves out a file
or folder (repeatable). --strict exits 1 when anything is over.

Functions are found the way the tree writes them (clang-format's style): a signature that
starts in column 0 and a body that ends with a "}" in column 0."""
import argparse
import os
import re
import sys

SIG = re.compile(r'^[A-Za-z_][\w \*]*?\b(\w+)\s*\(')
ATTR = re.compile(r'__attribute__\s*\(\(.*?\)\)\s*')  # not a function's name
SKIP = ('typedef', 'struct', 'enum', 'union', '#', 'extern "C" {')
FUNCTION_FILES = ('.c', '.cu', '.h')
SOURCE_FILES = ('.c', '.cu', '.cpp', '.h')
NO_FILE_LIMIT = ('include/brume.h',)


def functions(lines):
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
        yield m.group(1), i + 1, k - i + 1
        i = k + 1


def sources(paths, excluded):
    files = []
    for p in paths:
        if os.path.isdir(p):
            for d, dirs, names in os.walk(p):
                dirs[:] = sorted(x for x in dirs if os.path.abspath(os.path.join(d, x)) not in excluded)
                files += [os.path.join(d, n) for n in names if n.endswith(SOURCE_FILES)]
        else:
            files.append(p)
    return sorted(f for f in files if os.path.abspath(f) not in excluded)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--max', type=int, default=80, help='lines a function may have (80)')
    ap.add_argument('--max-file', type=int, default=800, help='lines a file may have (800)')
    ap.add_argument('--strict', action='store_true', help='exit 1 when anything is over')
    ap.add_argument('--exclude', action='append', default=[], help='a file or folder to leave out')
    ap.add_argument('paths', nargs='*')
    a = ap.parse_args()
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    paths = a.paths or [os.path.join(root, d) for d in ('src', 'cli', 'include', 'tests')]
    excluded = {os.path.abspath(e) for e in a.exclude}
    long_, big = [], []
    for f in sources(paths, excluded):
        with open(f, encoding='utf-8', errors='replace') as fh:
            lines = fh.read().split('\n')
        if lines and lines[-1] == '':
            lines.pop()
        rel = os.path.relpath(os.path.abspath(f), root)
        if len(lines) > a.max_file and rel not in NO_FILE_LIMIT:
            big.append((len(lines), rel))
        if f.endswith(FUNCTION_FILES):
            long_ += [(n, rel, line, name) for name, line, n in functions(lines) if n > a.max]
    long_.sort(key=lambda t: (-t[0], t[1]))
    big.sort(key=lambda t: (-t[0], t[1]))
    for n, f, line, name in long_:
        print(f'{n:5d} {f}:{line} {name}')
    for n, f in big:
        print(f'{n:5d} {f}')
    print(f'{len(long_)} functions over {a.max} lines, {len(big)} files over {a.max_file} lines')
    return 1 if a.strict and (long_ or big) else 0


if __name__ == '__main__':
    sys.exit(main())
