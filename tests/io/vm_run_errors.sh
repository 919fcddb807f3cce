#!/usr/bin/env bash
# Error paths of tools/vm/run: missing prepared image (125), bad usage (125), a command exiting 7
# inside (7, output back on the right streams), a hanging command (124), a crashed guest (122).
# Usage: vm_run_errors.sh TOOLS_VM_DIR   (SWUM_VM_DIR: the prepared cache)
set -u
run=$1/run
fails=0
check() {  # check NAME EXPECTED_STATUS ACTUAL_STATUS [text that stderr must contain] [stderr]
  if [ "$3" != "$2" ]; then echo "FAIL $1: status $3, expected $2"; fails=$((fails + 1)); return; fi
  if [ -n "${4:-}" ] && [[ "${5:-}" != *"$4"* ]]; then echo "FAIL $1: stderr lacks '$4': ${5:-}"; fails=$((fails + 1)); return; fi
  echo "ok   $1 (status $3)"
}
err=$("$run" --dir /nonexistent/vm -- true 2>&1 >/dev/null); check missing-image 125 $? "no prepared guest image" "$err"
err=$("$run" 2>&1 >/dev/null); check no-command 125 $? "no command given" "$err"
err=$("$run" --timeout x -- true 2>&1 >/dev/null); check bad-timeout 125 $? "not a positive whole number" "$err"
out=$("$run" -- sh -c 'echo to-out; echo to-err >&2; exit 7' 2>/tmp/vm_run_errors.$$); rc=$?
check exit-7 7 $rc "to-err" "$(cat /tmp/vm_run_errors.$$)"; rm -f /tmp/vm_run_errors.$$
[ "$out" = to-out ] || { echo "FAIL exit-7: stdout '$out'"; fails=$((fails + 1)); }
# The limit covers the boot too (--timeout is the whole run): 3 s ends it during the boot or in
# the sleep, the same kill either way, without waiting out a longer limit.
err=$("$run" --timeout 3 -- sleep infinity 2>&1 >/dev/null); check timeout 124 $? "timed out after 3 s" "$err"
err=$("$run" -- sh -c 'echo c > /proc/sysrq-trigger' 2>&1 >/dev/null); check guest-crash 122 $? "no exit status came back" "$err"
exit $((fails > 0))
