#!/bin/sh
# attack.sh - replays hostile inputs (tests/bad) against the brume tool under time and memory
# limits, in a scratch folder full of files brume did not write, and fails when any input
#   - crashes brume or gets it killed (an exit status from a signal it was not sent),
#   - runs past its time limit or its memory limit (ulimit -v),
#   - prints anything but one line on stderr when it fails,
#   - removes, replaces or changes a file brume did not write (checked by checksums), or
#   - makes a file or folder it was not asked for.
# The corpus of tests/bad/ (run by run_bad) covers bad inputs one reader at a time; this
# script covers what an attacker does with paths, signals and valid-looking scenes.
# Usage: scripts/attack.sh BRUME [CORPUS_DIR]   (CORPUS_DIR: tests/bad, for its meshes)
# Exit 0 when every attack is answered; 1, naming each failure, otherwise. ctest runs it
# (attack.replay): about 20 s.
set -u
brume=$1
corpus=${2:-$(cd "$(dirname "$0")/.." && pwd)/tests/bad}
work=$(mktemp -d "${TMPDIR:-/tmp}/brume-attack.XXXXXX")
trap 'rm -rf "$work"' EXIT
cd "$work" || exit 1
fails=0
MEM_KB=$((3 * 1024 * 1024)) # 3 GiB of address space: brume and its reader children

# ---- the victim files: brume must leave them as they are ---------------------------------------
echo keep > notes.txt
mkfifo fifo
mkdir folder
printf 'x%.0s' $(seq 32) > g.raw
cat > s.json <<'JSON'
{"camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "fov": 40},
 "lights": [{"type": "distant", "direction": [0, -1, 0], "irradiance": 1}],
 "media": [{"density": {"type": "grid", "file": "g.raw", "format": "raw", "dims": [2, 2, 2]}, "sigma_a": 0.1, "sigma_s": 1}],
 "render": {"width": 8, "height": 8, "spp": 1, "threads": 1}}
JSON
cat > light_over_scene.json <<'JSON'
{"camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "fov": 40},
 "lights": [{"type": "distant", "direction": [0, -1, 0], "irradiance": 1}],
 "media": [{"density": {"type": "constant", "value": 1}, "sigma_a": 0.1, "sigma_s": 1}],
 "render": {"width": 8, "height": 8, "spp": 1, "method": "blasi"}, "blasi": {"light_rays": 100, "save_light": "light_over_scene.json"}}
JSON
cat > step_bomb.json <<'JSON'
{"camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "fov": 40},
 "lights": [{"type": "distant", "direction": [0, -1, 0], "irradiance": 1}],
 "media": [{"density": {"type": "procedural_cloud", "resolution": 32}, "sigma_a": 0.1, "sigma_s": 1}],
 "render": {"width": 8, "height": 8, "spp": 1, "method": "blasi"}, "blasi": {"step": 1e-6}}
JSON
cat > film_bomb.json <<'JSON'
{"camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "fov": 40},
 "render": {"width": 65536, "height": 4096, "spp": 1, "max_memory_mb": 1}}
JSON
cat > slow_load.json <<'JSON'
{"camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "fov": 40},
 "lights": [{"type": "distant", "direction": [0, -1, 0], "irradiance": 1}],
 "media": [{"density": {"type": "procedural_cloud", "resolution": 512}, "sigma_a": 0.1, "sigma_s": 1}],
 "render": {"width": 8, "height": 8, "spp": 1}}
JSON
cat > slow_light.json <<'JSON'
{"camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "fov": 40},
 "lights": [{"type": "distant", "direction": [0, -1, 0], "irradiance": 1}],
 "media": [{"density": {"type": "procedural_cloud", "resolution": 32}, "sigma_a": 0.1, "sigma_s": 1}],
 "render": {"width": 8, "height": 8, "spp": 1, "method": "blasi"}, "blasi": {"light_rays": 1e8, "step": 0.001}}
JSON
head -c 300000 /dev/zero | tr '\0' 'x' > junk.bin
for m in ply_no_end_header.ply ply_type_typo.ply obj_huge_polygon.obj gltf_nested.gltf; do
    cp "$corpus/meshes/$m" .
    printf '{"camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "fov": 40}, "surfaces": [{"type": "mesh", "file": "%s"}], "render": {"width": 8, "height": 8, "spp": 1, "max_memory_mb": 64}}\n' "$m" > "mesh_$m.json"
done
printf '{"camera": 5}\n' > bad.json

snapshot() { # every name with its type and checksum, the scratch folder's outputs aside
    find . \( -path ./out -o -path ./err.txt \) -prune -o -print | LC_ALL=C sort | while read -r f; do
        if [ -f "$f" ]; then echo "$f $(cksum < "$f")"; elif [ -p "$f" ]; then echo "$f fifo"; else echo "$f other"; fi
    done
}
before=$(snapshot)

