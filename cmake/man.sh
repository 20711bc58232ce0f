#!/bin/sh
# man.sh - writes the man page brume.1 from the tool's own help text (`brume help` and
# `brume help COMMAND` for each command it lists), so that the page cannot drift from the tool.
#   man.sh BRUME_EXE VERSION OUT
set -eu
exe=$1
version=$2
out=$3
tmp="$out.tmp"
# roff: a backslash is \e; a line starting with . or ' would be a request
esc() { sed -e 's/\\/\\e/g' -e "s/^\\([.']\\)/\\\\\\&\\1/"; }
"$exe" help > "$tmp.help"
cmds=$(awk '/^commands:/ {c = 1; next} /^$/ {c = 0} c && $1 != "help" {print $1}' "$tmp.help")
test -n "$cmds" || { echo "man.sh: \`$exe help\` lists no commands" >&2; exit 1; }
{
    # printf, not echo: dash's echo would take roff's \f for a form feed
    printf '.TH BRUME 1 "" "brume %s" "User Commands"\n' "$version"
    printf '%s\n' '.SH NAME' 'brume \- render participating media: clouds, fog, haze, smoke, fire' \
        '.SH SYNOPSIS' '.B brume' '.I COMMAND' '[\fIARGS\fR]' '.SH DESCRIPTION' \
        "This page is the tool's own help text: \\fBbrume help\\fR, then \\fBbrume help\\fR \\fICOMMAND\\fR for each command." \
        '.PP' '.nf'
    esc < "$tmp.help"
    printf '%s\n' '.fi'
    printf '%s\n' '.SH COMMANDS'
    for c in $cmds; do
        "$exe" help "$c" > "$tmp.cmd" || { echo "man.sh: \`$exe help $c\` failed" >&2; exit 1; }
        printf '.SS brume %s\n.nf\n' "$c"
        esc < "$tmp.cmd"
        printf '%s\n' '.fi'
    done
} > "$tmp"
rm -f "$tmp.help" "$tmp.cmd"
mv "$tmp" "$out"
