#!/usr/bin/env bash
# Every kernel figure of BENCHMARKS.md ("The kernels in one run") in one sitting, on an idle
# machine, in this order:
#   1. BVH closest hit beside Embree 3 and the `bvh` crate (needs `libembree-dev`);
#   2. the photon kd-tree beside kiddo (knn and radius queries, exact results asserted);
#   3. thread scaling, 1 against 2 threads: the machine, the photon pass, a whole render;
#   4. photon shooting on one pinned core, ours and LuxCore PhotonGI's (needs a Python with
#      pyluxcore 2.11: LUXCORE_PYTHON, default python3);
#   5. the photon pass's peak memory at 10^8 photons (about 3 GB and 3 minutes).
# Usage: benches/kernels.sh [LOG]   (default: kernels.log)
set -euo pipefail
cd "$(dirname "$0")/.."
log="${1:-kernels.log}"
lux="${LUXCORE_PYTHON:-python3}"
exec > >(tee "$log") 2>&1
echo "# kernels, $(date -u '+%Y-%m-%d %H:%M UTC'), $(nproc) cores, load: $(cut -d' ' -f1-3 /proc/loadavg)"
cargo build --release --bin photonmap-dev --benches --examples --features embree-bench -q
echo; echo "## 1. BVH"
cargo bench -q --features embree-bench --bench bvh -- --test
echo; echo "## 2. kd-tree"
cargo run -q --release --example kdtree_cputime
echo; echo "## 3. Thread scaling"
cargo bench -q --bench scaling
echo; echo "## 4. Photon shooting on one core"
taskset -c 0 cargo bench -q --bench photons -- --one-core
taskset -c 0 "$lux" benches/luxcore_photons.py --runs 3
echo; echo "## 5. 10^8 photons"
stats="$(mktemp -d)"
/usr/bin/time -v target/release/photonmap-dev render -o "$stats/out.exr" --quiet \
  --quality draft --width 16 --height 16 --spp 1 --photons 100000000 --caustic-photons 0 \
  --final-gather-rays 8 --threads 2 --stats "$stats/stats.json" 2>&1 |
  grep -E 'Maximum resident|Elapsed'
python3 - "$stats/stats.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
g = [m for m in s["photon_maps"] if m["map"] == "global"][0]
print(f"global map: {g['stored']} photons stored, {g['emitted']} paths, memory_bytes {g['memory_bytes']}"
      f" ({g['memory_bytes'] / g['stored']:.1f} B/photon), kd-tree {g['kdtree_seconds']:.1f} s")
e = s["memory_estimate"]
print(f"estimate: total_bytes {e['total_bytes']}, peak_bytes {e['peak_bytes']}")
print("seconds:", {k: round(v, 1) for k, v in s["seconds"].items()})
PY
rm -rf "$stats"
