#!/bin/sh
# gpu_resources.sh - the GPU kernels' resources as ptxas reports them, on a machine without a
# GPU (docs/gpu.md, "Kernel resources"): per kernel its registers, stack frame, spill stores
# and loads, SASS size and instructions, and its FP64 and FP32 arithmetic instructions; per
# device function the kernels call rather than inline, its stack frame and arithmetic.
#
#   sh bench/gpu_resources.sh [PTX [ARCH]]     (default build/kernel.ptx, sm_90)
#
# ptxas (CUDA's standard location or $PTXAS) compiles the PTX to a cubin in a temporary
# folder (KEEP=DIR keeps the cubin and ptxas's report there; with REUSE=DIR the script reads
# them from there instead of running ptxas, which takes minutes on the path kernel); readelf
# gives each kernel's .text section, its device functions included, and each device
# function's symbol (SASS, 16 bytes an instruction on sm_70 and later). The FP64 and FP32 counts are of the PTX, which is what clang makes: the
# arithmetic instructions (add, sub, mul, fma, div, rcp, sqrt, rsqrt, setp, min, max, abs,
# neg, testp, copysign, cvt) whose type is f64 or f32, a cvt between f32 and f64 counted on
# its own; a kernel's figures include the device functions it reaches (calls, direct or
# through a pointer).
set -u
ptx=${1:-build/kernel.ptx}
arch=${2:-sm_90}
ptxas=${PTXAS:-$(command -v ptxas || ls /usr/local/cuda/bin/ptxas 2>/dev/null | head -1)}
if [ -z "$ptxas" ] || [ ! -x "$ptxas" ]; then
    echo "gpu_resources.sh: no ptxas (CUDA's compiler tools; /usr/local/cuda/bin or \$PTXAS)" >&2
    exit 2
fi
if [ ! -f "$ptx" ]; then
    echo "gpu_resources.sh: $ptx: no PTX (build the library with BRUME_CUDA=ON first)" >&2
    exit 2
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$ptxas" --version | tail -1
if [ -n "${REUSE:-}" ]; then
    cp "$REUSE/k.cubin" "$REUSE/v.txt" "$tmp/"
    echo "ptxas -v -arch=$arch $ptx: reused from $REUSE"
else
    t0=$(date +%s.%N)
    if ! "$ptxas" -v -arch="$arch" -o "$tmp/k.cubin" "$ptx" >"$tmp/v.txt" 2>&1; then
        cat "$tmp/v.txt" >&2
        echo "gpu_resources.sh: ptxas failed on $ptx" >&2
        exit 1
    fi
    t1=$(date +%s.%N)
    echo "ptxas -v -arch=$arch $ptx: $(awk -v a="$t1" -v b="$t0" 'BEGIN { printf "%.1f", a - b }') s"
    if [ -n "${KEEP:-}" ]; then
        mkdir -p "$KEEP" && cp "$tmp/k.cubin" "$tmp/v.txt" "$KEEP/"
    fi
fi
readelf -S -W "$tmp/k.cubin" >"$tmp/s.txt" 2>/dev/null
readelf -s -W "$tmp/k.cubin" >"$tmp/y.txt" 2>/dev/null
python3 - "$ptx" "$tmp/v.txt" "$tmp/s.txt" "$tmp/y.txt" <<'PY'
import re, sys
ptx_path, v_path, s_path, y_path = sys.argv[1:5]
ARITH = {"add", "sub", "mul", "fma", "mad", "div", "rcp", "sqrt", "rsqrt", "setp", "min", "max", "abs", "neg",
         "testp", "copysign", "cvt"}

# the PTX's functions: kind, own counts, the functions their bodies name (calls, direct or
# through a pointer; a call's callee is on a line of its own)
funcs, order, cur = {}, [], None
head = re.compile(r"^(?:\.visible\s+|\.weak\s+)?\.(entry|func)\s+(?:\([^)]*\)\s*)?([\w$]+)\s*\(")
bodies = {}
for line in open(ptx_path, encoding="utf-8", errors="replace"):
    m = head.match(line)
    if m and not line.rstrip().endswith(";"):
        cur = m.group(2)
        funcs[cur] = {"kind": m.group(1), "f64": 0, "f32": 0, "cvt": 0, "ptx": 0, "calls": set()}
        order.append(cur)
        bodies[cur] = []
        continue
    if cur is None:
        continue
    if line.startswith("}"):
        cur = None
        continue
    bodies[cur].append(line)
