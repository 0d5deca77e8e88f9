#!/usr/bin/env bash
# sam_build: a build that sam_info accepts; each bad input gives exit status
# 1 or 2 with one error line and no output file; SIGINT leaves nothing
# behind; --threads does not change the data. Args: BIN SRC TMP
set -u
bin=$1 src=$2 tmp=$3
rm -rf "$tmp" && mkdir -p "$tmp"
fail() { echo "FAIL: $*"; exit 1; }
"$bin/sam_meshgen" ear -o "$tmp/ear.obj" --resolution 24 2>/dev/null || fail "meshgen"
"$bin/sam_build" "$tmp/ear.obj" -o "$tmp/ear.sam" --material skin --mm-per-unit 60 2> "$tmp/log.txt" \
  || fail "build: $(cat "$tmp/log.txt")"
grep -q "wrote .*ear.sam" "$tmp/log.txt" || fail "no summary line: $(cat "$tmp/log.txt")"
grep -q "100%" "$tmp/log.txt" || fail "no progress: $(cat "$tmp/log.txt")"
out=$("$bin/sam_info" "$tmp/ear.sam") || fail "sam_info rejects the build"
grep -q "SAM v2" <<<"$out" || fail "the default map is not a cut map (version 2): $out"
grep -q "samples per vertex: 16" <<<"$out" || fail "$out"
# --flat: the paper's map, version 1; --flat-scaled likewise; not both.
"$bin/sam_build" "$tmp/ear.obj" -o "$tmp/flat.sam" --material skin --mm-per-unit 60 --flat --quiet 2>/dev/null \
  || fail "--flat"
out=$("$bin/sam_info" "$tmp/flat.sam") || fail "sam_info rejects the flat build"
grep -q "SAM v1" <<<"$out" && grep -q "samples per vertex: 3" <<<"$out" || fail "--flat: $out"
"$bin/sam_build" "$tmp/ear.obj" -o "$tmp/scaled.sam" --material skin --mm-per-unit 60 --flat-scaled --quiet \
  2>/dev/null || fail "--flat-scaled"
grep -q '"map":"flat-scaled"' <<<"$("$bin/sam_info" "$tmp/scaled.sam")" || fail "--flat-scaled not recorded"
if "$bin/sam_build" "$tmp/ear.obj" -o "$tmp/x.sam" --material skin --mm-per-unit 60 --flat --flat-scaled \
  2> "$tmp/err.txt"; then fail "--flat --flat-scaled accepted"; fi
grep -q "exclude each other" "$tmp/err.txt" || fail "$(cat "$tmp/err.txt")"
grep -q '"sha256":"'"$(sha256sum "$tmp/ear.obj" | cut -c1-64)"'"' <<<"$out" || fail "INFO lacks the source hash: $out"

# --size-mm, --samples and --threads; the data chunks match across thread counts.
"$bin/sam_build" "$tmp/ear.obj" -o "$tmp/t1.sam" --material marble --size-mm 70 --samples 5 --threads 1 --quiet \
  2>/dev/null || fail "--threads 1"
"$bin/sam_build" "$tmp/ear.obj" -o "$tmp/t2.sam" --material marble --size-mm 70 --samples 5 --threads 2 --quiet \
  2>/dev/null || fail "--threads 2"
# Everything but the INFO chunk (which holds the build time) is identical:
# INFO is the first chunk, so compare from the second chunk on.
info_end() { python3 -c 'import struct,sys; d=open(sys.argv[1],"rb").read(); n=struct.unpack_from("<Q",d,24)[0]; print(16+16+((n+7)//8)*8+8)' "$1"; }
cmp <(tail -c +$(( $(info_end "$tmp/t1.sam") + 1 )) "$tmp/t1.sam") \
    <(tail -c +$(( $(info_end "$tmp/t2.sam") + 1 )) "$tmp/t2.sam") || fail "--threads changed the data"

