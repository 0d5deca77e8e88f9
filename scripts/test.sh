#!/usr/bin/env bash
# The whole test suite: installs dependencies, then builds and runs ctest in
#   build/        the normal RelWithDebInfo build (unit, cli and gl tests)
#   build-release/ a Release (-O3) build and its unit tests
#   build-asan/   the same tests under AddressSanitizer + UBSan
#   build-fuzz/   clang libFuzzer targets, each run for a bounded time
# Set SAM_FUZZ_SECONDS (default 30) to change the time per fuzzer.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/deps.sh"
jobs=$(nproc)

"$root/scripts/build.sh" "$root/build"
ctest --test-dir "$root/build" --output-on-failure -j"$jobs"

# A Release build (-O3) too: GCC's maybe-uninitialized analysis differs by
# optimisation level, and -Werror would stop a user's Release build.
"$root/scripts/build.sh" "$root/build-release" -DCMAKE_BUILD_TYPE=Release
ctest --test-dir "$root/build-release" --output-on-failure -j"$jobs" -L unit

"$root/scripts/build.sh" "$root/build-asan" -DSAM_SANITIZE=ON
ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir "$root/build-asan" --output-on-failure -j"$jobs"

CC=clang CXX=clang++ "$root/scripts/build.sh" "$root/build-fuzz" -DSAM_FUZZ=ON
seconds=${SAM_FUZZ_SECONDS:-30}
for fuzzer in "$root"/build-fuzz/fuzz/fuzz_*; do
  [ -x "$fuzzer" ] || continue
  name=$(basename "$fuzzer")
  corpus="$root/build-fuzz/corpus-$name"
  rm -rf "$corpus" && mkdir -p "$corpus"
  cp "$root/fuzz/corpus/${name#fuzz_}/"* "$corpus/" 2>/dev/null || true
  echo "fuzz: $name for ${seconds}s"
  (cd "$root/build-fuzz" && "$fuzzer" -max_total_time="$seconds" -timeout=60 -rss_limit_mb=4096 \
     -print_final_stats=0 "$corpus" > "$root/build-fuzz/$name.log" 2>&1) \
    || { tail -50 "$root/build-fuzz/$name.log"; echo "fuzz: $name FAILED"; exit 1; }
  grep -E "^Done|^#[0-9]+.*DONE" "$root/build-fuzz/$name.log" | tail -1 || true
done
echo "test.sh: all suites passed"
