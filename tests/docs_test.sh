#!/bin/sh
# docs_test.sh - the docs stay references, each claim with the run that shows it:
#   1. docs/performance.md is under 300 lines (current figures; the history is in git);
#   2. every run log in docs/bench/ is cited by a page, and every docs/bench/ file a page
#      cites exists;
#   3. every table of docs/*.md and README.md renders: a header row, a separator row and
#      body rows with the same number of cells (pipes inside backticks or escaped as \|
#      are not cell borders), and no prose line starts with a pipe;
#   4. every in-page link [text](#anchor) names a heading of that page (GitHub's anchors).
#   docs_test.sh SOURCE_DIR
set -eu
src=$1
cd "$src"
fail=0

# 1
n=$(wc -l < docs/performance.md)
if [ "$n" -ge 300 ]; then
    echo "docs: docs/performance.md has $n lines; a reference stays under 300 (history belongs in git)"
    fail=1
fi

# 2
pages="docs/*.md README.md bench tests scripts"
for f in docs/bench/*; do
    [ -e "$f" ] || continue
    if ! grep -rqF "docs/bench/$(basename "$f")" $pages; then
        echo "docs: $f is cited by no page (git rm it: the history is in git)"
        fail=1
    fi
done
for cited in $(grep -ohE 'docs/bench/[a-z0-9._-]+\.txt' docs/*.md README.md | sort -u); do
    if [ ! -f "$cited" ]; then
        echo "docs: $cited is cited but does not exist"
        fail=1
    fi
done

# 3 and 4
awk '
function ncells(line,    s, i, c, n, tick) {
    s = line
    sub(/^[ \t]*\|/, "", s)
    n = 1; tick = 0
    for (i = 1; i <= length(s); i++) {
        c = substr(s, i, 1)
        if (c == "\\") { i++; continue }
        if (c == "`") tick = !tick
        else if (c == "|" && !tick) n++
    }
    if (s ~ /\|[ \t]*$/ && s !~ /\\\|[ \t]*$/) n--
    return n
}
function slug(h,    s) {
    s = tolower(h)
    sub(/^#+[ \t]*/, "", s)
    gsub(/[^a-z0-9 _-]/, "", s)
    gsub(/ /, "-", s)
    return s
}
function bad(msg) { printf "docs: %s:%d: %s\n", FILENAME, FNR, msg; errors++ }
function checklinks(    k, a) {
    for (k = 1; k <= nlinks; k++) {
        split(links[k], a, SUBSEP)
        if (!(a[1] in anchors)) {
            printf "docs: %s:%d: a link to #%s, which no heading of the page makes\n", file, a[2], a[1]
            errors++
        }
    }
    split("", anchors); split("", links); nlinks = 0
}
FNR == 1 { if (NR > 1) checklinks(); file = FILENAME; fence = 0; prev = ""; rows = 0 }
/^[ \t]*```/ { fence = !fence; prev = $0; rows = 0; next }
fence { next }
/^#+ / { anchors[slug($0)] = 1 }
{
    line = $0
    while (match(line, /\]\(#[^)]*\)/)) {
        links[++nlinks] = substr(line, RSTART + 3, RLENGTH - 4) SUBSEP FNR
        line = substr(line, RSTART + RLENGTH)
    }
}
/^\|/ {
    if (rows == 0) {
        if (prev !~ /^[ \t]*$/ && prev !~ /^#/) bad("a line starting with a pipe continues a paragraph (a broken table, or prose to rewrap)")
        header = ncells($0)
    } else if (rows == 1) {
        if ($0 !~ /^\|([ \t]*:?-+:?[ \t]*\|)+[ \t]*$/) bad("a table without a separator row under its header")
        else if (ncells($0) != header) bad("the separator row has " ncells($0) " cells, the header " header)
    } else if (ncells($0) != header) {
        bad("a row of " ncells($0) " cells in a table of " header)
    }
    rows++; prev = $0; next
}
{
    if (rows == 1) bad("the line above is a table of one row (no separator)")
    rows = 0; prev = $0
}
END { checklinks(); exit errors > 0 }
' docs/*.md README.md || fail=1

if [ $fail = 0 ]; then
    echo "ok docs: performance.md $n lines, $(ls docs/bench | wc -l) cited logs, every table and in-page link of $(ls docs/*.md | wc -l) pages and README.md well formed"
fi
exit $fail
