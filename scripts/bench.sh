#!/usr/bin/env bash
# The benchmark suite: builds if needed, runs bench_build, bench_frame and
# bench_truth in turn, and writes their JSON, their printed tables (.txt),
# suite.json (the machine and each step's time) and PNG plots to one folder.
#
#   scripts/bench.sh [--quick] [--out DIR] [--build DIR | --bin DIR] [--only LIST]
#
#   --quick   small meshes and frames, few runs: checks that the whole suite
#             runs (about a minute), not a measurement; default --out is
#             then DIR/bench_quick of the build folder
#   --out     where results go (default bench/results)
#   --build   build folder, built with scripts/build.sh first (default build)
#   --bin     use the programs already in this folder; build nothing
#   --only    comma-separated steps out of build,frame,truth (default all);
#             plots are made from every result in --out
#
# Progress goes to stderr, the tables to stdout. Every file appears whole or
# not at all (written beside its name, then renamed).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
quick=0 out="" build="$root/build" bin="" only="build,frame,truth"
usage() { echo "usage: scripts/bench.sh [--quick] [--out DIR] [--build DIR | --bin DIR] [--only build,frame,truth]" >&2; exit 2; }
while [ $# -gt 0 ]; do
  case $1 in
    --quick) quick=1 ;;
    --out) [ $# -ge 2 ] || usage; out=$2; shift ;;
    --build) [ $# -ge 2 ] || usage; build=$2; shift ;;
    --bin) [ $# -ge 2 ] || usage; bin=$2; shift ;;
    --only) [ $# -ge 2 ] || usage; only=$2; shift ;;
    *) usage ;;
  esac
  shift
done
for step in ${only//,/ }; do
  case $step in build|frame|truth) ;; *) echo "bench.sh: unknown step '$step' in --only (build, frame, truth)" >&2; exit 2 ;; esac
done
say() { echo "bench.sh: $*" >&2; }
die() { say "$*"; exit 1; }

command -v gnuplot >/dev/null || die "gnuplot not found (scripts/deps.sh installs gnuplot-nox)"
command -v python3 >/dev/null || die "python3 not found (scripts/deps.sh installs it)"
if [ -z "$bin" ]; then
  say "building $build (scripts/build.sh)"
  "$root/scripts/build.sh" "$build" >&2 || die "the build of $build failed"
  bin="$build/bin"
fi
bin=$(cd "$bin" && pwd) || die "no folder $bin"
for program in bench_build bench_frame bench_truth; do
  [ -x "$bin/$program" ] || die "$bin/$program is missing (build it with scripts/build.sh)"
done
if [ -z "$out" ]; then
  if [ $quick = 1 ]; then out="$(dirname "$bin")/bench_quick"; else out="$root/bench/results"; fi
fi
mkdir -p "$out" || die "cannot create $out"
out=$(cd "$out" && pwd)
# A step killed halfway leaves its JSON's temporary file: clear those.
trap 'rm -f "$out"/*.tmp.* "$out"/*.txt.tmp' EXIT

quick_flag=() frame_flags=()
# The texture-space optimisation study takes minutes of close-up 1080p
# renders and is not the suite's: --quick still runs it, to keep it working.
[ $quick = 1 ] && quick_flag=(--quick) frame_flags=(--quick --optimizations)
steps_json=""
# run_step NAME COMMAND...: the command's tables go to stdout and NAME.txt.
run_step() {
  local name=$1
  shift
  say "$name: $(basename "$1") ${*:2}"
  local start=$SECONDS status=0
  # Line-buffered, so the tables show as they are measured.
  (cd "$root" && stdbuf -oL "$@") | tee "$out/$name.txt.tmp" || status=$?
  if [ $status != 0 ]; then
    mv "$out/$name.txt.tmp" "$out/$name.failed.txt"
    die "$name failed (exit $status): $* (its output so far: $out/$name.failed.txt)"
  fi
  mv "$out/$name.txt.tmp" "$out/$name.txt"
  local took=$((SECONDS - start))
  say "$name: done in ${took} s -> $out/$name.json"
  steps_json+="${steps_json:+, }\"$name\": $took"
}

suite_start=$SECONDS
for step in ${only//,/ }; do
  case $step in
    build)
      if [ $quick = 1 ]; then
        studies=(brute scaling cut memory)
      else
        # The issue's builder numbers and the cut map's targets (build time,
        # sam_build's memory on ~1M vertices); candidates (how C was chosen)
        # and dragon are bench_build's on demand.
        studies=(brute scaling large cut memory)
      fi
      run_step build "$bin/bench_build" "${quick_flag[@]}" --json "$out/build.json" --scans "$root/meshes/scans" \
        "${studies[@]}" ;;
    frame) run_step frame "$bin/bench_frame" "${frame_flags[@]}" --json "$out/frame.json" --scenes "$root/scenes" ;;
    truth) run_step truth "$bin/bench_truth" "${quick_flag[@]}" --json "$out/truth.json" --scenes "$root/scenes" ;;
  esac
done

# The machine, for docs/performance.md.
cpu=$(grep -m1 "model name" /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//' || echo unknown)
memory=$(awk '/MemTotal/ {printf "%.1f", $2 / 1048576}' /proc/meminfo)
commit=$(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown)
cat > "$out/suite.json.tmp" <<JSON
{
  "date": "$(date -u +%Y-%m-%dT%H:%M:%SZ)",
  "commit": "$commit",
  "quick": $([ $quick = 1 ] && echo true || echo false),
  "cpu": "$cpu",
  "cores": $(nproc),
  "memory_gib": $memory,
  "load_average_at_end": "$(cut -d' ' -f1-3 /proc/loadavg)",
  "step_seconds": {$steps_json},
  "total_seconds": $((SECONDS - suite_start))
}
JSON
mv "$out/suite.json.tmp" "$out/suite.json"

say "plots"
python3 "$root/bench/plot.py" "$out" || die "plotting $out failed"
say "done in $((SECONDS - suite_start)) s: $out"