# attack NAME LIMIT_S EXPECT ARGS...: runs brume ARGS; EXPECT is the exit status wanted
attack() {
    name=$1 limit=$2 expect=$3
    shift 3
    rm -rf out err.txt
    mkdir out
    t0=$(date +%s)
    ( ulimit -v $MEM_KB; exec timeout -s KILL "$limit" "$brume" "$@" ) >/dev/null 2>err.txt
    rc=$?
    t1=$(date +%s)
    lines=$(wc -l < err.txt)
    why=""
    [ "$rc" -eq 137 ] && why="killed at its $limit s limit (or out of memory)"
    [ -z "$why" ] && [ "$rc" -ne "$expect" ] && why="exit $rc, expected $expect"
    [ -z "$why" ] && [ "$rc" -ne 0 ] && [ "$lines" -ne 1 ] && why="$lines lines on stderr"
    now=$(snapshot)
    [ -z "$why" ] && [ "$now" != "$before" ] && why="files brume did not write changed: $(printf '%s\n' "$before" "$now" | sort | uniq -u | head -3 | tr '\n' ' ')"
    if [ -n "$why" ]; then
        echo "FAIL $name: $why: $(head -c 300 err.txt)"
        fails=$((fails + 1))
    else
        echo "ok   $name ($((t1 - t0)) s, exit $rc)"
    fi
}

# signal_attack NAME SIGNAL WAIT_S ARGS...: brume ARGS, SIGNAL after WAIT_S: it must end
# within a second with 128 + the signal
signal_attack() {
    name=$1 sig=$2 wait=$3
    shift 3
    rm -rf out
    mkdir out
    ( ulimit -v $MEM_KB; exec "$brume" "$@" ) >/dev/null 2>err.txt &
    pid=$!
    sleep "$wait"
    kill -"$sig" $pid
    t0=$(date +%s.%N)
    rc=""
    for _ in $(seq 50); do
        if ! kill -0 $pid 2>/dev/null; then break; fi
        sleep 0.05
    done
    if kill -0 $pid 2>/dev/null; then
        kill -KILL $pid
        wait $pid
        echo "FAIL $name: still running 2.5 s after SIG$sig"
        fails=$((fails + 1))
        return
    fi
    wait $pid
    rc=$?
    case $sig in INT) want=130 ;; TERM) want=143 ;; *) want=129 ;; esac
    if [ "$rc" -ne "$want" ]; then
        echo "FAIL $name: exit $rc after SIG$sig, expected $want"
        fails=$((fails + 1))
    else
        echo "ok   $name (SIG$sig answered, exit $rc)"
    fi
}

# ---- files brume did not write ----------------------------------------------------------------
attack checkpoint_notes 30 1 render s.json -o out/o.png --quiet --checkpoint notes.txt
attack checkpoint_scene 30 1 render s.json -o out/o.png --quiet --checkpoint s.json
attack checkpoint_input 30 1 render s.json -o out/o.png --quiet --checkpoint g.raw
attack checkpoint_fifo 30 1 render s.json -o out/o.png --quiet --checkpoint fifo
attack checkpoint_folder 30 1 render s.json -o out/o.png --quiet --checkpoint folder
attack checkpoint_dev_null 30 1 render s.json -o out/o.png --quiet --checkpoint /dev/null
attack save_light_scene 30 1 render s.json -o out/o.png --quiet --method blasi --save-light s.json
attack save_light_input 30 1 render s.json -o out/o.png --quiet --method blasi --save-light g.raw
attack save_light_fifo 30 1 render s.json -o out/o.png --quiet --method blasi --save-light fifo
attack scene_save_light_itself 30 1 render light_over_scene.json -o out/o.png --quiet
attack video_option 30 2 render s.json --frames 0-1 -o out/f%d.png --quiet --video -y
attack folders_bad_scene 30 1 render bad.json --frames 0-2000 -o out/d%d/f.png --quiet
[ -z "$(ls out)" ] || { echo "FAIL folders_bad_scene: made $(ls out | wc -l) folders"; fails=$((fails + 1)); }
# ---- readers ------------------------------------------------------------------------------------
attack resume_junk 30 1 render s.json -o out/o.png --quiet --width 256 --height 256 --resume junk.bin
attack resume_dev_zero 30 1 render s.json -o out/o.png --quiet --resume /dev/zero
attack resume_fifo 30 1 render s.json -o out/o.png --quiet --resume fifo
for m in ply_no_end_header.ply ply_type_typo.ply obj_huge_polygon.obj gltf_nested.gltf; do
    attack "mesh_$m" 60 1 render "mesh_$m.json" -o out/o.png --quiet
done
# ---- work and memory ----------------------------------------------------------------------------
attack blasi_step_bomb 30 1 render step_bomb.json -o out/o.png --quiet
attack film_bomb 30 1 render film_bomb.json -o out/o.png --quiet
# ---- signals in every phase ---------------------------------------------------------------------
signal_attack sigint_loading INT 1 render slow_load.json -o out/o.png --quiet
signal_attack sigterm_loading TERM 1 render slow_load.json -o out/o.png --quiet
signal_attack sigint_light_pass INT 2 render slow_light.json -o out/o.png --quiet
signal_attack sigterm_light_pass TERM 2 render slow_light.json -o out/o.png --quiet
now=$(snapshot)
[ "$now" = "$before" ] || { echo "FAIL: files brume did not write changed"; fails=$((fails + 1)); }

if [ "$fails" -ne 0 ]; then
    echo "attack.sh: $fails attack(s) not answered"
    exit 1
fi
echo "attack.sh: every attack answered"
