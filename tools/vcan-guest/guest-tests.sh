#!/bin/sh
# The vcan checks, run inside the qemu guest by /init (or natively by run.sh on a host that has
# vcan0 up). Needs on PATH: stickslip, test_socketcan, can-utils (cangen, candump, canplayer,
# cansend) and `timeout`. Every command runs under `timeout`. Exit status 0 when every check
# passes; each check prints "check: NAME: ok" or "check: NAME: FAILED".
set -u
iface="${STICKSLIP_VCAN_IFACE:-vcan0}"
out="${VCAN_OUT:-/tmp/vcan-out}"
mkdir -p "$out"
failures=0

check() {  # check NAME COMMAND... (sh has no locals: the check_ names are this function's own)
  check_name="$1"; shift
  check_start=$(cut -d' ' -f1 /proc/uptime)
  if "$@"; then
    echo "check: $check_name: ok ($check_start -> $(cut -d' ' -f1 /proc/uptime) s)"
  else
    echo "check: $check_name: FAILED (status $?)"
    failures=$((failures + 1))
  fi
}

# 1. The SocketCAN transport against the real kernel (CppUTest), incl. cansend -> our receive
#    and our send -> candump.
socketcan_group() {
  STICKSLIP_VCAN_IFACE="$iface" STICKSLIP_VCAN_DOWN_IFACE="${STICKSLIP_VCAN_DOWN_IFACE:-vcan9}" \
    timeout 300 test_socketcan -v -sg "$1"
}
check "CppUTest SocketCanWithoutInterface" socketcan_group SocketCanWithoutInterface
check "CppUTest SocketCanFrame" socketcan_group SocketCanFrame
check "CppUTest SocketCanVcan" socketcan_group SocketCanVcan

# 2. The project's bus commands on the real kernel. The reference is the offline result: replay
#    over the in-process loopback bus, which equals `simulate` on the quantised samples.
duration="${VCAN_DURATION_S:-10}"
model="--model stick-slip --ffk 45"
input_id=100  # SeatInput (docs/can)
samples=$(awk "BEGIN { printf \"%d\", $duration / 0.001 + 1.5 }")

# Prints the value of counter NAME from the one-line JSON in FILE.
counter() { grep -o "\"$1\":[0-9]*" "$2" | tail -n 1 | cut -d: -f2; }
# expect FILE NAME VALUE: counter NAME in FILE equals VALUE.
expect() {
  value=$(counter "$2" "$1")
  if [ "$value" != "$3" ]; then echo "  $1: $2 = ${value:-missing}, expected $3"; return 1; fi
}
# expect_at_least FILE NAME VALUE
expect_at_least() {
  value=$(counter "$2" "$1")
  if [ -z "$value" ] || [ "$value" -lt "$3" ]; then echo "  $1: $2 = ${value:-missing}, expected >= $3"; return 1; fi
}
# Sockets bound to $iface, as the kernel lists them (to start senders only once receivers listen).
receivers() { cat /proc/net/can/rcvlist_* 2>/dev/null | grep -c " $iface " || true; }
wait_for_receivers_above() {
  for _ in $(seq 1 200); do
    [ "$(receivers)" -gt "$1" ] && { sleep 0.2; return 0; }
    sleep 0.05
  done
  echo "  no new receiver on $iface after 10 s"; return 1
}
# No frame refused or missing (bus silence before the first frame is counted, and allowed).
expect_clean() {
  for name in lost duplicate out_of_order bad_crc wrong_length unknown_id can_fd error_frame \
              remote_frame alive_mismatch invalid_signal resync held_samples receive_drops malformed_reads; do
    expect "$1" "$name" 0 || return 1
  done
}
same_file() {
  if cmp "$1" "$2"; then return 0; fi
  echo "  $1 and $2 differ"; return 1
}
# Bit for bit, except t: the node alone on a bus has no time line and writes t = n dt.
same_columns_after_t() {
  cut -d, -f2- "$1" > "$1.nt" && cut -d, -f2- "$2" > "$2.nt" && same_file "$1.nt" "$2.nt"
}