for name, body in bodies.items():
    f = funcs[name]
    for line in body:
        t = line.strip()
        for w in re.findall(r"[A-Za-z_$][\w$]*", t):
            if w in funcs and w != name:
                f["calls"].add(w)
        if not t or t.startswith(("//", "{", "}", ".", "$", "(", ")")) or t.endswith(","):
            continue
        f["ptx"] += 1
        op = t.split()[0]
        if op.startswith("@"):
            op = t.split()[1]
        parts = op.split(".")
        if parts[0] in ARITH:
            types = [p for p in parts[1:] if re.fullmatch(r"f(16|32|64)", p)]
            if parts[0] == "cvt" and "f64" in types and "f32" in types:
                f["cvt"] += 1
            elif "f64" in types:
                f["f64"] += 1
            elif "f32" in types:
                f["f32"] += 1


def reach(name):
    seen, stack = set(), [name]
    while stack:
        n = stack.pop()
        for c in funcs.get(n, {}).get("calls", ()):
            if c in funcs and c not in seen:
                seen.add(c)
                stack.append(c)
    return seen

# ptxas -v: registers of each entry, stack frame and spills of each function
props, cur = {}, None
for line in open(v_path):
    m = re.search(r"Function properties for ([\w$]+)", line)
    if m:
        cur = m.group(1)
        props.setdefault(cur, {})
        continue
    m = re.search(r"Compiling entry function '([\w$]+)'", line)
    if m:
        cur = m.group(1)
        props.setdefault(cur, {})
        continue
    if cur is None:
        continue
    m = re.search(r"(\d+) bytes stack frame, (\d+) bytes spill stores, (\d+) bytes spill loads", line)
    if m:
        props[cur].update(stack=int(m.group(1)), spill_st=int(m.group(2)), spill_ld=int(m.group(3)))
    m = re.search(r"Used (\d+) registers", line)
    if m:
        props[cur]["regs"] = int(m.group(1))
    m = re.search(r"(\d+) bytes cumulative stack size", line)
    if m:
        props[cur]["cumstack"] = int(m.group(1))

# the cubin's sections: .text.KERNEL and its size (the kernel with its device functions)
sass = {}
for line in open(s_path):
    m = re.search(r"\]\s+\.text\.([\w$]+)\s+\S+\s+[0-9a-f]+\s+[0-9a-f]+\s+([0-9a-f]+)", line)
    if m:
        sass[m.group(1)] = int(m.group(2), 16)
# the device functions' symbols, $KERNEL$NAME, and their sizes
fsass = {}
for line in open(y_path):
    parts = line.split()
    if len(parts) >= 8 and parts[3] == "FUNC":
        m = re.fullmatch(r"\$[\w]+\$([\w]+)", parts[-1])
        if m:
            size = int(parts[2], 16) if parts[2].startswith("0x") else int(parts[2])
            fsass[m.group(1)] = fsass.get(m.group(1), 0) + size

def short(n):
    m = re.match(r"_ZN12_GLOBAL__N_1(\d+)", n)
    return n[m.end():m.end() + int(m.group(1))] if m else n

print("kernel | registers | stack frame B | cumulative stack B | spill stores B | spill loads B | SASS KiB | "
      "SASS instructions | FP64 | FP32 | f32-f64 conversions | PTX instructions | device functions reached")
for n in order:
    if funcs[n]["kind"] != "entry":
        continue
    p, r = props.get(n, {}), reach(n)
    f64, f32, cvt = (funcs[n][k] + sum(funcs[c][k] for c in r) for k in ("f64", "f32", "cvt"))
    nptx = funcs[n]["ptx"] + sum(funcs[c]["ptx"] for c in r)
    b = sass.get(n, 0)
    print(f"{n} | {p.get('regs', '?')} | {p.get('stack', '?')} | {p.get('cumstack', '?')} | {p.get('spill_st', '?')} | "
          f"{p.get('spill_ld', '?')} | {b / 1024:.1f} | {b // 16} | {f64} | {f32} | {cvt} | {nptx} | {len(r)}")
funcs_only = [n for n in order if funcs[n]["kind"] == "func"]
if funcs_only:
    print()
    print("device function (called, not inlined) | stack frame B | spill stores B | spill loads B | SASS KiB | FP64 | "
          "FP32 | f32-f64 conversions | PTX instructions")
    for n in funcs_only:
        p = props.get(n, {})
        print(f"{short(n)} | {p.get('stack', '?')} | {p.get('spill_st', '?')} | {p.get('spill_ld', '?')} | "
              f"{fsass.get(n, 0) / 1024:.1f} | {funcs[n]['f64']} | {funcs[n]['f32']} | {funcs[n]['cvt']} | {funcs[n]['ptx']}")
PY
