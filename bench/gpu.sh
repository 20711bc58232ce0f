#!/bin/sh
# gpu.sh - brume's GPU timings (docs/gpu.md, "Speed"): the floors of issue 35 on the GPU and
# on the same machine's own cores, in one run, and where the kernel's time goes (Nsight
# Compute, when it is there). Run by tests/gpu/run.sh after its checks:
#
#   sh bench/gpu.sh BRUME OUTDIR DATA
#
# BRUME is the brume tool (with its libraries found), DATA the folder holding wdas.nvdb.
# Times are whole process (start-up, load, prepare, passes, write) with the driver's
# compile of the PTX already cached; brume's own line gives the render's time.
set -u
br=$1; out=$2; data=$3
now() { date +%s.%N; }
sub() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.3f", a - b }'; }
wdas="scenes/wdas-dense.json --set media.0.density.file=$data/wdas.nvdb"
echo "== timings: wdas-dense 256 x 256 on the GPU, whole process (start-up, load, prepare, passes, write)"
for spp in 1 64 64 64 256 1024; do
    t0=$(now)
    line=$(timeout 120 "$br" render $wdas --spp $spp --device cuda -o "$out/t.exr" 2>&1 | tail -1)
    echo "wdas-dense gpu $spp spp: $(sub "$(now)" "$t0") s; $line"
done
t0=$(now)
line=$(timeout 120 "$br" render $wdas --spp 64 -o "$out/t.exr" 2>&1 | tail -1)
echo "wdas-dense cpu ($(nproc) cores) 64 spp: $(sub "$(now)" "$t0") s; $line"
echo "== budgets on the GPU: --time 3 (wdas-dense), --noise 0.05 (the chromatic cloud over a ground)"
t0=$(now)
line=$(timeout 60 "$br" render $wdas --spp 100000 --time 3 --device cuda -o "$out/t.exr" 2>&1 | tail -1)
echo "wdas-dense --time 3: $(sub "$(now)" "$t0") s whole process; $line"
t0=$(now)
line=$(timeout 60 "$br" render tests/gpu/chromatic-emissive.json --noise 0.05 --device cuda -o "$out/t.exr" 2>&1 | tail -1)
echo "chromatic --noise 0.05: $(sub "$(now)" "$t0") s whole process; $line"
echo "== the default scene at its 3 % noise target, whole process"
for dev in cuda cpu; do
    t0=$(now)
    line=$(timeout 150 "$br" render --device $dev -o "$out/default-$dev.png" 2>&1 | tail -1)
    echo "default $dev: $(sub "$(now)" "$t0") s; $line"
done

ncu=$(command -v ncu || ls /opt/nvidia/nsight-compute/*/ncu /usr/local/cuda/bin/ncu 2>/dev/null | head -1)
if [ -n "$ncu" ] && [ "${NCU:-1}" = 1 ]; then
    # the pass after the first (1 spp): 2^21 samples (32 spp), as most of a render's launches
    echo "== ncu ($ncu) on brume_paths: wdas-dense 256 x 256, the second pass's launch"
    timeout 200 "$ncu" --launch-skip 1 --launch-count 1 --kernel-name brume_paths --section SpeedOfLight \
        --section Occupancy --section LaunchStats --section WarpStateStats --section SchedulerStats \
        --section MemoryWorkloadAnalysis "$br" render $wdas --spp 64 --device cuda -o "$out/n.exr" 2>&1 |
        grep -v "^==PROF==" | grep -E "Duration|Throughput|Occupancy|Registers|Local|Block Limit|Warp Cycles|Stall|Eligible|Issued|Hit Rate|Threads|Waves|Achieved|Theoretical|Active Warps|No Eligible" | head -60
    echo "== ncu: why warps wait (cycles per issued instruction, by stall reason), same launch"
    timeout 150 "$ncu" --launch-skip 1 --launch-count 1 --kernel-name brume_paths \
        --metrics "regex:smsp__average_warps_issue_stalled_.*_per_issue_active\.ratio,smsp__thread_inst_executed_per_inst_executed.ratio,smsp__inst_executed.sum,sm__warps_active.avg.pct_of_peak_sustained_active" \
        "$br" render $wdas --spp 64 --device cuda -o "$out/n.exr" 2>&1 | grep -v "^==PROF==" | grep -E "smsp__|sm__" |
        awk '{ if ($NF + 0 >= 0.05 || $1 !~ /stalled/) print }' | head -40
fi