expect_error() { # expected-status label args...
  local want=$1 label=$2; shift 2
  "$bin/sam_build" "$@" > "$tmp/out.txt" 2> "$tmp/err.txt"
  local rc=$?
  [ $rc -eq "$want" ] || fail "$label: exit status $rc, expected $want ($(cat "$tmp/err.txt"))"
  [ "$(wc -l < "$tmp/err.txt")" -eq 1 ] || fail "$label: expected one error line, got: $(cat "$tmp/err.txt")"
  ls "$tmp"/bad.sam* > /dev/null 2>&1 && fail "$label: left an output or temporary file"
  return 0
}
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\n' > "$tmp/nofaces.obj"
expect_error 1 "unknown material" "$tmp/ear.obj" -o "$tmp/bad.sam" --material unobtainium --mm-per-unit 1
expect_error 2 "zero scale" "$tmp/ear.obj" -o "$tmp/bad.sam" --material skin --mm-per-unit 0
expect_error 2 "negative scale" "$tmp/ear.obj" -o "$tmp/bad.sam" --material skin --mm-per-unit -3
expect_error 2 "NaN scale" "$tmp/ear.obj" -o "$tmp/bad.sam" --material skin --mm-per-unit nan
expect_error 2 "zero size" "$tmp/ear.obj" -o "$tmp/bad.sam" --material skin --size-mm 0
expect_error 2 "two scales" "$tmp/ear.obj" -o "$tmp/bad.sam" --material skin --size-mm 5 --mm-per-unit 1
expect_error 2 "no scale" "$tmp/ear.obj" -o "$tmp/bad.sam" --material skin
expect_error 2 "samples 0" "$tmp/ear.obj" -o "$tmp/bad.sam" --material skin --mm-per-unit 1 --samples 0
expect_error 2 "samples 65" "$tmp/ear.obj" -o "$tmp/bad.sam" --material skin --mm-per-unit 1 --samples 65
grep -q -- "--samples must be a whole number in 1..64" "$tmp/err.txt" || fail "samples 65: $(cat "$tmp/err.txt")"
expect_error 2 "cut budget under N" "$tmp/ear.obj" -o "$tmp/bad.sam" --material skin --mm-per-unit 1 --samples 16 \
  --cut-budget 8
grep -q "cut budget must be 0 (the larger of the samples per vertex and 32) or in 16..64" "$tmp/err.txt" \
  || fail "cut budget under N: $(cat "$tmp/err.txt")"
expect_error 1 "no triangles" "$tmp/nofaces.obj" -o "$tmp/bad.sam" --material skin --mm-per-unit 1
expect_error 1 "missing mesh" "$tmp/none.obj" -o "$tmp/bad.sam" --material skin --mm-per-unit 1
expect_error 1 "unwritable output" "$tmp/ear.obj" -o "$tmp/no/such/dir/bad.sam" --material skin --mm-per-unit 1
expect_error 1 "existing output" "$tmp/ear.obj" -o "$tmp/ear.sam" --material skin --mm-per-unit 1
mkdir -p "$tmp/dir.sam"
expect_error 1 "a folder as output" "$tmp/ear.obj" -o "$tmp/dir.sam" --material skin --mm-per-unit 1 --force
grep -q "is a folder" "$tmp/err.txt" || fail "a folder as output: $(cat "$tmp/err.txt")"
ls "$tmp"/dir.sam.tmp* > /dev/null 2>&1 && fail "a folder as output: a temporary file was left"
expect_error 1 "not a .sam name" "$tmp/ear.obj" -o "$tmp/bad.png" --material skin --mm-per-unit 1
grep -q "must end in .sam" "$tmp/err.txt" || fail "not a .sam name: $(cat "$tmp/err.txt")"
[ -e "$tmp/bad.png" ] && fail "not a .sam name: wrote $tmp/bad.png"
expect_error 1 "missing folder" "$tmp/ear.obj" -o "$tmp/nodir/bad.sam" --material skin --mm-per-unit 1
grep -q "the folder .*nodir does not exist" "$tmp/err.txt" || fail "missing folder: $(cat "$tmp/err.txt")"
# A folder whose permission bits say yes but that takes no new file (/proc refuses even root, which
# access() lets through) is refused before the build, not at its end.
if ! touch /proc/sam_probe 2> /dev/null; then
  expect_error 1 "a folder that takes no file" "$tmp/ear.obj" -o /proc/bad.sam --material skin --mm-per-unit 1
  grep -q "cannot write in /proc" "$tmp/err.txt" || fail "a folder that takes no file: $(cat "$tmp/err.txt")"
