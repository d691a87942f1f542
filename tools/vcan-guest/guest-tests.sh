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
  # VCAN_ONLY=TEXT: only the checks whose name contains TEXT (for work on one check).
  case "$check_name" in *"${VCAN_ONLY:-}"*) ;; *) echo "check: $check_name: skipped (VCAN_ONLY)"; return 0 ;; esac
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
  for _ in $(seq 1 600); do
    [ "$(receivers)" -gt "$1" ] && { sleep 0.2; return 0; }
    sleep 0.05
  done
  echo "  no new receiver on $iface after 30 s"; return 1
}
# No frame refused or missing (bus silence before the first frame is counted, and allowed).
expect_clean() {
  for name in lost duplicate out_of_order bad_crc wrong_length foreign_frames can_fd error_frame \
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

# The full recording: 120 s of lorry data replayed over vcan0 by the project's replay
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

# The closed loop over the bus: stickslip plant and stickslip controller as two processes on
# $iface. Lock-step (--pace max), the trace equals closed-loop --can-resolution in process byte
# for byte, and so do the figures; then one real-time paced run prints its pacing report.
loop_duration="${VCAN_LOOP_DURATION_S:-3}"
loop_samples=$(awk "BEGIN { printf \"%d\", $loop_duration / 0.001 + 1.5 }")
loop_seat="--model stick-slip --ffk 40 --ffs 55"
loop_sensors="--a-x-noise 0.02 --x-r-noise 1e-4"
loop_law="--controller skyhook-semi --gain 1500 --actuator-lag 0.005"
start_controller() {  # start_controller NAME: the controller in the background, listening
  before=$(receivers)
  timeout 300 stickslip controller --bus "$iface" $loop_seat $loop_sensors $loop_law --idle-exit 1 \
      > "$out/$1-controller.txt" 2> "$out/$1-controller.err" &
  controller=$!
  wait_for_receivers_above "$before"
}
closed_loop_lock_step() {
  timeout 60 stickslip generate --kind lorry --rms 0.6 --duration "$loop_duration" --dt 0.001 --seed 3 \
      --output "$out/loop-in.csv" >/dev/null &&
    timeout 120 stickslip closed-loop --input "$out/loop-in.csv" --output "$out/loop-in-process.csv" \
      --can-resolution $loop_seat $loop_sensors $loop_law --seed 7 > "$out/loop-in-process.txt" || return 1
  start_controller loop || return 1
  timeout 300 stickslip plant --bus "$iface" --pace max --input "$out/loop-in.csv" \
      --output "$out/loop-vcan.csv" $loop_seat $loop_sensors --seed 7 > "$out/loop-plant.txt" ||
    { echo "  plant exited with $?"; kill "$controller"; return 1; }
  wait "$controller" || { echo "  controller exited with $?"; cat "$out/loop-controller.err"; return 1; }
  tail -n 1 "$out/loop-plant.txt" > "$out/loop-plant.json"
  tail -n 1 "$out/loop-controller.txt" > "$out/loop-controller.json"
  grep -o '"controlled":{[^}]*}' "$out/loop-in-process.txt" > "$out/loop-figures-in-process.txt"
  grep -o '"controlled":{[^}]*}' "$out/loop-plant.json" > "$out/loop-figures-vcan.txt"
  echo "  $(cat "$out/loop-figures-vcan.txt")"
  expect "$out/loop-plant.json" commands_applied $((loop_samples - 1)) &&
    expect "$out/loop-plant.json" commands_missing 0 && expect "$out/loop-plant.json" commands_late 0 &&
    expect "$out/loop-controller.json" answered "$loop_samples" &&
    expect "$out/loop-controller.json" sample_gaps 0 &&
    same_file "$out/loop-vcan.csv" "$out/loop-in-process.csv" &&
    same_file "$out/loop-figures-vcan.txt" "$out/loop-figures-in-process.txt"
}
check "closed loop: stickslip plant + controller on $iface (--pace max) == closed-loop --can-resolution, byte for byte" closed_loop_lock_step
closed_loop_realtime() {
  start_controller loop-rt || return 1
  timeout 300 stickslip plant --bus "$iface" --pace realtime --input "$out/loop-in.csv" \
      --output "$out/loop-rt.csv" $loop_seat $loop_sensors --seed 7 > "$out/loop-rt.txt" 2> "$out/loop-rt.err" ||
    { echo "  plant exited with $?"; cat "$out/loop-rt.err"; kill "$controller"; return 1; }
  wait "$controller" || { echo "  controller exited with $?"; return 1; }
  tail -n 1 "$out/loop-rt.txt" > "$out/loop-rt.json"
  grep "^plant: paced" "$out/loop-rt.err" | sed 's/^/  /'
  applied=$(counter commands_applied "$out/loop-rt.json") missing=$(counter commands_missing "$out/loop-rt.json")
  echo "  answers applied $applied, missing $missing, late $(counter commands_late "$out/loop-rt.json")," \
       "held $(counter held_frames "$out/loop-rt.json"), failsafe $(counter failsafe_frames "$out/loop-rt.json")"
  grep -q "^plant: paced $((loop_samples - 1)) ticks" "$out/loop-rt.err" &&
    expect "$out/loop-rt.json" ticks $((loop_samples - 1)) &&
    [ $((applied + missing)) -eq $((loop_samples - 1)) ]
}
check "closed loop: stickslip plant --pace realtime on $iface reports its pacing (median/99.9 %/worst lateness, misses)" closed_loop_realtime

# The node on a silent bus: it says what it waits for, stops at --timeout by itself (not by the
# outer `timeout`) with status 0, and prints its statistics with no sample taken.
ecu_timeout_on_a_silent_bus() {
  started=$(cut -d' ' -f1 /proc/uptime)
  timeout 60 stickslip ecu --bus "$iface" --timeout 2 $model > "$out/timeout.txt" 2> "$out/timeout.err" ||
    { echo "  ecu exited with $?"; cat "$out/timeout.err"; return 1; }
  took=$(awk "BEGIN { print $(cut -d' ' -f1 /proc/uptime) - $started }")
  grep -q "^ecu: waiting for SeatInput frames on $iface until 2 s, SIGINT or SIGTERM" "$out/timeout.err" ||
    { echo "  no line on what it waits for:"; cat "$out/timeout.err"; return 1; }
  awk "BEGIN { exit !($took >= 2 && $took < 30) }" || { echo "  stopped after $took s, not at 2 s"; return 1; }
  tail -n 1 "$out/timeout.txt" > "$out/timeout.json"
  expect "$out/timeout.json" samples 0 && expect "$out/timeout.json" frames_received 0 &&
    expect_clean "$out/timeout.json"
}
check "stickslip ecu --timeout 2 on a silent $iface says what it waits for and stops by itself" ecu_timeout_on_a_silent_bus

capture_read_back() {
  capture=$(ls "$out"/capture/candump-*.log 2>/dev/null | head -n 1)
  [ -n "$capture" ] || { echo "  candump -l wrote no log"; return 1; }
  [ "$(wc -l < "$capture")" -eq "$samples" ] || { echo "  capture has $(wc -l < "$capture") lines"; return 1; }
  timeout 120 stickslip replay --input "$capture" --dt 0.001 --retime --bus loopback --output "$out/capture.csv" $model \
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
    expect "$out/faults.json" remote_frame 1 && expect "$out/faults.json" foreign_frames 1
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
  expect_at_least "$out/burst.json" frames 100 && expect_at_least "$out/burst.json" foreign_frames 1 &&
    expect_at_least "$out/burst.json" bad_crc 10 && expect_at_least "$out/burst.json" can_fd 1 &&
    expect_at_least "$out/burst.json" remote_frame 1
}
check "cangen burst: the node keeps running and counts the frames" cangen_burst

# 5. The node under load and faults (ecu-load-faults). A 65 s recording (65001 samples, so the
#    16-bit counter does not wrap) is played at ${VCAN_LOAD_SPEED:-3}x real time, 3 kHz, by
#    stickslip play (it goes on when the bus refuses a frame; canplayer would stop), while cangen
#    floods the bus with id 123 at 1 kHz and candump -D captures ids 100 and 123 throughout.
#    Half a second in, node1 is killed (SIGKILL) and node2 started; 0.3 s after node2 listens it
#    is stopped (SIGTERM) and node3 started; 0.3 s after node3 listens vcan0 is set down for
#    0.3 s and up again. Then, from the sender's counts, the capture and the nodes' counters:
#    - the sender attempted every frame; the ones it could not send were refused because the
#      interface was down; the capture holds the rest in order, but for the few the kernel had
#      taken and dropped as the interface went down (in flight);
#    - each node's counters add up: every frame read has one verdict, its span first..last is
#      accepted + invalid_signal + lost + skipped, nothing duplicated, out of order, corrupted or
#      dropped by its socket;
#    - each restarted node reports where it joined the stream (first_sample: the samples before
#      it are the gap across the restart); every frame on the bus inside a node's span was used
#      by it; every frame missing from the bus lies in node3's span and is its lost + skipped
#      (the gap the bus down left, = refused + in flight); the frames on the bus add up to
#      before node2 + used by node2 + between node2 and node3 + used by node3;
#    - the flood is counted as foreign_frames (the node takes every id, no receive filter), at
#      least once and at most as many as were on the bus;
#    - each node's rows used exactly the recording's sample for their sample number (held rows
#      repeat the previous one), and its outputs equal, bit for bit, the offline result for that
#      sequence of samples: nothing came from a corrupted, stale or misplaced frame.
#    node1's counters die with it (SIGKILL); node2's and node3's are checked.
load_duration="${VCAN_LOAD_DURATION_S:-65}"  # recording length, s (sample number < 2^16)
load_speed="${VCAN_LOAD_SPEED:-3}"
# Priorities on the guest's one (emulated, slow) CPU: the node and the sender (cheap: a send
# per frame, woken once a millisecond) at niceness -10, as an ECU's control task and a sensor
# would be; the flood at 0; candump at 10 (its 64 MiB buffer holds the stream, it catches up
# after); this shell, which times the faults, and `ip` at -15 while the stream runs.
# `sh -c "$reniced" N COMMAND...` runs COMMAND at niceness N (as is where not root).
node_nice=-10
reniced='renice "$0" -p $$ >/dev/null 2>&1; exec "$@"'

flood_id=123
json_value() { grep -o "\"$1\":[-0-9.a-z]*" "$2" | tail -n 1 | cut -d: -f2; }
# Captured SeatInput sample counters (bytes 2-3 of the payload, little endian), one a line.
# Hex bytes are looked up in a table of the 256: decoding a capture digit by digit takes about
# half a minute in the guest.
captured_counters() {
  awk -v id="$input_id" -F '[ #]' '
    BEGIN { for (i = 0; i < 256; i++) byte[sprintf("%02X", i)] = i }
    $3 == id && length($4) == 16 { print byte[toupper(substr($4, 5, 2))] + 256 * byte[toupper(substr($4, 7, 2))] }' "$1"
}
# count_between FILE LO HI [LO HI]...: for each range, the lines of FILE (numbers) with
# LO <= n <= HI, one count a line; one pass over FILE.
count_between() {
  count_file=$1; shift
  awk -v ranges="$*" 'BEGIN { n = split(ranges, r, " ") }
    { for (i = 1; i < n; i += 2) if ($1 >= r[i] + 0 && $1 <= r[i + 1] + 0) c[i]++ }
    END { for (i = 1; i < n; i += 2) print c[i] + 0 }' "$count_file"
}
# start_node NAME: a node on $iface writing $out/NAME.{txt,csv,idx}; sets node (the job) and
# node_pid (stickslip itself: a signal to `timeout` would not reach it as such).
start_node() {
  before=$(receivers)
  rm -f "$out/$1.pid"
  timeout 300 sh -c 'echo $$ > "$1"; renice "$2" -p $$ >/dev/null 2>&1; shift 2; exec "$@"' \
      sh "$out/$1.pid" "$node_nice" stickslip ecu --bus "$iface" --receive-buffer 33554432 --output "$out/$1.csv" --sample-index "$out/$1.idx" $model \
      > "$out/$1.txt" 2>&1 &
  node=$!
  wait_for_receivers_above "$before" && node_pid=$(cat "$out/$1.pid")
}
# node_accounts NAME: the node's own counters add up; prints why not.
node_accounts() {
  j="$out/$1.json"
  for name in duplicate out_of_order bad_crc wrong_length can_fd error_frame remote_frame alive_mismatch; do
    expect "$j" "$name" 0 || return 1
  done
  expect "$j" receive_drops 0 && expect "$j" malformed_reads 0 || return 1
  # Every frame read has one verdict.
  verdicts=0
  for name in accepted ignored_output duplicate out_of_order bad_crc wrong_length foreign_frames can_fd \
              error_frame remote_frame alive_mismatch invalid_signal; do
    verdicts=$((verdicts + $(counter "$name" "$j")))
  done
  [ "$verdicts" -eq "$(counter frames_received "$j")" ] && [ "$verdicts" -eq "$(counter frames "$j")" ] ||
    { echo "  $1: $verdicts verdicts for $(counter frames_received "$j") frames read"; return 1; }
  # The span first..last is covered by used, held (lost) and skipped samples.
  first=$(json_value first_sample "$j"); last=$(json_value last_sample "$j")
  span=$(( $(counter accepted "$j") + $(counter invalid_signal "$j") + $(counter lost "$j") + $(counter skipped "$j") ))
  [ "$span" -eq $((last - first + 1)) ] ||
    { echo "  $1: accepted + invalid_signal + lost + skipped = $span over samples $first..$last"; return 1; }
  [ "$(wc -l < "$out/$1.idx")" -eq $(( $(counter accepted "$j") + $(counter held_samples "$j") + 1 )) ] ||
    { echo "  $1: $(wc -l < "$out/$1.idx") index lines"; return 1; }
}
# node_used_the_recording NAME: each row's a_u is the recording's sample for its sample number
# (held rows: the previous row's), and the outputs equal simulate over those samples, bit for bit.
node_used_the_recording() {
  # The input the node should have used, from the offline reference (row n + 2 = sample n).
  awk -F, 'NR == FNR { if (FNR > 1) ref[FNR - 2] = $2; next }
           FNR == 1 { print "t,a_u"; next }
           { a = ($3 == 1) ? prev : ref[$2]; prev = a; printf "%.17g,%s\n", ($1 + 0) * 0.001, a }' \
      "$out/load-ref.csv" "$out/$1.idx" > "$out/$1-expected-in.csv"
  # The node's a_u column is exactly that input.
  cut -d, -f2 "$out/$1.csv" > "$out/$1.au" && cut -d, -f2 "$out/$1-expected-in.csv" > "$out/$1-expected.au" &&
    same_file "$out/$1.au" "$out/$1-expected.au" || return 1
  # Offline: that input as frames (record) over the loopback bus, dt exactly as the node's.
  timeout 60 stickslip record --input "$out/$1-expected-in.csv" --output "$out/$1-expected.log" >/dev/null &&
    timeout 120 stickslip replay --input "$out/$1-expected.log" --dt 0.001 --bus loopback \
      --output "$out/$1-expected.csv" $model >/dev/null &&
    same_columns_after_t "$out/$1.csv" "$out/$1-expected.csv"
}
ecu_load_faults() {
  timeout 60 stickslip generate --kind lorry --rms 0.35 --duration "$load_duration" --dt 0.001 --seed 2 \
      --output "$out/load.csv" >/dev/null &&
    timeout 120 stickslip replay --input "$out/load.csv" --bus loopback --output "$out/load-ref.csv" $model \
      >/dev/null || return 1
  total=$(( $(wc -l < "$out/load.csv") - 1 ))
  [ "$total" -le 65536 ] || { echo "  $total samples: the counters would wrap (VCAN_LOAD_DURATION_S <= 65)"; return 1; }
  stream_s=$(awk "BEGIN { print $load_duration / $load_speed }")
  rm -rf "$out/load-capture" "$out/flood.stop" && mkdir -p "$out/load-capture"
  before=$(receivers)
  # -D: candump goes on when the interface goes down; -r: a receive buffer that holds the whole
  # stream, so that the capture is complete however slowly candump runs.
  (cd "$out/load-capture" &&
     exec sh -c "$reniced" 10 timeout 300 candump -D -r 67108864 -l "$iface,$input_id:7FF,$flood_id:7FF") &
  dump=$!
  wait_for_receivers_above "$before" || return 1
  start_node node1 || return 1
  node1=$node; node1_pid=$node_pid
  # The flood: cangen stops when a write fails (the bus down), so it is started again.
  flood_s=$(awk "BEGIN { printf \"%d\", $stream_s + 30 }")
  ( while [ ! -e "$out/flood.stop" ]; do
      timeout "$flood_s" cangen "$iface" -I "$flood_id" -L 8 -D r -g 1 2>/dev/null & echo $! > "$out/flood.pid"; wait
      sleep 0.05
    done ) &
  flood=$!
  { sh -c "$reniced" "$node_nice" timeout 300 stickslip play --input "$out/load.csv" --bus "$iface" --speed "$load_speed" > "$out/play.txt"
    status=$?; touch "$out/play.done"; exit $status; } &
  player=$!
  # The events follow each other in time, each while the stream still runs (a node's start
  # takes a second or more on a busy guest); the times (guest uptime) are printed.
  event() { echo "  $(cut -d' ' -f1 /proc/uptime) s: $1"; }
  running() { [ -e "$out/play.done" ] && { echo "  the stream ended too early (guest too slow?)"; return 1; }; return 0; }
  rm -f "$out/play.done"
  renice -15 -p $$ >/dev/null 2>&1
  # The kill must hit a node while the stream runs: wait until the capture shows its first frames
  # (a slow guest, or an ASan build, may take seconds to start the player).
  streamed() { grep -q " $input_id#" "$out"/load-capture/candump-*.log 2>/dev/null; }
  for _ in $(seq 1 1500); do
    streamed && break
    [ -e "$out/play.done" ] && break
    sleep 0.02
  done
  streamed || { echo "  no frame of the stream on the bus within 30 s"; return 1; }
  event "stream started ($total frames at ${load_speed}x: ${stream_s} s) and on the bus"
  sleep 0.5
  running || return 1
  kill -KILL "$node1_pid"; wait "$node1" 2>/dev/null
  event "node1 killed (SIGKILL)"
  start_node node2 || return 1
  node2=$node
  event "node2 listening"
  sleep 0.3
  running || return 1
  kill -TERM "$node_pid"; wait "$node2" || { echo "  node2 exited with $?"; cat "$out/node2.txt"; return 1; }
  event "node2 stopped (SIGTERM)"
  start_node node3 || return 1
  node3=$node; node3_pid=$node_pid
  event "node3 listening"
  sleep 0.3
  running || return 1
  set_link() { timeout 10 /usr/local/bin/ip link set "$iface" "$1" 2>/dev/null || timeout 10 ip link set "$iface" "$1"; }
  set_link down && event "$iface down" && sleep 0.3 && set_link up && event "$iface up" || return 1
  renice 0 -p $$ >/dev/null 2>&1
  wait "$player" || { echo "  stickslip play failed"; return 1; }
  event "stream ended"
  touch "$out/flood.stop"
  for _ in 1 2 3; do kill "$(cat "$out/flood.pid")" 2>/dev/null; sleep 0.1; done
  wait "$flood"
  kill -0 "$node3_pid" || { echo "  node3 died"; cat "$out/node3.txt"; return 1; }
  # SIGTERM: the node takes what is still queued for it, then reports.
  kill -TERM "$node3_pid"; wait "$node3" || { echo "  node3 exited with $?"; cat "$out/node3.txt"; return 1; }
  event "node3 stopped (SIGTERM, after taking what was queued for it)"
  # candump (niced) may still be working through its buffer: stop it once its log has stopped
  # growing (the bus is quiet now; its writes are buffered, so "stopped" means for a second).
  renice 0 -p "$dump" >/dev/null 2>&1
  size=-1
  for _ in $(seq 1 120); do
    now_size=$(stat -c %s "$out"/load-capture/candump-*.log 2>/dev/null || echo 0)
    [ "$now_size" -eq "$size" ] && break
    size=$now_size; sleep 1
  done
  kill -TERM "$dump" 2>/dev/null; wait "$dump"
  event "capture closed"
  for name in node2 node3; do tail -n 1 "$out/$name.txt" > "$out/$name.json"; cat "$out/$name.json"; done
  tail -n 1 "$out/play.txt" > "$out/play.json"; cat "$out/play.json"

  # The sender: every frame attempted, sent or refused because the interface was down.
  sent=$(counter sent "$out/play.json"); not_sent=$(counter not_sent "$out/play.json")
  expect "$out/play.json" attempted "$total" && expect "$out/play.json" other_failures 0 || return 1
  [ $((sent + not_sent)) -eq "$total" ] && [ "$(counter interface_down "$out/play.json")" -ge 1 ] ||
    { echo "  sent $sent + not sent $not_sent != $total, or no frame refused while down"; return 1; }
  # The bus: the capture holds the frames sent, in order, but for those the kernel dropped as the
  # interface went down (send() had taken them: in flight); the flood was on it.
  capture=$(ls "$out"/load-capture/candump-*.log 2>/dev/null | head -n 1)
  [ -n "$capture" ] || { echo "  candump -l wrote no log"; return 1; }
  captured_counters "$capture" > "$out/load-sent.txt"
  on_bus=$(wc -l < "$out/load-sent.txt")
  in_flight=$((sent - on_bus))
  flood_on_bus=$(grep -c " $flood_id#" "$capture")
  [ "$in_flight" -ge 0 ] || { echo "  capture: $on_bus input frames, sender: $sent"; return 1; }
  awk 'NR > 1 && $1 <= last { bad = 1 } { last = $1 } END { exit bad }' "$out/load-sent.txt" ||
    { echo "  capture: counters not increasing"; return 1; }
  [ "$flood_on_bus" -ge 100 ] || { echo "  capture: $flood_on_bus flood frames"; return 1; }

  node_accounts node2 && node_accounts node3 || return 1
  f2=$(json_value first_sample "$out/node2.json"); l2=$(json_value last_sample "$out/node2.json")
  f3=$(json_value first_sample "$out/node3.json"); l3=$(json_value last_sample "$out/node3.json")
  # The restarts happened mid-stream, the third node saw the stream to its end.
  [ "$f2" -gt 0 ] && [ "$f3" -gt "$l2" ] && [ "$l3" -eq $((total - 1)) ] ||
    { echo "  samples: node2 $f2..$l2, node3 $f3..$l3 of 0..$((total - 1))"; return 1; }
  # Within each node's span every frame on the bus was used. The frames missing from the bus
  # (refused while down, or in flight as it went down) all lie in node3's span, and are its
  # lost + skipped: the gap the bus down left, reported by the node.
  # Frames on the bus: in node2's span, in node3's, before node2's first sample, between the two.
  count_between "$out/load-sent.txt" "$f2" "$l2" "$f3" "$l3" 0 $((f2 - 1)) $((l2 + 1)) $((f3 - 1)) > "$out/load-spans.txt"
  in2=$(sed -n 1p "$out/load-spans.txt"); in3=$(sed -n 2p "$out/load-spans.txt")
  before2=$(sed -n 3p "$out/load-spans.txt"); between=$(sed -n 4p "$out/load-spans.txt")
  expect "$out/node2.json" accepted "$in2" && expect "$out/node2.json" lost 0 && expect "$out/node2.json" skipped 0 &&
    expect "$out/node3.json" accepted "$in3" || return 1
  gap3=$(( $(counter lost "$out/node3.json") + $(counter skipped "$out/node3.json") ))
  missing=$((total - on_bus))
  [ "$gap3" -eq "$missing" ] && [ $((l3 - f3 + 1 - in3)) -eq "$missing" ] && [ "$missing" -eq $((not_sent + in_flight)) ] &&
    [ "$(counter bus_down "$out/node3.json")" -ge 1 ] ||
    { echo "  node3: lost + skipped = $gap3; not on the bus: $missing (refused $not_sent, in flight $in_flight)"; return 1; }
  # Every frame on the bus: before node2's first sample (node1, killed, and the restart), used by
  # node2, between node2's last and node3's first (the second restart), used by node3.
  [ $((before2 + in2 + between + in3)) -eq "$on_bus" ] || { echo "  the frames on the bus do not add up"; return 1; }
  # The flood: counted as foreign frames, never more than were on the bus.
  unknown=$(( $(counter foreign_frames "$out/node2.json") + $(counter foreign_frames "$out/node3.json") ))
  [ "$unknown" -ge 1 ] && [ "$unknown" -le "$flood_on_bus" ] ||
    { echo "  foreign_frames $unknown for $flood_on_bus flood frames"; return 1; }
  node_used_the_recording node2 && node_used_the_recording node3 || return 1
  echo "  $total samples at ${load_speed}x in $(json_value duration_s "$out/play.json") s: sent $sent, refused while down $not_sent," \
       "on the bus $on_bus (in flight at the down $in_flight); before node2 (node1, killed, and the restart) $before2," \
       "node2 used $in2 (samples $f2..$l2), restart gap $between, node3 used $in3 (samples $f3..$l3," \
       "bus down $(counter bus_down "$out/node3.json"), gap lost + skipped $gap3 = refused + in flight);" \
       "flood on the bus $flood_on_bus, counted foreign_frames $unknown"
}
# The faults are timed at a higher priority; whatever happens, the shell goes back to 0.
ecu_load_faults_at_0() { ecu_load_faults; status=$?; renice 0 -p $$ >/dev/null 2>&1; return $status; }
check "ecu-load-faults: ${load_speed}x replay + cangen flood, node killed and restarted, $iface down/up: every frame accounted" ecu_load_faults_at_0

echo "VCAN-GUEST: $failures failed check(s)"
[ "$failures" -eq 0 ]
