#!/usr/bin/env python3
"""startup.py - how long a brume process takes before and around its work: wall-clock
medians of many short runs, interleaved, against /bin/true (the cost of starting any
process) and optionally against another brume binary.

    python3 bench/startup.py [--build build] [--runs 40] [--against OTHER_BRUME]

Each round runs, in turn: /bin/true; `brume --version` (start-up alone: the dynamic loader
and the libraries' initialisation); a render of the built-in default scene at 8 x 6 pixels,
1 sample (start-up, scene building and one tiny render); and with the Python package built,
`python3 -c "import brume"` against `python3 -c "pass"` (with /usr/bin/python3, the
interpreter CMake builds the package for). With --against, the same brume
commands run with the other binary too, in the same rounds, and the ratios are printed.
Part of docs/performance.md ("Start-up"); not part of `make test`.
"""
import argparse
import os
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def wall(cmd, env=None):
    t0 = time.perf_counter()
    subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env, check=True)
    return time.perf_counter() - t0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--build", default=os.path.join(HERE, "build"))
    ap.add_argument("--runs", type=int, default=40)
    ap.add_argument("--against", help="another brume binary, timed in the same rounds")
    a = ap.parse_args()
    brume = os.path.join(a.build, "brume")
    out = os.path.join(a.build, "startup_bench.png")
    cases = [("/bin/true", ["/bin/true"], None)]
    bins = [("brume", brume)] + ([("against", a.against)] if a.against else [])
    for name, b in bins:
        cases.append((name + " --version", [b, "--version"], None))
        cases.append((name + " render 8x6 1 spp", [b, "render", "--width", "8", "--height", "6", "--spp", "1",
                                                   "--quiet", "-o", out], None))
    py = os.path.join(a.build, "python")
    python = "/usr/bin/python3" if os.path.exists("/usr/bin/python3") else sys.executable  # as CMake picks it
    if os.path.isdir(os.path.join(py, "brume")):
        env = dict(os.environ, PYTHONPATH=py, PYTHONDONTWRITEBYTECODE="1")
        cases.append(("python3 -c pass", [python, "-c", "pass"], env))
        cases.append(("python3 -c 'import brume'", [python, "-c", "import brume"], env))
    times = {name: [] for name, _, _ in cases}
    for _ in range(a.runs):
        for name, cmd, env in cases:
            times[name].append(wall(cmd, env))
    if os.path.exists(out):
        os.remove(out)
    print("machine:", os.uname().nodename, os.cpu_count(), "cores; load", os.getloadavg())
    print("median wall-clock ms over %d interleaved rounds:" % a.runs)
    med = {k: 1000.0 * statistics.median(v) for k, v in times.items()}
    for name, _, _ in cases:
        print("  %-32s %8.1f ms" % (name, med[name]))
    if a.against:
        for what in ("--version", "render 8x6 1 spp"):
            print("  brume / against, %-16s %.3f" % (what + ":", med["brume " + what] / med["against " + what]))


if __name__ == "__main__":
    main()
