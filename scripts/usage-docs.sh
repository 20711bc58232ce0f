#!/bin/sh
# usage-docs.sh - rewrites README.md's usage block under "## The tool" (between its BEGIN and
# END comments) with `brume help --usage`, made from the commands' flag tables (cli/cli_flags.h):
# the text ctest cli_help.readme_usage_is_generated expects after a flag changed.
#   scripts/usage-docs.sh [BRUME]      (BRUME: the tool to ask, default build/brume)
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
brume=${1:-$root/build/brume}
doc=$root/README.md
tmp=$(mktemp)
trap 'rm -f "$tmp" "$tmp.md"' EXIT
"$brume" help --usage > "$tmp"
grep -q '^<!-- BEGIN brume help --usage -->$' "$doc" && grep -q '^<!-- END brume help --usage -->$' "$doc" ||
    { echo "usage-docs.sh: $doc has no BEGIN and END brume help --usage comments" >&2; exit 1; }
awk -v gen="$tmp" '
    /^<!-- BEGIN brume help --usage -->$/ { print; while ((getline l < gen) > 0) print l; skip = 1; next }
    /^<!-- END brume help --usage -->$/ { skip = 0 }
    !skip { print }' "$doc" > "$tmp.md"
cat "$tmp.md" > "$doc"