offline_reference() {
  timeout 60 stickslip generate --kind lorry --rms 0.35 --duration "$duration" --dt 0.001 --seed 1 \
      --output "$out/in.csv" >/dev/null &&
    timeout 120 stickslip replay --input "$out/in.csv" --bus loopback --output "$out/loopback.csv" $model \
      > "$out/loopback.txt" &&
    timeout 120 stickslip simulate --input "$out/loopback.csv" --output "$out/simulate.csv" $model >/dev/null &&
    same_file "$out/simulate.csv" "$out/loopback.csv" &&
    [ "$(wc -l < "$out/loopback.csv")" -eq $((samples + 1)) ]
}
check "offline: replay over loopback == simulate on the quantised samples ($samples samples)" offline_reference

replay_over_vcan() {
  timeout 300 stickslip replay --input "$out/in.csv" --bus "$iface" --output "$out/vcan.csv" $model \
      > "$out/vcan.txt" || return 1
  tail -n 1 "$out/vcan.txt" > "$out/vcan.json"
  expect "$out/vcan.json" accepted "$samples" && expect_clean "$out/vcan.json" &&
    expect "$out/vcan.json" receive_drops 0 && same_file "$out/vcan.csv" "$out/loopback.csv"
}
check "stickslip replay --bus $iface == offline, bit for bit" replay_over_vcan

# The issue's full recording: 120 s of lorry data replayed over vcan0 by the project's replay
# equals the offline result (loopback replay == simulate on the quantised samples), bit for bit.
full_duration="${VCAN_FULL_DURATION_S:-120}"
full_samples=$(awk "BEGIN { printf \"%d\", $full_duration / 0.001 + 1.5 }")
full_recording_over_vcan() {
  timeout 120 stickslip generate --kind lorry --rms 0.35 --duration "$full_duration" --dt 0.001 --seed 1 \
      --output "$out/full.csv" >/dev/null &&
    timeout 300 stickslip replay --input "$out/full.csv" --bus loopback --output "$out/full-loopback.csv" $model \
      >/dev/null &&
    timeout 300 stickslip simulate --input "$out/full-loopback.csv" --output "$out/full-simulate.csv" $model \
      --repetitions 1 >/dev/null &&
    same_file "$out/full-simulate.csv" "$out/full-loopback.csv" || return 1
  timeout 600 stickslip replay --input "$out/full.csv" --bus "$iface" --output "$out/full-vcan.csv" $model \
      > "$out/full-vcan.txt" || return 1
  tail -n 1 "$out/full-vcan.txt" > "$out/full-vcan.json"
  expect "$out/full-vcan.json" accepted "$full_samples" && expect_clean "$out/full-vcan.json" &&
    same_file "$out/full-vcan.csv" "$out/full-loopback.csv"
}
check "$full_duration s recording: replay --bus $iface == loopback replay == simulate, bit for bit" full_recording_over_vcan

# The node alone (stickslip ecu) fed by can-utils' canplayer from a log that stickslip record
# wrote, while candump -l captures the input frames; then the capture is read back.
canplayer_to_ecu() {
  timeout 60 stickslip record --input "$out/in.csv" --output "$out/record.log" --interface "$iface" >/dev/null ||
    return 1
  rm -rf "$out/capture" && mkdir -p "$out/capture"
  before=$(receivers)
  timeout 300 stickslip ecu --bus "$iface" --frames "$samples" --output "$out/ecu.csv" $model \
      > "$out/ecu.txt" 2>&1 &
  ecu=$!
  wait_for_receivers_above "$before" || return 1
  before=$(receivers)
  (cd "$out/capture" && exec timeout 300 candump -l "$iface,$input_id:7FF") &
  dump=$!
  wait_for_receivers_above "$before" || return 1
  timeout 300 canplayer -I "$out/record.log" || { echo "  canplayer failed"; return 1; }
  wait "$ecu" || { echo "  ecu exited with $?"; cat "$out/ecu.txt"; return 1; }
  sleep 0.5
  kill -TERM "$dump" 2>/dev/null; wait "$dump"
  tail -n 1 "$out/ecu.txt" > "$out/ecu.json"
  expect "$out/ecu.json" accepted "$samples" && expect_clean "$out/ecu.json" &&
    same_columns_after_t "$out/ecu.csv" "$out/loopback.csv"
}
check "canplayer (log from stickslip record) -> stickslip ecu --bus $iface == offline" canplayer_to_ecu

