#!/bin/bash
# swum-emu over Modbus TCP with Debian's mbpoll as the independent client: 32-bit setpoints
# written with mbpoll's big-endian word order (-B), as config/modbus_registers.json documents;
# enable -> speed near the model's steady state; out-of-range -> "Illegal data value", state
# unchanged; SIGTERM -> exit 0 with statistics.
set -euo pipefail
: "${SWUM_EMU:?}" "${SWUM_EMU_REFERENCE:?}" "${SWUM_SOURCE_DIR:?}"
work=$(mktemp -d)
pid=
cleanup() { [[ -n $pid ]] && kill -KILL "$pid" 2>/dev/null; rm -rf "$work"; }
trap cleanup EXIT

mkfifo "$work/out"
"$SWUM_EMU" --config "$SWUM_SOURCE_DIR/config/li2019.toml" --modbus tcp://127.0.0.1:0 --speedup 4 \
  --watchdog-ms 0 >"$work/out" 2>"$work/err" &
pid=$!
exec 3<"$work/out"
read -r -t 30 ready <&3 || { echo "no ready line"; cat "$work/err"; exit 1; }
echo "$ready"
port=$(sed -n 's/.*modbus=tcp:\/\/127.0.0.1:\([0-9]*\).*/\1/p' <<<"$ready")
cat <&3 >"$work/rest" &   # keep draining stdout

mb() { mbpoll -m tcp -p "$port" -0 -1 -q "$@" 127.0.0.1; }                  # reads
mbw() { local t=$1 r=$2; shift 2; mbpoll -m tcp -p "$port" -0 -1 -q -t "$t" -B -r "$r" 127.0.0.1 "$@"; }  # writes
value() { sed -n 's/^\[[0-9]*\]:[[:space:]]*\(-\?[0-9]*\).*/\1/p' | head -1; }
read_i32() { mb -t 3:int -B -r "$1" -c 1 | value; }
read_u16() { mb -t 3 -r "$1" -c 1 | value; }

mbw 4:int 1 40000000 >/dev/null     # frequency 40000.000 Hz (mHz, high word first)
mbw 4 3 4000 >/dev/null                # 400.0 V
mbw 4 0 1 >/dev/null                   # enable
# Applied at the next tick boundary: a read right after the write may still show the tick before.
for _ in $(seq 200); do [[ $(read_u16 1) == 1 ]] && break; done
[[ $(read_u16 1) == 1 ]] || { echo "not enabled"; exit 1; }
start=$(read_i32 21)
writes=3
while (( $(read_i32 21) < start + 120 )); do mbw 4 0 0 >/dev/null; writes=$((writes + 1)); done   # keep-alive until +120 ms
speed=$(read_i32 8)
ref=$("$SWUM_EMU_REFERENCE" "$SWUM_SOURCE_DIR/config/li2019.toml" 400 40000)
echo "speed ${speed} um/s; reference ${ref}"
python3_bin=/usr/bin/python3
$python3_bin - "$speed" "$ref" <<'PY'
import json, sys
speed = int(sys.argv[1]) / 1000.0
ref = json.loads(sys.argv[2])["speed_mm_s"]
assert abs(speed - ref) <= 0.03 * abs(ref) + 2.0, (speed, ref)
PY

# Out of range: 700 V -> exception 03, nothing changes. First every accepted write applied
# (the last keep-alive takes effect at the next tick boundary).
for _ in $(seq 200); do [[ $(read_i32 6) == "$writes" ]] && break; done
applied=$(read_i32 6)
[[ $applied == "$writes" ]] || { echo "$writes writes accepted, $applied applied"; exit 1; }
if out=$(mbw 4 3 7000 2>&1); then echo "700 V accepted: $out"; exit 1; fi
grep -qi "illegal data value" <<<"$out" || { echo "unexpected: $out"; exit 1; }
[[ $(read_u16 3) == 2 ]] || { echo "last reject reason not 2 (amplitude out of range)"; exit 1; }
[[ $(mb -t 4 -r 3 -c 1 | value) == 4000 ]] || { echo "amplitude setpoint changed"; exit 1; }
[[ $(read_i32 6) == "$applied" ]] || { echo "a command was applied"; exit 1; }
[[ $(read_u16 1) == 1 ]] || { echo "state changed"; exit 1; }
# Half of a 32-bit register -> exception 02.
if out=$(mbw 4 2 5 2>&1); then echo "split write accepted"; exit 1; fi
grep -qi "illegal data address" <<<"$out" || { echo "unexpected: $out"; exit 1; }

kill -TERM "$pid"
wait "$pid"; rc=$?
pid=
exec 3<&-
wait
cat "$work/rest"
grep -q "loop statistics" "$work/rest"
grep -q "state disabled" "$work/rest"
echo "PASS mbpoll (exit $rc)"
