#!/usr/bin/env python3
"""sampler_efficiency.py - render.sampler=sobol against render.sampler=independent for `path`:
efficiency = 1 / (CPU time x variance), as a ratio sobol / independent, per scene and spp.

    python3 bench/sampler_efficiency.py [--build build] [--rounds 3] [--scenes cloud64:16,64 wdas-dense:8,32]

The variance of an image needs no reference: two renders with different seeds differ by
noise only, so half their mean squared difference (over pixels and RGB channels) is the
variance of one render. Each round renders, for each sampler in turn (the order alternating
between rounds), the same two seeds; CPU time is the user + system time of the `brume
render` processes (2 threads). Printed: per round the time and variance ratios, then the
medians over rounds and the efficiency ratio of the medians (> 1: sobol is better). The
relative variance (variance / mean^2 of the pair) is printed to compare scenes. Part of
docs/performance.md, section "Low-discrepancy sampling"; not part of `make test`.
"""
import argparse
import array
import os
import resource
import statistics
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def read_pfm(path):
    """The pixel values of a PFM file, as a flat array of floats."""
    with open(path, "rb") as f:
        f.readline()
        f.readline()
        scale = float(f.readline())
        data = array.array("f", f.read())
    if (scale < 0) != (sys.byteorder == "little"):
        data.byteswap()
    return data


def render(brume, scene, spp, seed, sampler, out):
    """Renders and returns the CPU seconds (user + system) the process used."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    p = subprocess.run([brume, "render", scene, "--spp", str(spp), "--seed", str(seed), "--threads", "2",
                        "--set", f'render.sampler="{sampler}"', "-o", out],
                       stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if p.returncode != 0:
        sys.exit(p.stderr.strip())
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default="build")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--scenes", nargs="*", default=["cloud64:16,64", "wdas-dense:8,32"],
                    help="SCENE:SPP,SPP... (scenes/SCENE.json)")
    a = ap.parse_args()
    brume = os.path.join(HERE, a.build, "brume")
    if not os.access(brume, os.X_OK):
        sys.exit(f"{brume}: build brume first")
    print("load:", os.getloadavg())
    tmp = tempfile.mkdtemp(prefix="brume-sampler-")
    samplers = ["sobol", "independent"]
    for item in a.scenes:
        name, spps = item.split(":")
        scene = os.path.join(HERE, "scenes", name + ".json")
        for spp in (int(v) for v in spps.split(",")):
            t = {s: [] for s in samplers}
            var = {s: [] for s in samplers}
            rel = {s: [] for s in samplers}
            for r in range(a.rounds):
                order = samplers if r % 2 == 0 else samplers[::-1]
                for s in order:
                    imgs, cpu = [], 0.0
                    for k in range(2):
                        out = os.path.join(tmp, f"{name}-{spp}-{s}-{k}.pfm")
                        cpu += render(brume, scene, spp, 1000 + 2 * r + k, s, out)
                        imgs.append(read_pfm(out))
                    n = len(imgs[0])
                    v = 0.5 * sum((x - y) * (x - y) for x, y in zip(imgs[0], imgs[1])) / n
                    m = 0.5 * (sum(imgs[0]) + sum(imgs[1])) / n
                    t[s].append(cpu / 2)
                    var[s].append(v)
                    rel[s].append(v / (m * m))
                print(f"{name} {spp:4d} spp round {r + 1}: time sobol/indep {t['sobol'][-1] / t['independent'][-1]:.3f}"
                      f"  variance sobol/indep {var['sobol'][-1] / var['independent'][-1]:.3f}", flush=True)
            med = {s: (statistics.median(t[s]), statistics.median(var[s]), statistics.median(rel[s])) for s in samplers}
            ts, vs, rs = med["sobol"]
            ti, vi, ri = med["independent"]
            print(f"{name} {spp:4d} spp: cpu s/render sobol {ts:.2f} indep {ti:.2f} (ratio {ts / ti:.3f});"
                  f" relative variance sobol {rs:.3g} indep {ri:.3g} (ratio {vs / vi:.3f});"
                  f" efficiency sobol/indep {(ti * vi) / (ts * vs):.3f}", flush=True)
    print("load:", os.getloadavg())


if __name__ == "__main__":
    main()
