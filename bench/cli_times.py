#!/usr/bin/env python3
"""cli_times.py - the figures of docs/performance.md as a user meets them: whole `brume`
processes, as the command line runs them (start-up, scene, render, the image written),
beside the inner figures of the benchmarks that time one part through the API.

    python3 bench/cli_times.py [--build build] [--runs 5] [--only NAME,NAME] [--against OTHER_BRUME]

Each round runs every case once, in turn (interleaved, so that a change of load touches
them alike), and prints per case the median wall-clock seconds and the median CPU seconds
(user + system of the process, from wait4: what load inflates least), and the load
average before and after. The cases and the inner figure each stands beside:

  default        `brume render --width 240 --height 160 --spp 32`: bench_render's default
                 scene at its size (its samples/s; docs/performance.md, "The path tracer on
                 its own"); samples/s of the whole process are printed too
  stam-N         `brume render STAM_N.json`, N = 10, 100, 1000 blobs: bench_stam's 640 x 480
                 frame at 1 spp (the scene from `bench_stam --scene N`; "Stam's method")
  cloud64-hg     `brume render scenes/cloud64.json --width 256 --height 256 --spp 16`: a dense
                 grid walked by the DDA (bench_grid) with Henyey-Greenstein's phase function
  cloud64-schlick  the same with Schlick's of the same g (`--set media.0.phase=...`):
                 the ratio to cloud64-hg is what bench_phase's Schlick / HG ratio is worth in
                 a render
  wdas-dense     `brume render scenes/wdas-dense.json --width 256 --height 256 --spp 4`: a
                 sparse grid read from .vdb into NanoVDB (bench_sparse, bench_grid's lookups)
  adaptive       `brume render --width 240 --height 160 --noise 0.1 --min-spp 4`: the default
                 scene to a per-pixel noise target (bench_adaptive; samples/s not printed: the
                 count is the target's)
  denoise        `brume denoise IN.exr -o OUT.exr`: the denoiser as a command, on the default
                 scene at 480 x 320, 8 spp with its layers (rendered once, before the rounds;
                 bench_denoise's "denoise s" column)

The default scene has the surfaces (Embree, bench_surfaces). With --against, every case
runs with the other binary too, in the same rounds, and the ratios are printed. The
machine is noted; not part of `make test`.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def run(cmd):
    """Wall seconds and CPU seconds (user + system) of one process."""
    import time
    t0 = time.perf_counter()
    pid = os.posix_spawn(cmd[0], cmd, os.environ,
                         file_actions=[(os.POSIX_SPAWN_OPEN, 1, os.devnull, os.O_WRONLY, 0),
                                       (os.POSIX_SPAWN_OPEN, 2, os.devnull, os.O_WRONLY, 0)])
    _, status, ru = os.wait4(pid, 0)
    wall = time.perf_counter() - t0
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit("cli_times: failed: " + " ".join(cmd))
    return wall, ru.ru_utime + ru.ru_stime


def cases(build, tmp):
    out = os.path.join(tmp, "out.png")
    scenes = os.path.join(HERE, "scenes")
    yield "default", ["render", "--width", "240", "--height", "160", "--spp", "32", "--quiet", "-o", out], 240 * 160 * 32
    for n in (10, 100, 1000):
        path = os.path.join(tmp, "stam-%d.json" % n)
        with open(path, "w") as f:
            f.write(subprocess.run([os.path.join(build, "bench", "bench_stam"), "--scene", str(n)], check=True,
                                   capture_output=True, text=True).stdout)
        yield "stam-%d" % n, ["render", path, "--quiet", "-o", out], 640 * 480
    cloud = ["render", os.path.join(scenes, "cloud64.json"), "--width", "256", "--height", "256", "--spp", "16",
             "--quiet", "-o", out]
    yield "cloud64-hg", cloud, 256 * 256 * 16
    g = json.load(open(os.path.join(scenes, "cloud64.json")))["media"][0]["phase"]["g"]
    yield "cloud64-schlick", cloud + ["--set", 'media.0.phase={"type": "schlick", "g": %r}' % g], 256 * 256 * 16
    yield "wdas-dense", ["render", os.path.join(scenes, "wdas-dense.json"), "--width", "256", "--height", "256",
                         "--spp", "4", "--quiet", "-o", out], 256 * 256 * 4
    yield "adaptive", ["render", "--width", "240", "--height", "160", "--noise", "0.1", "--min-spp", "4", "--quiet",
                       "-o", out], 0
    layers = os.path.join(tmp, "layers.exr")
    subprocess.run([os.path.join(build, "brume"), "render", "--spp", "8", "--aov", "variance,albedo,normal,depth",
                    "--quiet", "-o", layers], check=True)
    yield "denoise", ["denoise", layers, "-o", os.path.join(tmp, "denoised.exr")], 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--build", default=os.path.join(HERE, "build"))
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--only", help="comma-separated case names")
    ap.add_argument("--against", help="another brume binary, timed in the same rounds")
    a = ap.parse_args()
    bins = [("brume", os.path.join(a.build, "brume"))] + ([("against", a.against)] if a.against else [])
    with tempfile.TemporaryDirectory() as tmp:
        todo = [c for c in cases(a.build, tmp) if not a.only or c[0] in a.only.split(",")]
        load0 = os.getloadavg()
        times = {(b, c[0]): [] for b, _ in bins for c in todo}
        for _ in range(a.runs):
            for name, args, _ in todo:
                for b, exe in bins:
                    times[(b, name)].append(run([exe] + args))
        load1 = os.getloadavg()
    print("machine: %s, %d cores; load before %.2f %.2f %.2f, after %.2f %.2f %.2f" %
          ((os.uname().nodename, os.cpu_count()) + load0 + load1))
    print("whole process, medians of %d interleaved rounds: wall s, CPU s (user + system)" % a.runs)
    for name, args, samples in todo:
        for b, exe in bins:
            w = statistics.median(t[0] for t in times[(b, name)])
            c = statistics.median(t[1] for t in times[(b, name)])
            rate = "%7.3f M samples/s wall" % (samples / w / 1e6) if samples else "%22s" % ""
            print("  %-16s %-8s %8.3f s wall %8.3f s CPU  %s   %s" % (name, b, w, c, rate, " ".join(["brume"] + args)))
        if a.against:
            r = [x[0] / y[0] for x, y in zip(times[("brume", name)], times[("against", name)])]
            rc = [x[1] / y[1] for x, y in zip(times[("brume", name)], times[("against", name)])]
            print("  %-16s brume / against: wall %.3f, CPU %.3f (medians of the rounds' ratios)" %
                  (name, statistics.median(r), statistics.median(rc)))
    if not a.only or "cloud64-schlick" in a.only:
        hg = [t[1] for t in times[("brume", "cloud64-hg")]] if ("brume", "cloud64-hg") in times else None
        sc = [t[1] for t in times[("brume", "cloud64-schlick")]] if ("brume", "cloud64-schlick") in times else None
        if hg and sc:
            print("  CPU, cloud64 Schlick / HG: %.3f (median of the rounds' ratios)" %
                  statistics.median(x / y for x, y in zip(sc, hg)))


if __name__ == "__main__":
    main()
