#!/bin/sh
# setup.sh - install the Debian packages brume needs (scripts/debian-packages.txt), skipping
# those already present. Needs root (or sudo) only when something is missing.
#   sh scripts/setup.sh          everything `make test` needs (the render packages included)
#   sh scripts/setup.sh render   only what `make render` needs: the library and the tool
# When another apt or dpkg holds the package lock (an unattended upgrade, a second terminal),
# it waits up to BRUME_APT_WAIT seconds (default 600) for it, then stops with one message.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
case ${1:-test} in
render) tags=render ;;
test) tags="render test" ;;
*) echo "usage: sh scripts/setup.sh [render|test]" >&2; exit 2 ;;
esac
wait_s=${BRUME_APT_WAIT:-600}
want=$(sed -e 's/#.*//' -e '/^[[:space:]]*$/d' "$here/debian-packages.txt" |
       awk -v tags=" $tags " 'index(tags, " " $2 " ") {print $1}')
missing=""
for p in $want; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
        missing="$missing $p"
    fi
done
if [ -z "$missing" ]; then
    exit 0
fi
echo "setup: installing$missing" >&2
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO=sudo; fi
export DEBIAN_FRONTEND=noninteractive
log=$(mktemp "${TMPDIR:-/tmp}/brume-setup-XXXXXX")
trap 'rm -f "$log"' EXIT
locked() {
    echo "setup: another package manager held the apt/dpkg lock for $wait_s s; let it finish" \
         "(or see who holds it: $(grep -o 'held by process [0-9]* ([^)]*)' "$log" | head -1))," \
         "then run sh scripts/setup.sh again" >&2
    exit 1
}
# `apt-get update` takes the package lists' lock, which DPkg::Lock::Timeout does not cover:
# retry it while the lock is taken, up to the same bound
start=$(date +%s)
until $SUDO apt-get -o DPkg::Lock::Timeout="$wait_s" update -qq > "$log" 2>&1; do
    if ! grep -q 'Could not get lock\|Unable to lock' "$log"; then cat "$log" >&2; exit 1; fi
    [ $(($(date +%s) - start)) -lt "$wait_s" ] || locked
    sleep 5
done
# apt-get install waits for the dpkg lock itself (apt >= 1.9.11; Debian 12 has 2.6)
left=$((wait_s - ($(date +%s) - start)))
[ "$left" -gt 10 ] || left=10
# shellcheck disable=SC2086
if ! $SUDO apt-get -o DPkg::Lock::Timeout="$left" install -y -qq --no-install-recommends $missing > "$log" 2>&1; then
    if grep -q 'Could not get lock\|Unable to acquire the dpkg frontend lock' "$log"; then locked; fi
    cat "$log" >&2
    exit 1
fi
