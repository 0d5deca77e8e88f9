#!/usr/bin/env bash
# Proves that a change leaves every output bit for bit as it was: builds
# REV (a git revision, default origin/main or HEAD~1) in its own worktree,
# runs the same jobs with its programs and with this tree's, and compares
# every file they write byte for byte:
#   - the demo (scripts/demo.sh's build, info, profile, preview and render);
#   - every scene in scenes/: the .sam of its mesh, material and scale, and
#     its render (EXR, PNG and per-vertex CSV; animated scenes 3 frames);
#   - every comparison scene (scenes/compare_*.json) rendered with each
#     technique, and sam_compare's images and report on the slab scenes with
#     a small ground truth.
# Timings are the one thing allowed to differ: the .sam's build time and the
# reports' seconds are zeroed on both sides before the comparison.
#
#   scripts/check_identical.sh [REV] [OUT_DIR]   (OUT_DIR default out/identical)
# Needs this tree built in build/ (scripts/build.sh). Scenes whose scans are
# missing are fetched by meshes/fetch_scans.sh. Exits 1 when any file differs.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
rev=${1:-HEAD~1}
out=${2:-$root/out/identical}
new_bin=${SAM_BUILD_DIR:-$root/build}/bin
[ -x "$new_bin/sam_render" ] || { echo "check_identical.sh: no $new_bin/sam_render; run scripts/build.sh first" >&2; exit 1; }
ref_src=$root/build-ref/src
ref_bin=$root/build-ref/build/bin
commit=$(git -C "$root" rev-parse --verify "$rev^{commit}") \
  || { echo "check_identical.sh: '$rev' is not a revision of this repository" >&2; exit 1; }

# The reference build: a detached worktree at REV, rebuilt only when REV moved.
if [ "$(cat "$root/build-ref/commit" 2>/dev/null)" != "$commit" ]; then
  echo "check_identical.sh: building $rev ($commit) in build-ref/" >&2
  git -C "$root" worktree remove --force "$ref_src" 2>/dev/null || rm -rf "$ref_src"
  git -C "$root" worktree prune
  mkdir -p "$root/build-ref"
  git -C "$root" worktree add --detach "$ref_src" "$commit" > /dev/null
  "$ref_src/scripts/build.sh" "$root/build-ref/build" > "$root/build-ref/build.log" 2>&1 \
    || { tail -30 "$root/build-ref/build.log" >&2; exit 1; }
  echo "$commit" > "$root/build-ref/commit"
fi
"$root/meshes/fetch_scans.sh" > /dev/null

