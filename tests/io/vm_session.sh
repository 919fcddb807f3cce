#!/usr/bin/env bash
# Session mode of the test guest (tools/vm/session, tools/vm/init "Session mode"), in the shared
# guest of the ctest run: each command finds the guest as a fresh boot would, whatever the one
# before it did (files written, a process left running in a session of its own, vcan1 deleted,
# the gpio-sim chip removed); a command's status and streams come back; one over its limit is
# killed (124) and the guest stays up for the next; --reread sees host files changed since; as
# root the guest runs at the raised share.
# Usage: vm_session.sh TOOLS_VM_DIR   (SWUM_VM_SESSION: the session's folder, guest up)
set -u
tools_vm=$(cd "$1" && pwd)
session_tool=$tools_vm/session
dir=${SWUM_VM_SESSION:?SWUM_VM_SESSION names the session folder}
fails=0
fail() { echo "FAIL $*"; fails=$((fails + 1)); }
ok() { echo "ok   $*"; }
exec_in() { "$session_tool" exec "$dir" "$@"; }

"$session_tool" alive "$dir" || { echo "FAIL no guest up in $dir (the fixture io.vm.session_start)"; exit 1; }
mark=/tmp/swum-session-mark.$$
chip_tool=$(printf %q "$tools_vm/gpio-sim-chip")
out=$(exec_in -- bash -c "touch $mark; setsid sleep 1000.$$ < /dev/null > /dev/null 2>&1 &
  ip link del vcan1; [ ! -d /sys/kernel/config/gpio-sim ] || sh $chip_tool remove; echo to-out; echo to-err >&2; exit 7" 2> "$mark.err")
rc=$?
[ "$rc" = 7 ] && [ "$out" = to-out ] && grep -qx to-err "$mark.err" && ok "status 7 and both streams back" ||
  fail "first command: status $rc, stdout '$out', stderr '$(cat "$mark.err")'"
rm -f "$mark.err"

# The next command: nothing of the first one's left, the devices as after a boot.
check=$(cat <<EOF
[ ! -e $mark ] || echo "the previous command's file $mark is still there"
! pgrep -f '[s]leep 1000.$$' > /dev/null || echo "the previous command's process still runs"
ip -br link show vcan1 2>/dev/null | grep -q UP || echo "vcan1 is not back and up"
ip -br link show vcan0 2>/dev/null | grep -q UP || echo "vcan0 is not up"
if [ -d /sys/kernel/config/gpio-sim ]; then
  [ -e /sys/kernel/config/gpio-sim/swum/live ] && [ "\$(cat /sys/kernel/config/gpio-sim/swum/live)" = 1 ] ||
    echo "the gpio-sim chip is not back"
fi
EOF
)
out=$(exec_in -- bash -c "$check" 2>&1)
rc=$?
[ "$rc" = 0 ] && [ -z "$out" ] && ok "the next command finds a fresh guest" || fail "fresh guest: status $rc: $out"

# The guest keeps what it read of the host root; --reread reads a changed host file anew.
probe=$(mktemp /tmp/swum-session-probe.XXXXXX)
echo before > "$probe"
out=$(exec_in -- cat "$probe" 2>&1)
echo after > "$probe"
out2=$(exec_in --reread -- cat "$probe" 2>&1)
rm -f "$probe"
[ "$out" = before ] && [ "$out2" = after ] && ok "--reread sees a host file changed during the session" ||
  fail "--reread: read '$out', then '$out2' after the change"

err=$(exec_in --timeout 2 -- sleep 60 2>&1 >/dev/null)
rc=$?
[ "$rc" = 124 ] && [[ "$err" == *"timed out after 2 s"* ]] && ok "over its limit: 124" ||
  fail "timeout: status $rc, stderr '$err'"
out=$(exec_in -- echo still-up 2>&1)
rc=$?
[ "$rc" = 0 ] && [ "$out" = still-up ] && ok "the guest stays up after a timeout" || fail "after the timeout: status $rc, '$out'"

# The raised share: DIR/nice records what tools/vm/session set (as root with CAP_SYS_NICE); the
# guest's threads and autogroup must then have it. Without the record they must be as they were.
pid=$(cat "$dir/qemu.pid")
want=$(cat "$dir/nice" 2>/dev/null || echo 0)
nice_now=$(ps -o ni= -p "$pid" | tr -d ' ')
[ "$nice_now" = "$want" ] && ok "QEMU's nice: $nice_now (recorded: $(cat "$dir/nice" 2>/dev/null || echo none))" ||
  fail "QEMU's nice is $nice_now, not $want"
if [ -s "$dir/nice" ] && [ -r "/proc/$pid/autogroup" ]; then
  group=$(cat "/proc/$pid/autogroup")
  [[ "$group" == *"nice $want" ]] && ok "the guest's autogroup: $group" || fail "the guest's autogroup is '$group', not at nice $want"
fi
if [ "$(id -u)" = 0 ] && [ ! -s "$dir/nice" ]; then
  echo "note root without the right to raise priorities (a container without CAP_SYS_NICE): the share is not raised"
fi
exit $((fails > 0))
