# Sourced by the window tests, which stop here when Xvfb is missing.
command -v xvfb-run > /dev/null || { echo "FAIL: xvfb-run is missing (scripts/deps.sh installs xvfb)"; exit 1; }

# xvfb_run DIR PROGRAM ARGS... runs PROGRAM
# under Xvfb and returns PROGRAM's own exit status: xvfb-run's can be its
# own (5 when it cannot clean up its temporary folder, seen under ASan's
# slower exits). DIR keeps the status file.
xvfb_run() {
  local dir=$1
  shift
  rm -f "$dir/rc"
  xvfb-run -a -s "-screen 0 1024x768x24" sh -c '"$0" "$@"; echo $? > "'"$dir"'/rc"' "$@"
  [ -s "$dir/rc" ] || return 99
  return "$(cat "$dir/rc")"
}
