#!/usr/bin/env python3
"""cpu_ab.py - CPU time of one render by two brume binaries, interleaved, pinned to one core.

    python3 bench/cpu_ab.py BEFORE AFTER SCENE SPP RUNS [CPU]

Runs `brume render SCENE --spp SPP --threads 1` RUNS times with each binary, alternating
which goes first, each under `taskset -c CPU` (default 1: this VM's two cores were at times
1.35 x apart in speed, docs/performance.md), and prints the median CPU time (user + system)
of each and their ratio AFTER / BEFORE. For changes that keep the image (or change it by
rounding only); bench/efficiency.py measures variance as well. Not part of `make test`.
"""
import resource
import statistics
import subprocess
import sys


def main():
    if len(sys.argv) not in (6, 7):
        sys.exit(__doc__.strip().splitlines()[2].strip())
    before, after, scene, spp, runs = sys.argv[1:6]
    cpu = sys.argv[6] if len(sys.argv) == 7 else "1"
    if not (spp.isdigit() and runs.isdigit() and 0 < int(runs) <= 1000):
        sys.exit(f"cpu_ab.py: SPP and RUNS must be whole numbers, RUNS 1 to 1000 (got {spp!r}, {runs!r})")
    times = {before: [], after: []}
    for i in range(int(runs)):
        for b in (before, after) if i % 2 == 0 else (after, before):
            r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
            p = subprocess.run(["taskset", "-c", cpu, b, "render", scene, "--spp", spp, "--threads", "1", "--quiet",
                                "-o", "/tmp/brume-cpu-ab.exr"], stderr=subprocess.PIPE, text=True)
            if p.returncode != 0:
                sys.exit(f"cpu_ab.py: {b}: " + (p.stderr.strip().splitlines() or ["failed"])[-1])
            r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
            times[b].append(r1.ru_utime - r0.ru_utime + r1.ru_stime - r0.ru_stime)
    mb, ma = statistics.median(times[before]), statistics.median(times[after])
    print(f"{scene} {spp} spp, core {cpu}: before {mb:.3f} s, after {ma:.3f} s, after / before {ma / mb:.3f}")
    print("  before " + " ".join(f"{t:.3f}" for t in times[before]))
    print("  after  " + " ".join(f"{t:.3f}" for t in times[after]))


if __name__ == "__main__":
    main()
