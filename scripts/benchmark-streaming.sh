#!/usr/bin/env bash
# Measures the streaming mode on a synthetic volume of at least 2^31 voxels written to disk: the
# filter in memory, and streamed under memory limits of 1 GiB and 256 MiB, each timed with its
# read, filter and write split, peak resident memory (as the process measured it) and page faults;
# and the in-memory filter's time per voxel on 16 M voxels of the same kind (median of fifteen runs), for the
# throughput target (streamed filtering within twice that per voxel, plus reading and writing the file once);
# and the in-memory run's peak beyond its input, per voxel. Three rounds: the table has the median of each.
#
#   scripts/benchmark-streaming.sh DIR [NX NY NZ]    (default 2048 1024 1024: 2 GiB of uint8)
#
# DIR receives the volumes and outputs (about 3 times the volume). Uses the tools in
# $SMALLISO_BUILD_DIR (default ./build; run scripts/setup.sh first). Run it on a quiet machine.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${SMALLISO_BUILD_DIR:-$root/build}
dir=${1:?usage: scripts/benchmark-streaming.sh DIR [NX NY NZ]}
nx=${2:-2048}
ny=${3:-1024}
nz=${4:-1024}
filter=$build/apps/SmallIsoComponentFilter
generate=$build/benchmark/SmallIsoComponentLargeVolume
mkdir -p "$dir"
[[ -x $filter && -x $generate ]] || { echo "benchmark-streaming: build the project first (scripts/setup.sh)" >&2; exit 2; }

volume=$dir/large.mhd
small=$dir/small-16M.mhd
[[ -f $volume ]] || "$generate" "$volume" "$nx" "$ny" "$nz"
[[ -f $small ]] || "$generate" "$small" 256 256 256

# run NAME INPUT OUTPUT [OPTIONS...]: one run of the filter, its JSON in DIR/NAME.json, its
# /usr/bin/time record in DIR/NAME.time.
run() {
  local name=$1 input=$2 output=$3
  shift 3
  rm -f "$output" "${output%.*}.raw"
  sync
  /usr/bin/time -v -o "$dir/$name.time" "$filter" "$input" "$output" --isovalue 127.5 --max-size 20 \
    --no-compression --quiet --stats "$dir/$name.json" "$@"
}
# Three rounds of the three large runs, interleaved: the filter times of one run move by a third
# on a virtual machine; the table shows the run with the median filter time of each kind.
for round in 1 2 3; do
  for i in 1 2 3 4 5; do run "small-in-memory-$round-$i" "$small" "$dir/small-out.mhd"; done
  run "in-memory-$round" "$volume" "$dir/out-memory.mhd"
  run "streamed-1G-$round" "$volume" "$dir/out-1G.mhd" --memory-limit 1G
  run "streamed-256M-$round" "$volume" "$dir/out-256M.mhd" --memory-limit 256M
  cmp "$dir/out-memory.raw" "$dir/out-1G.raw" && cmp "$dir/out-memory.raw" "$dir/out-256M.raw" ||
    { echo "benchmark-streaming: a streamed output differs from the in-memory output" >&2; exit 1; }
done
echo "benchmark-streaming: the streamed outputs equal the in-memory output byte for byte in every round"

python3 - "$dir" <<'PY'
import json, re, sys
dir = sys.argv[1]
def load(name):
    stats = json.load(open(f"{dir}/{name}.json"))["statistics"]
    timing = open(f"{dir}/{name}.time").read()
    def field(label):
        return float(re.search(re.escape(label) + r": ([0-9.:]+)", timing).group(1).split(":")[-1])
    wall = re.search(r"Elapsed \(wall clock\) time.*: (.*)", timing).group(1)
    parts = [float(p) for p in wall.split(":")]
    stats["wall"] = sum(p * 60 ** i for i, p in enumerate(reversed(parts)))
    stats["faults"] = int(field("Minor (reclaiming a frame) page faults"))
    stats["system"] = field("System time (seconds)")
    return stats
# The 16 M-voxel run takes milliseconds: the median of its fifteen runs (five a round).
small = sorted(load(f"small-in-memory-{r}-{i}")["seconds"] for r in (1, 2, 3) for i in range(1, 6))
voxels = json.load(open(f"{dir}/in-memory-1.json"))["input"]["size"]
n = voxels[0] * voxels[1] * voxels[2]
per_voxel = small[len(small) // 2] / (256 ** 3)
print(f"{n} voxels; in-memory filter on 16 M voxels: {per_voxel * 1e9:.2f} ns per voxel "
      f"(median of {len(small)}; {small[0] / 256 ** 3 * 1e9:.2f} to {small[-1] / 256 ** 3 * 1e9:.2f})")
print("| run | wall s | read s | filter s | write s | peak resident MiB | limit MiB | slab planes | minor faults | system s | filter / (2 x per-voxel x N) | ratios of the 3 rounds |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|")
medians = {}
for name in ("in-memory", "streamed-1G", "streamed-256M"):
    rounds = sorted((load(f"{name}-{r}") for r in (1, 2, 3)), key=lambda s: s["seconds"])
    s = medians[name] = rounds[1]
    limit = s["memory_limit_bytes"] >> 20 if s["memory_limit_bytes"] else "-"
    ratios = ", ".join(f"{r['seconds'] / (2 * per_voxel * n):.2f}" for r in rounds)
    ratio = s["seconds"] / (2 * per_voxel * n)
    print(f"| {name} | {s['wall']:.1f} | {s.get('read_seconds', 0):.1f} | {s['seconds']:.1f} | "
          f"{s.get('write_seconds', 0):.1f} | {s['peak_resident_bytes'] >> 20} | {limit} | {s.get('slab_planes', '-')} | "
          f"{s['faults']} | {s['system']:.1f} | {ratio:.2f} | {ratios} |")
# In memory the tool filters in place: what it holds beyond the input's voxels, per voxel (the
# target is at most 0.1 byte), measured (the process's peak) and as the filter counted it.
memory = medians["in-memory"]
pixel_bytes = {"uint8": 1, "int8": 1, "uint16": 2, "int16": 2, "uint32": 4, "int32": 4, "float32": 4, "float64": 8}
input_bytes = n * pixel_bytes[json.load(open(f"{dir}/in-memory-1.json"))["input"]["pixel_type"]]
print(f"in memory beyond the input: {(memory['peak_resident_bytes'] - input_bytes) / n:.3f} bytes per voxel "
      f"resident (the whole process), {memory['peak_extra_bytes'] / n:.3f} counted by the filter")
PY
