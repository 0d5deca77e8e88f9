#!/usr/bin/env bash
# The runtime's files call each other in layers, never back into a file that
# called them (scripts/check_layers.py), and the checker finds a cycle when
# there is one. Args: BIN_DIR SOURCE_DIR TMP_DIR
set -u
src=$2 tmp=$3
rm -rf "$tmp" && mkdir -p "$tmp"
fail() { echo "FAIL: $*"; exit 1; }

out=$(python3 "$src/scripts/check_layers.py" "$src/sam_runtime/src" 2>&1) || fail "$out"
grep -q "no cycle" <<<"$out" || fail "no verdict in: $out"

# Two files that call each other must be refused, naming both.
printf 'int b_fn(void);\nint a_fn(void)\n{\n    return b_fn();\n}\n' > "$tmp/a.c"
printf 'int a_fn(void);\nint b_fn(void)\n{\n    return a_fn() + 1;\n}\n' > "$tmp/b.c"
out=$(python3 "$src/scripts/check_layers.py" "$tmp" 2>&1) && fail "a cycle was accepted: $out"
grep -q "cycle: a.c -> b.c -> a.c" <<<"$out" || fail "cycle not named: $out"
echo "layers: ok"