capture_read_back() {
  capture=$(ls "$out"/capture/candump-*.log 2>/dev/null | head -n 1)
  [ -n "$capture" ] || { echo "  candump -l wrote no log"; return 1; }
  [ "$(wc -l < "$capture")" -eq "$samples" ] || { echo "  capture has $(wc -l < "$capture") lines"; return 1; }
  timeout 120 stickslip replay --input "$capture" --dt 0.001 --bus loopback --output "$out/capture.csv" $model \
      > "$out/capture.txt" || return 1
  tail -n 1 "$out/capture.txt" > "$out/capture.json"
  expect "$out/capture.json" accepted "$samples" && expect_clean "$out/capture.json" && same_file "$out/capture.csv" "$out/loopback.csv"
}
check "candump -l capture read back by stickslip replay == offline" capture_read_back

# 3. Faults on the wire: hand-made frames (cansend, and a canplayer log with a duplicate, an
#    out-of-order and two lost frames), each counted by the node exactly.
hand_made_faults() {
  # Samples 0-4, 4 again, 2, then 7-9: 1 duplicate, 1 out of order, 2 lost, 8 accepted.
  { sed -n 1,5p "$out/record.log"; sed -n 5p "$out/record.log"; sed -n 3p "$out/record.log"
    sed -n 8,10p "$out/record.log"; } > "$out/faults.log"
  before=$(receivers)
  timeout 120 stickslip ecu --bus "$iface" $model > "$out/faults.txt" 2>&1 &
  ecu=$!
  wait_for_receivers_above "$before" || return 1
  timeout 60 canplayer -I "$out/faults.log" || return 1
  for frame in 100#00000000E2020080 100#0011 100##000000000E2020080 20000004#0004000000000000 \
               100#R 555#11; do
    timeout 10 cansend "$iface" "$frame" || { echo "  cansend $frame failed"; return 1; }
  done
  sleep 0.5
  kill -0 "$ecu" || { echo "  the node died"; return 1; }
  kill -TERM "$ecu"; wait "$ecu" || { echo "  ecu exited with $?"; return 1; }
  tail -n 1 "$out/faults.txt" > "$out/faults.json"
  cat "$out/faults.json"
  expect "$out/faults.json" accepted 8 && expect "$out/faults.json" duplicate 1 &&
    expect "$out/faults.json" out_of_order 1 && expect "$out/faults.json" lost 2 &&
    expect "$out/faults.json" bad_crc 1 && expect "$out/faults.json" wrong_length 1 &&
    expect "$out/faults.json" can_fd 1 && expect "$out/faults.json" error_frame 1 &&
    expect "$out/faults.json" remote_frame 1 && expect "$out/faults.json" unknown_id 1
}
check "hand-made faults (cansend, canplayer) counted exactly by stickslip ecu" hand_made_faults

# 4. A burst of random frames from cangen (random ids, and random data on the input id) for
#    ${VCAN_BURST_S:-10} s: the node keeps running and counts them.
cangen_burst() {
  before=$(receivers)
  timeout 120 stickslip ecu --bus "$iface" $model > "$out/burst.txt" 2>&1 &
  ecu=$!
  wait_for_receivers_above "$before" || return 1
  burst="${VCAN_BURST_S:-10}"
  timeout "$burst" cangen "$iface" -g 1 -m &
  random_ids=$!
  timeout "$burst" cangen "$iface" -g 2 -I "$input_id" -L 8 -D r &
  random_data=$!
  wait "$random_ids"; wait "$random_data"
  sleep 0.5
  kill -0 "$ecu" || { echo "  the node died during the burst"; return 1; }
  kill -TERM "$ecu"; wait "$ecu" || { echo "  ecu exited with $?"; return 1; }
  tail -n 1 "$out/burst.txt" > "$out/burst.json"
  cat "$out/burst.json"
  expect_at_least "$out/burst.json" frames 100 && expect_at_least "$out/burst.json" unknown_id 1 &&
    expect_at_least "$out/burst.json" bad_crc 10 && expect_at_least "$out/burst.json" can_fd 1 &&
    expect_at_least "$out/burst.json" remote_frame 1
}
check "cangen burst: the node keeps running and counts the frames" cangen_burst

echo "VCAN-GUEST: $failures failed check(s)"
[ "$failures" -eq 0 ]
