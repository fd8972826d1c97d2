#!/usr/bin/env bash
# The GPU backend on a real GPU: one run that records the adapter and its driver, times
# `bench --backend gpu` (W1-W4, the snow storm, 10 M sprites, with and without
# --fixed-function-blending, and the CPU backend on the same machine for scale), and runs the
# conformance suite and the GPU crate's tests on that adapter. docs/PERFORMANCE.md ("On a real
# GPU") and crates/gpu/README.md record what it gave.
#
#   crates/gpu/gpu-check.sh OUT              build with cargo here, then run; results in OUT
#   crates/gpu/gpu-check.sh --build BIN      only build: the release CLI and the test programs
#                                            into BIN, for a GPU machine without a toolchain
#   crates/gpu/gpu-check.sh --prebuilt BIN OUT   run with what --build put in BIN
#
# Run from the repository root. Environment: FRAMES (timed frames per bench row, default 20),
# POINTS_10M (points of the large rows, default 10000000). It does not stop at a failing step:
# each step's exit status is in OUT/summary.txt, and the script exits 1 if any step failed.
# The Vulkan loader must be installed; NVIDIA's driver files are found under /usr/local/nvidia
# when the loader finds no driver by itself.
set -u

usage() {
    sed -n '8,10p' "$0" >&2
    exit 2
}

[ -f Cargo.toml ] && [ -d crates/gpu ] || { echo "gpu-check: run it from the repository root" >&2; exit 2; }

build() {
    local bin=$1
    mkdir -p "$bin" || exit 2
    cargo build --release -p pointillist-cli || exit 2
    cp target/release/pointillist "$bin/" || exit 2
    # Each test program, named for its test target (integration, embed, workloads).
    {
        cargo test --release --no-run --message-format=json -p pointillist-conformance --test integration &&
            cargo test --release --no-run --message-format=json -p pointillist-gpu --tests
    } >"$bin/build.json" || exit 2
    python3 - "$bin" <<'PY' || exit 2
import json, shutil, sys
for line in open(f"{sys.argv[1]}/build.json"):
    m = json.loads(line)
    exe = m.get("executable")
    name = m.get("target", {}).get("name")
    if exe and name in ("integration", "embed", "workloads"):
        shutil.copy(exe, f"{sys.argv[1]}/{name}")
PY
    rm -f "$bin/build.json"
    for f in pointillist integration embed workloads; do
        [ -x "$bin/$f" ] || { echo "gpu-check: the build made no $f" >&2; exit 2; }
    done
    strip "$bin"/* 2>/dev/null
    # The test programs find the suite's files by the path they were built in.
    pwd >"$bin/root.txt"
}

case ${1-} in
--build)
    [ $# -eq 2 ] || usage
    build "$2"
    exit 0
    ;;
--prebuilt)
    [ $# -eq 3 ] || usage
    bin=$(cd "$2" && pwd) || exit 2
    out=$3
    ;;
-* | '') usage ;;
*)
    [ $# -eq 1 ] || usage
    out=$1
    bin=$PWD/target/gpu-check
    build "$bin"
    ;;
esac

mkdir -p "$out" || exit 2
out=$(cd "$out" && pwd)
root=$(cat "$bin/root.txt")
if [ "$root" != "$PWD" ] && [ ! -e "$root" ]; then
    mkdir -p "$(dirname "$root")" && ln -s "$PWD" "$root" ||
        { echo "gpu-check: the test programs need this checkout at $root" >&2; exit 2; }
fi
if ! ls /usr/share/vulkan/icd.d/*nvidia* /etc/vulkan/icd.d/*nvidia* >/dev/null 2>&1 &&
    [ -f /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json ] && [ -z "${VK_DRIVER_FILES-}" ]; then
    export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
fi

frames=${FRAMES:-20}
big=${POINTS_10M:-10000000}
summary=$out/summary.txt
: >"$summary"
failed=0

# step NAME LOG COMMAND...: runs COMMAND, its output appended to OUT/LOG, and records the time
# and exit status in the summary.
step() {
    local name=$1 log=$out/$2
    shift 2
    local start=$SECONDS
    { echo "### $name"; echo "\$ $*"; } >>"$log"
    "$@" >>"$log" 2>&1
    local rc=$?
    echo >>"$log"
    printf '%-44s exit %d  %4d s\n' "$name" "$rc" $((SECONDS - start)) | tee -a "$summary"
    [ $rc -eq 0 ] || failed=1
}

{
    date -u
    uname -a
    grep -m1 'model name' /proc/cpuinfo
    echo "cores: $(nproc)"
    command -v nvidia-smi >/dev/null && nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm --format=csv
    echo "VK_DRIVER_FILES=${VK_DRIVER_FILES-}"
    echo "commit: $(git rev-parse HEAD 2>/dev/null || echo unknown)"
} >"$out/machine.txt" 2>&1

p=$bin/pointillist
export POINTILLIST_REQUIRE_GPU=1
# One workload a step, so that one the backend refuses (the exact blending path has a pass
# limit per adapter) leaves the others timed.
for w in w1 w2 w3 w4 snow; do
    step "bench gpu $w" bench.txt "$p" bench --backend gpu --workloads $w --frames "$frames"
    step "bench gpu $w, fixed-function blending" bench.txt "$p" bench --backend gpu --fixed-function-blending --workloads $w --frames "$frames"
done
for w in w1 w2; do
    step "bench gpu $w at $big points" bench.txt "$p" bench --backend gpu --workloads $w --points "$big" --frames "$frames"
done
step "bench cpu w1-w4, snow (same machine)" bench.txt "$p" bench --workloads w1,w2,w3,w4,snow --frames "$frames"
step "conformance suite, GPU adapter" suite.txt "$bin/integration"
step "gpu crate: workloads vs CPU" gpu-tests.txt "$bin/workloads"
step "gpu crate: embedding" gpu-tests.txt "$bin/embed"

# The pictures of any GPU difference (testkit writes them under target/).
diffs=$(find target/gpu-diffs target/golden-failures -name '*.png' -newer "$out/machine.txt" 2>/dev/null | head -200)
if [ -n "$diffs" ]; then
    printf '%s\n' "$diffs" | tar -czf "$out/diffs.tar.gz" -T - 2>/dev/null
fi
echo "results in $out" >&2
exit $failed