fi
expect_error 2 "unknown option" "$tmp/ear.obj" -o "$tmp/bad.sam" --material skin --mm-per-unit 1 --bogus
"$bin/sam_build" "$tmp/ear.obj" -o "$tmp/ear.sam" --material skin --mm-per-unit 60 --force --quiet 2>/dev/null \
  || fail "--force"

# Interrupting a longer build leaves neither the output nor a temporary file.
"$bin/sam_meshgen" knot -o "$tmp/knot.ply" --resolution 1400 2>/dev/null || fail "meshgen knot"
"$bin/sam_build" "$tmp/knot.ply" -o "$tmp/bad.sam" --material skin --size-mm 40 --threads 1 2> "$tmp/int.txt" &
pid=$!
sleep 1
kill -INT $pid
wait $pid
rc=$?
[ $rc -ne 0 ] || fail "interrupted build exited 0 (was the build already done? $(tail -1 "$tmp/int.txt"))"
grep -q "interrupted; no output written" "$tmp/int.txt" || fail "no interruption message: $(tail -2 "$tmp/int.txt")"
ls "$tmp"/bad.sam* > /dev/null 2>&1 && fail "interrupted build left files"
# A closed mesh wound inside out (its normals point in) is turned outside out with one warning, and every
# vertex gets samples; --keep-orientation keeps it (and then most vertices have no back side).
"$bin/sam_meshgen" sphere -o "$tmp/sphere.obj" --resolution 12 2>/dev/null || fail "meshgen sphere"
awk '/^f / { print $1, $2, $4, $3; next } { print }' "$tmp/sphere.obj" > "$tmp/inward.obj"
"$bin/sam_build" "$tmp/inward.obj" -o "$tmp/inward.sam" --material skin --size-mm 20 --quiet 2> "$tmp/inward.txt" \
  || fail "inward mesh: $(cat "$tmp/inward.txt")"
[ "$(grep -c "warning: .*inward.obj is closed and faces inward (negative volume): turned outside out" "$tmp/inward.txt")" -eq 1 ] \
  || fail "no orientation warning: $(cat "$tmp/inward.txt")"
grep -q "(0.0% have none)" "$tmp/inward.txt" || fail "the turned mesh has vertices without samples: $(cat "$tmp/inward.txt")"
"$bin/sam_build" "$tmp/inward.obj" -o "$tmp/kept.sam" --material skin --size-mm 20 --quiet --keep-orientation \
  2> "$tmp/kept.txt" || fail "--keep-orientation: $(cat "$tmp/kept.txt")"
grep -q "turned outside out" "$tmp/kept.txt" && fail "--keep-orientation still turned it"
grep -q "(0.0% have none)" "$tmp/kept.txt" && fail "--keep-orientation turned the mesh anyway"
grep -q "warning: .* have no back side .*inward.obj is closed and faces inward" "$tmp/kept.txt" \
  || fail "no warning on the dark map of the inward mesh: $(cat "$tmp/kept.txt")"
grep -q "have no back side" "$tmp/inward.txt" && fail "the turned mesh's map was called dark"
# A single sheet has no back side: the warning says so.
printf 'v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n' > "$tmp/sheet.obj"
"$bin/sam_build" "$tmp/sheet.obj" -o "$tmp/sheet.sam" --material skin --size-mm 20 --quiet 2> "$tmp/sheet.txt" \
  || fail "sheet: $(cat "$tmp/sheet.txt")"
grep -q "warning: 100% of the vertices (4 of 4) have no back side .*sheet.obj is open .*single sheet" "$tmp/sheet.txt" \
  || fail "no single-sheet warning: $(cat "$tmp/sheet.txt")"
"$bin/sam_build" --help | grep -q "usage: sam_build" || fail "--help"
echo "sam_build cli: ok"