# jobs BIN DIR: every output into DIR.
jobs() {
  local bin=$1 dir=$2
  rm -rf "$dir" && mkdir -p "$dir"
  echo "check_identical.sh: running $bin" >&2
  (
    set -e
    cd "$dir"
    q() { "$@" > /dev/null 2>> "$dir/stderr.log"; }
    # The demo.
    q "$bin/sam_build" "$root/meshes/ear.obj" -o demo_ear.sam --material skin --mm-per-unit 60 --quiet
    "$bin/sam_info" demo_ear.sam > demo_info.txt 2>&1
    q "$bin/sam_profile_image" skin -o demo_profile_skin.png
    q "$bin/sam_preview" demo_ear.sam -o demo_ear_translucency.png
    q "$bin/sam_render" "$root/scenes/ear_backlit.json" -o demo_render.exr --png demo_render.png --passes 4
    # Every scene: its map and its picture.
    for scene in "$root"/scenes/*.json; do
      name=$(basename "$scene" .json)
      read -r mesh material scale value animated < <(python3 - "$scene" <<'PY'
import json, os, sys
s = json.load(open(sys.argv[1]))
sc = s.get("scale", {})
kind, v = ("--mm-per-unit", sc["mm_per_unit"]) if "mm_per_unit" in sc else ("--size-mm", sc.get("size_mm", 60))
mesh = os.path.normpath(os.path.join(os.path.dirname(sys.argv[1]), s["mesh"]))
anim = 1 if s.get("deformers") or s.get("keyframes") else 0
print(mesh, s.get("material", "skin"), kind, v, anim)
PY
)
      q "$bin/sam_build" "$mesh" -o "$name.sam" --material "$material" "$scale" "$value" --quiet
      if [ "$animated" = 1 ]; then
        q "$bin/sam_render" "$scene" -o "$name.exr" --png "$name.png" --animate 3
      else
        q "$bin/sam_render" "$scene" -o "$name.exr" --png "$name.png" --passes 2 --dump-vertices "$name.csv"
      fi
    done
    # The comparison scenes under every technique (tsm needs texture space).
    for scene in "$root"/scenes/compare_*.json; do
      name=$(basename "$scene" .json)
      for t in sam none transmittance tsm; do
        d=()
        [ "$t" = tsm ] && d=(--diffusion texture)
        q "$bin/sam_render" "$scene" -o "${name}_$t.exr" --technique "$t" "${d[@]}" --translucency-only || true
      done
    done
    # sam_compare end to end on small truths.
    for name in slab_area slab_environment; do
      q "$bin/sam_compare" "$root/scenes/compare_$name.json" -o "cmp_$name" --truth-samples 4096 \
        --samples-sweep 3,5
    done
    # Timings are the one thing allowed to change: zero them.
    python3 - . <<'PY'
import os, re, struct, sys
secs = re.compile(rb'("(?:build_)?seconds"|"map_build_seconds")\s*:\s*[0-9.eE+-]+')
for d, _, files in os.walk(sys.argv[1]):
    for f in files:
        p = os.path.join(d, f)
        if f.endswith(".sam"):
            # The INFO chunk records the build's time: keep every chunk's tag
            # and payload, that time zeroed (CRCs follow the payload).
            b = open(p, "rb").read()
            out, off = [b[:16]], 16
            while off + 16 <= len(b):
                tag, length = b[off:off + 4], struct.unpack("<Q", b[off + 8:off + 16])[0]
                payload = b[off + 16:off + 16 + length]
                out.append(tag + secs.sub(rb'\1: 0', payload))
                off += 16 + (length + 7) // 8 * 8 + 8
            open(p, "wb").write(b"".join(out))
        elif f == "report.json":
            open(p, "wb").write(secs.sub(rb'\1: 0', open(p, "rb").read()))
        elif f == "report.md":
            t = re.sub(r'(?m)^(\| [0-9]+ \| )[0-9.]+ \|', r'\1t |', open(p).read())
            t = re.sub(r'(surface samples, )[0-9.]+ s,', r'\1t s,', t)
            open(p, "w").write(t)
        elif f.endswith("_info.txt"):
            t = re.sub(r'(?m)^(\s*build_seconds\s+).*$', r'\1t', open(p).read())
            open(p, "w").write(t)
PY
  ) || { echo "check_identical.sh: a job failed with $bin; see $dir/stderr.log" >&2; tail -5 "$dir/stderr.log" >&2; exit 1; }
  rm -f "$dir/stderr.log"
}

jobs "$ref_bin" "$out/ref"
jobs "$new_bin" "$out/new"

same=0
differ=()
while IFS= read -r f; do
  if cmp -s "$out/ref/$f" "$out/new/$f"; then
    same=$((same + 1))
  else
    differ+=("$f")
  fi
done < <(cd "$out/ref" && find . -type f | sort)
missing=$(comm -13 <(cd "$out/ref" && find . -type f | sort) <(cd "$out/new" && find . -type f | sort) | wc -l)
echo "check_identical.sh: $same files identical, ${#differ[@]} differ, $missing only in the new tree (against $rev)"
for f in "${differ[@]}"; do echo "  differs: $f"; done
[ ${#differ[@]} -eq 0 ] && [ "$missing" -eq 0 ]
