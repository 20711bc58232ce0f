#!/usr/bin/env python3
"""efficiency.py - the path tracer's efficiency, 1 / (CPU time x variance), of configurations
against the first one, per scene and spp.

    python3 bench/efficiency.py [--build build] [--rounds 3] [--threads 2]
                                [--scenes cloud64:16,64 wdas-dense:8,32]
                                [--pin CPUS] [--configs NAME=ARGS ...]

A configuration is extra `brume render` arguments, e.g. `off='--set path.sun_lobe=0' on=`
(sun-lobe sampling off and at its default) or the default pair
`independent='--set render.sampler="independent"' sobol='--set render.sampler="sobol"'`.
Leading `VAR=value` words of a configuration set the renders' environment instead (for a
throwaway build's switches), except `BIN=path`, which renders that configuration with another
binary (`base='BIN=/work/base/build/brume' new=`: main before a change against it). The first
configuration is the baseline of the ratios.
`--pin 1` runs every render under `taskset -c 1`: on the project's VM one core was at times
1.35 x slower than the other (2026-11-26, 00:30 UTC; equal ten minutes later), so one-thread
comparisons left to the scheduler can mix the two.

The variance of an image needs no reference: two renders with different seeds differ by
noise only, so half their mean squared difference (over pixels and RGB channels) is the
variance of one render. Each round renders, for each configuration in turn (the order
alternating between rounds), the same two seeds; CPU time is the user + system time of the
`brume render` processes. Printed: per round each configuration's time and variance, then
per configuration the medians over rounds and efficiency = 1 / (CPU time x variance) against
the baseline, from the medians and from the fastest round (which a loaded machine disturbs
least). The relative variance (variance / mean^2) compares scenes. Part of
docs/performance.md; not part of `make test`.
"""
import argparse
import array
import os
import resource
import shlex
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


def render(brume, scene, spp, seed, threads, args, out, pin=None):
    """Renders and returns the CPU seconds (user + system) the process used."""
    env = dict(os.environ)
    while args and "=" in args[0] and args[0].split("=", 1)[0].isupper():  # leading VAR=value: environment
        k, v = args[0].split("=", 1)
        if k == "BIN":  # BIN=path: this configuration's binary (another build, e.g. main before a change)
            if not (os.path.isfile(v) and os.access(v, os.X_OK)):
                sys.exit(f"efficiency.py: BIN={v}: not an executable file")
            brume = v
        else:
            env[k] = v
        args = args[1:]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    prefix = ["taskset", "-c", pin] if pin else []
    p = subprocess.run(prefix + [brume, "render", scene, "--spp", str(spp), "--seed", str(seed), "--threads", str(threads),
                        "-o", out] + args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, env=env)
    if p.returncode != 0:
        sys.exit(p.stderr.strip())
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default="build")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--pin", default=None, help="taskset CPU list for every render, e.g. 1 (this VM's two cores "
                    "were at times 1.35 x apart in speed)")
    ap.add_argument("--scenes", nargs="*", default=["cloud64:16,64", "wdas-dense:8,32"],
                    help="SCENE:SPP,SPP... (scenes/SCENE.json)")
    ap.add_argument("--configs", nargs="*", default=["independent=--set render.sampler=\"independent\"",
                                                     "sobol=--set render.sampler=\"sobol\""],
                    help="NAME=ARGS: extra render arguments; the first is the baseline")
    a = ap.parse_args()
    brume = os.path.join(HERE, a.build, "brume")
    if not os.access(brume, os.X_OK):
        sys.exit(f"{brume}: build brume first")
    configs = []
    for c in a.configs:
        name, _, args = c.partition("=")
        configs.append((name, shlex.split(args)))
    names = [n for n, _ in configs]
    print("load:", os.getloadavg())
    tmp = tempfile.mkdtemp(prefix="brume-efficiency-")
    for item in a.scenes:
        scene_name, spps = item.split(":")
        scene = os.path.join(HERE, "scenes", scene_name + ".json")
        for spp in (int(v) for v in spps.split(",")):
            t = {n: [] for n in names}
            var = {n: [] for n in names}
            rel = {n: [] for n in names}
            for r in range(a.rounds):
                for name, args in (configs if r % 2 == 0 else configs[::-1]):
                    imgs, cpu = [], 0.0
                    for k in range(2):
                        out = os.path.join(tmp, f"{scene_name}-{spp}-{name}-{k}.pfm")
                        cpu += render(brume, scene, spp, 1000 + 2 * r + k, a.threads, args, out, a.pin)
                        imgs.append(read_pfm(out))
                    n = len(imgs[0])
                    v = 0.5 * sum((x - y) * (x - y) for x, y in zip(imgs[0], imgs[1])) / n
                    m = 0.5 * (sum(imgs[0]) + sum(imgs[1])) / n
                    t[name].append(cpu / 2)
                    var[name].append(v)
                    rel[name].append(v / (m * m))
                print(f"{scene_name} {spp:4d} spp round {r + 1}: " +
                      "  ".join(f"{n} {t[n][-1]:.3f} s, rel. variance {rel[n][-1]:.4g}" for n in names), flush=True)
            base = names[0]
            tb, vb, tbmin = statistics.median(t[base]), statistics.median(var[base]), min(t[base])
            for name in names:
                tm, vm, rm = statistics.median(t[name]), statistics.median(var[name]), statistics.median(rel[name])
                print(f"{scene_name} {spp:4d} spp {name}: cpu s/render {tm:.3f} (fastest {min(t[name]):.3f}),"
                      f" relative variance {rm:.4g}; against {base}: time {tm / tb:.3f}, variance {vm / vb:.3f},"
                      f" efficiency {(tb * vb) / (tm * vm):.3f} (fastest rounds: {(tbmin * vb) / (min(t[name]) * vm):.3f})",
                      flush=True)
    print("load:", os.getloadavg())


if __name__ == "__main__":
    main()
