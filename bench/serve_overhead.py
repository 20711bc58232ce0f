#!/usr/bin/env python3
"""serve_overhead.py - what `brume render --serve` costs while a viewer watches.

Renders the same scene alternately without and with --serve, the latter polled as the live
page polls it (/status.json and /image.png once a second), and prints each pair's times, the
median of the ratios and the medians of the times. The machine is shared: pairs alternate so
that load changes hit both sides alike.

    python3 bench/serve_overhead.py [BRUME] [PAIRS]   (defaults: build/brume, 5)
"""
import re
import statistics
import subprocess
import sys
import threading
import time
import urllib.request

BRUME = sys.argv[1] if len(sys.argv) > 1 else "build/brume"
PAIRS = int(sys.argv[2]) if len(sys.argv) > 2 else 5
ARGS = ["render", "scenes/cloud64.json", "--spp", "64", "--threads", "2", "--quiet", "-o", "/tmp/serve-bench.png"]


def plain():
    t0 = time.monotonic()
    subprocess.run([BRUME] + ARGS, check=True)
    return time.monotonic() - t0


def served():
    t0 = time.monotonic()
    p = subprocess.Popen([BRUME] + ARGS + ["--serve", "127.0.0.1:0", "--serve-exit"], stderr=subprocess.PIPE, text=True)
    line = p.stderr.readline()
    port = re.search(r"127\.0\.0\.1:(\d+)/", line).group(1)
    done = threading.Event()
    polls = [0]

    def poll():
        while not done.is_set():
            for path in ("/status.json", "/image.png?exposure=0"):
                try:
                    urllib.request.urlopen(f"http://127.0.0.1:{port}{path}", timeout=5).read()
                    polls[0] += 1
                except OSError:
                    pass
            done.wait(1.0)

    th = threading.Thread(target=poll)
    th.start()
    p.wait()
    dt = time.monotonic() - t0
    done.set()
    th.join()
    if p.returncode != 0:
        sys.exit(f"brume --serve exited {p.returncode}")
    return dt, polls[0]


def main():
    with open("/proc/loadavg") as f:
        print("load average at start:", " ".join(f.read().split()[:3]))
    ratios, tp, ts = [], [], []
    for k in range(PAIRS):
        a = plain()
        b, n = served()
        tp.append(a)
        ts.append(b)
        ratios.append(b / a)
        print(f"pair {k}: plain {a:.2f} s, --serve {b:.2f} s ({n} requests answered), ratio {b / a:.3f}", flush=True)
    print(f"median ratio {statistics.median(ratios):.3f} (overhead {100 * (statistics.median(ratios) - 1):+.1f} %); "
          f"median times {statistics.median(tp):.2f} s plain, {statistics.median(ts):.2f} s --serve")
    with open("/proc/loadavg") as f:
        print("load average at end:", " ".join(f.read().split()[:3]))


if __name__ == "__main__":
    main()
