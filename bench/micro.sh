#!/usr/bin/env bash
# Micro-benchmarks: incremental distance map vs full rebuild, and Perfect Match vs CICP.
#
#   bench/micro.sh [extra Google Benchmark flags, e.g. --benchmark_filter=PM_]
#
# Builds Release into build/ (override with BUILD_DIR=...), runs bench_distance_map and
# bench_alignment with 5 repetitions (aggregates only), merges both JSON reports into
# bench/results/micro.json and prints a Markdown summary with the ratios (medians of the
# 5 repetitions) on stdout; the benchmarks' own console output goes to stderr.
# Timings are CPU time; on a loaded machine they are noisy.
set -euo pipefail

cd "$(dirname "$0")/.."
BUILD_DIR=${BUILD_DIR:-build}
OUT=bench/results/micro.json

cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release >&2
cmake --build "$BUILD_DIR" -j2 --target bench_distance_map bench_alignment >&2

mkdir -p bench/results
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

for b in bench_distance_map bench_alignment; do
	echo "== $b" >&2
	"$BUILD_DIR/bin/$b" --benchmark_repetitions=5 --benchmark_report_aggregates_only=true \
		--benchmark_out="$tmp/$b.json" --benchmark_out_format=json "$@" >&2
done

python3 - "$OUT" "$tmp/bench_distance_map.json" "$tmp/bench_alignment.json" <<'EOF'
import json, sys

out, *inputs = sys.argv[1:]
merged = {"context": {}, "benchmarks": []}
for path in inputs:
    with open(path) as f:
        d = json.load(f)
    binary = path.rsplit("/", 1)[-1][:-len(".json")]
    for k, v in d["context"].items():
        merged["context"].setdefault(k, v)
    for b in d["benchmarks"]:
        b["binary"] = binary
        merged["benchmarks"].append(b)
with open(out, "w") as f:
    json.dump(merged, f, indent=2)

med = {b["run_name"]: b for b in merged["benchmarks"]
       if b.get("run_type") == "aggregate" and b.get("aggregate_name") == "median"}
cv = {b["run_name"]: b for b in merged["benchmarks"]
      if b.get("run_type") == "aggregate" and b.get("aggregate_name") == "cv"}

def t(seconds):
    for unit, f in (("s", 1), ("ms", 1e3), ("µs", 1e6), ("ns", 1e9)):
        if seconds * f >= 1:
            return f"{seconds * f:.3g} {unit}"
    return f"{seconds * 1e9:.3g} ns"

def spread(name, key):
    c = cv.get(name, {}).get(key)
    return f"±{100 * c:.0f}%" if c is not None else ""

ctx = merged["context"]
print(f"## Micro-benchmarks ({ctx.get('date', '')}, {ctx.get('num_cpus', '?')} CPUs, "
      f"load {', '.join(f'{x:.2f}' for x in ctx.get('load_avg', []))})\n")
print("Medians of 5 repetitions (CPU time); ± is the coefficient of variation.\n")

print("### Distance map: incremental update vs full rebuild\n")
print(f"{ctx.get('floor', '')}; {ctx.get('obstacle_cells', '?')} obstacle cells.\n")
print("| benchmark | cells changed | cells processed | time per update | full rebuild / this |")
print("|---|---:|---:|---:|---:|")
full = med.get("BM_FullRebuild")
for name, b in med.items():
    if not (name.startswith("BM_IncrementalUpdate") or name == "BM_FullRebuild"):
        continue
    ratio = f"{full['time_per_update'] / b['time_per_update']:.0f}×" if full else "n/a"
    print(f"| {name} | {b['cells_changed']:.0f} | {b['cells_processed']:.0f} | "
          f"{t(b['time_per_update'])} {spread(name, 'time_per_update')} | {ratio} |")
for name in ("BM_DistanceAt", "BM_DistanceAtGrad"):
    if name in med:
        print(f"\n`{name}`: {t(med[name]['time_per_query'])} per query {spread(name, 'time_per_query')}", end="")
print("\n")

print("### Scan alignment: Perfect Match vs CICP\n")
print(f"{ctx.get('world', '')}; {ctx.get('queries', '')}.\n")
print("| matcher | beams | time per alignment | mean err (mm) | max err (mm) | mean err (°) | iterations | fails | time / PM_RPROP |")
print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
rows = [(n, b) for n, b in med.items() if "/beams:" in n]
order = ["PM_RPROP", "PM_GaussNewton", "PM_LevenbergMarquardt", "CICP_points", "CICP_points_ini", "CICP_grid"]
rank = lambda m: order.index(m) if m in order else len(order)
for name, b in sorted(rows, key=lambda r: (int(r[0].split("beams:")[1]), rank(r[0].split("/")[0]), r[0])):
    matcher, beams = name.split("/beams:")
    pm = med.get(f"PM_RPROP/beams:{beams}")
    rel = f"{b['time_per_align'] / pm['time_per_align']:.2f}" if pm else "n/a"
    print(f"| {matcher} | {beams} | {t(b['time_per_align'])} {spread(name, 'time_per_align')} | "
          f"{b['err_mm']:.1f} | {b['max_err_mm']:.1f} | {b['err_deg']:.2f} | {b['iters']:.1f} | "
          f"{b['fails']:.0f} | {rel} |")
print()
for beams in sorted({int(n.split("beams:")[1]) for n, _ in rows}):
    pm = med.get(f"PM_RPROP/beams:{beams}")
    for icp in ("CICP_points", "CICP_points_ini", "CICP_grid"):
        c = med.get(f"{icp}/beams:{beams}")
        if pm and c:
            r = c["time_per_align"] / pm["time_per_align"]
            verdict = f"PM is {r:.2f}× faster" if r >= 1 else f"PM is {1 / r:.2f}× slower"
            print(f"- {beams} beams, PM_RPROP vs {icp}: {t(pm['time_per_align'])} vs "
                  f"{t(c['time_per_align'])} per alignment ({verdict}); error "
                  f"{pm['err_mm']:.1f} mm vs {c['err_mm']:.1f} mm")
if full:
    for name, b in med.items():
        if name.startswith("BM_IncrementalUpdate"):
            print(f"- Distance map, {b['cells_changed']:.0f} cells changed: incremental "
                  f"{t(b['time_per_update'])} vs full rebuild {t(full['time_per_update'])} "
                  f"({full['time_per_update'] / b['time_per_update']:.0f}× faster)")
print(f"\nFull results: {out}")
EOF
