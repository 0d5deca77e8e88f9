#!/usr/bin/env bash
# Every library's files call each other in layers, never back into a file
# that called them (scripts/check_layers.py), and the checker finds a cycle
# when there is one. Args: BIN_DIR SOURCE_DIR TMP_DIR
set -u
src=$2 tmp=$3
rm -rf "$tmp" && mkdir -p "$tmp"
fail() { echo "FAIL: $*"; exit 1; }

core=("$src"/sam_core/src "$src"/sam_core/src/*/)
for dirs in "${core[*]}" sam_builder/src sam_app/src sam_runtime/src sam_truth/src sam_viewer/src; do
  args=()
  for d in $dirs; do [[ $d = /* ]] && args+=("$d") || args+=("$src/$d"); done
  out=$(python3 "$src/scripts/check_layers.py" "${args[@]}" 2>&1) || fail "$dirs: $out"
  grep -q "no cycle" <<<"$out" || fail "no verdict for $dirs in: $out"
done

# Two files that call each other must be refused, naming both.
printf 'int b_fn(void);\nint a_fn(void)\n{\n    return b_fn();\n}\n' > "$tmp/a.c"
printf 'int a_fn(void);\nint b_fn(void)\n{\n    return a_fn() + 1;\n}\n' > "$tmp/b.c"
out=$(python3 "$src/scripts/check_layers.py" "$tmp" 2>&1) && fail "a cycle was accepted: $out"
grep -q "cycle: a.c -> b.c -> a.c" <<<"$out" || fail "cycle not named: $out"
echo "layers: ok"
