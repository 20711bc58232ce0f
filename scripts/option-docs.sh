#!/bin/sh
# option-docs.sh - rewrites the tables of docs/scene-format.md's "Method options" (between its
# BEGIN and END comments) with `brume options --markdown`, the text ctest
# options.doc_is_generated expects after a method's option table changed.
#   scripts/option-docs.sh [BRUME]      (BRUME: the tool to ask, default build/brume)
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
brume=${1:-$root/build/brume}
doc=$root/docs/scene-format.md
tmp=$(mktemp)
trap 'rm -f "$tmp" "$tmp.md"' EXIT
"$brume" options --markdown > "$tmp"
grep -q '^<!-- BEGIN brume options --markdown -->$' "$doc" && grep -q '^<!-- END brume options --markdown -->$' "$doc" ||
    { echo "option-docs.sh: $doc has no BEGIN and END brume options comments" >&2; exit 1; }
awk -v gen="$tmp" '
    /^<!-- BEGIN brume options --markdown -->$/ { print; print ""; while ((getline l < gen) > 0) print l; print ""; skip = 1; next }
    /^<!-- END brume options --markdown -->$/ { skip = 0 }
    !skip { print }' "$doc" > "$tmp.md"
cat "$tmp.md" > "$doc"
