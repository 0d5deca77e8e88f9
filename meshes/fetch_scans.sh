#!/usr/bin/env bash
# Copies real scanned and modelled meshes from the Debian package
# libcgal-demo (its CGAL data archive) into meshes/scans/, which git
# ignores, and derives denser ones from them with loop_subdivide.py.
# Installs the package with apt-get when it is missing. Safe to run again:
# files whose contents are already there are left alone, and a derived mesh
# is remade only when its source changed, it is missing, or
# loop_subdivide.py is newer than it.
#
#   meshes/fetch_scans.sh [DEST_DIR]      (default: the scans/ folder beside this script)
set -euo pipefail

PACKAGE=libcgal-demo
# stable name : path inside the package's data archive
MESHES=(
  "bunny.off:data/meshes/bunny00.off"
  "armadillo.off:data/meshes/armadillo.off"
  "dragon.off:data/meshes/ChineseDragon-10kv.off"
  "elephant.off:data/meshes/elephant.off"
  "head.off:data/meshes/mannequin-devil.off"
  "man.off:data/meshes/man.off"
  "hand.off:data/meshes/hand.off"
  "camel.off:data/meshes/camel.off"
  "mushroom.off:data/meshes/mushroom.off"
  "lion_head.off:data/meshes/lion-head.off"
  "homer.off:data/meshes/homer.off"
  "cow.off:data/meshes/cow.off"
  "bull.off:data/meshes/bull.off"
  "dino.off:data/meshes/dino.off"
  "femur.off:data/meshes/femur.off"
  "bear.off:data/meshes/bear.off"
  "diplodocus.off:data/meshes/diplodocus.off"
  "elk.off:data/meshes/elk.off"
  "cactus.off:data/meshes/cactus.off"
)
# derived name : stable name above : Loop subdivision steps. The archive's
# densest statue-like scan, man.off (a standing figure, 17,495 vertices,
# closed), subdivided twice has 279,890 vertices, the order of the SAM
# paper's Happy Buddha (549k); no scan in the archive comes near it.
DERIVED=(
  "man_loop2.off:man.off:2"
)

die() {
  echo "fetch_scans.sh: $*" >&2
  exit 1
}

case "${1:-}" in
  -h|--help)
    sed -n '2,10p' "$0" | sed 's/^# \{0,1\}//'
    exit 0
    ;;
esac
[ $# -le 1 ] || die "too many arguments (usage: fetch_scans.sh [DEST_DIR])"
dest=${1:-"$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/scans"}

installed() {
  [ "$(dpkg-query -W -f='${Status}' "$PACKAGE" 2>/dev/null || true)" = "install ok installed" ]
}

if ! installed; then
  command -v apt-get >/dev/null || die "$PACKAGE is not installed and apt-get is not available"
  sudo=()
  if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null || die "$PACKAGE is not installed; run as root or install sudo"
    sudo=(sudo)
  fi
  echo "fetch_scans.sh: installing $PACKAGE" >&2
  export DEBIAN_FRONTEND=noninteractive
  # A fresh machine may have no package lists yet: update once and retry.
  if ! "${sudo[@]}" apt-get install -y --no-install-recommends "$PACKAGE" >&2; then
    "${sudo[@]}" apt-get update >&2 || die "apt-get update failed"
    "${sudo[@]}" apt-get install -y --no-install-recommends "$PACKAGE" >&2 \
      || die "apt-get install $PACKAGE failed"
  fi
  installed || die "$PACKAGE is still not installed after apt-get"
fi
version=$(dpkg-query -W -f='${Version}' "$PACKAGE")

archive=$(dpkg -L "$PACKAGE" | grep '/data\.tar\.gz$' | head -n 1 || true)
[ -n "$archive" ] && [ -f "$archive" ] \
  || die "$PACKAGE $version ships no data.tar.gz (dpkg -L $PACKAGE | grep tar)"

mkdir -p "$dest" || die "cannot create $dest"
work=$(mktemp -d "$dest/.fetch.XXXXXX") || die "cannot create a temporary folder in $dest"
trap 'rm -rf "$work"' EXIT

members=()
for entry in "${MESHES[@]}"; do
  members+=("${entry#*:}")
done
listing=$(tar -tzf "$archive") || die "cannot list $archive"
for m in "${members[@]}"; do
  grep -qxF "$m" <<<"$listing" || die "$archive ($PACKAGE $version) has no $m"
done
tar -xzf "$archive" -C "$work" "${members[@]}" || die "cannot extract from $archive"

# Prints "VERTICES FACES" from an OFF header (comments and blank lines skipped).
off_counts() {
  awk '
    { sub(/#.*/, "") }
    { for (i = 1; i <= NF; ++i) tok[n++] = $i }
    n >= 4 { exit }
    END {
      if (n < 4 || tok[0] !~ /^[A-Z]*OFF$/ || tok[1] !~ /^[0-9]+$/ || tok[2] !~ /^[0-9]+$/) exit 1
      print tok[1], tok[2]
    }' "$1"
}

declare -A written=()
for entry in "${MESHES[@]}"; do
  name=${entry%%:*}
  src=${entry#*:}
  file="$work/$src"
  counts=$(off_counts "$file") || die "$src in $archive is not an OFF mesh"
  read -r vertices faces <<<"$counts"
  [ "$vertices" -gt 0 ] && [ "$faces" -gt 0 ] || die "$src in $archive is empty"
  if [ -f "$dest/$name" ] && cmp -s "$file" "$dest/$name"; then
    state=unchanged
  else
    mv -f "$file" "$dest/$name"
    state=written
    written[$name]=1
  fi
  printf '%s/%s: %s vertices, %s faces (%s %s: %s) %s\n' \
    "$dest" "$name" "$vertices" "$faces" "$PACKAGE" "$version" "$src" "$state"
done

subdivide="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/loop_subdivide.py"
for entry in "${DERIVED[@]}"; do
  IFS=: read -r name src steps <<<"$entry"
  # The source's mtime comes from the archive, so a changed source is known
  # by having been written above, not by comparing times.
  if [ -f "$dest/$name" ] && [ -z "${written[$src]:-}" ] && [ ! "$subdivide" -nt "$dest/$name" ]; then
    state=unchanged
  else
    python3 "$subdivide" "$steps" "$dest/$src" "$work/$name" || die "cannot subdivide $src"
    mv -f "$work/$name" "$dest/$name"
    state=written
  fi
  read -r vertices faces <<<"$(off_counts "$dest/$name")"
  printf '%s/%s: %s vertices, %s faces (%s, %s Loop subdivision steps) %s\n' \
    "$dest" "$name" "$vertices" "$faces" "$src" "$steps" "$state"
done
