#!/usr/bin/env bash
# slurm.array_sweep_equals_single_run: docs/SCALING.md's Slurm recipe on a private one-node Slurm
# cluster on this machine. Starts its own munged, slurmctld and slurmd from a scratch directory
# (own key, socket, ports, state and logs; nothing under /etc is read or written), submits the
# doc's sweep.sbatch as a job array and the doc's dependent merge job, and requires the merged CSV
# to equal the single-process sweep of the same points byte for byte. Every daemon it started is
# stopped on exit, also on failure, and the run fails if any process it started is still alive.
#
# Where Slurm cannot start (packages missing, not root, a daemon that does not come up) the test
# prints "SKIPPED: <why>" (CTest counts it as skipped), unless CI=true: then that is a failure,
# with the daemons' log tails. SLURMCTLD, SLURMD and MUNGED name the daemons' binaries (defaults:
# the Debian packages' /usr/sbin ones).
#
# Usage: array_sweep.sh STICKSLIP_BINARY SOURCE_DIR SCRATCH_DIR
#        array_sweep.sh --check-doc SOURCE_DIR   (only: the doc quotes the tested text verbatim)
set -euo pipefail

say() { echo "array_sweep: $*"; }
fail() { echo "array_sweep: FAILED: $*" >&2; exit 1; }

# The fenced block number $2 (1-based) of docs/SCALING.md's "## Slurm job array" section.
doc_block() {
  awk -v want="$2" '
    /^## / { in_section = ($0 == "## Slurm job array") }
    in_section && /^```/ { if (in_block) { in_block = 0; count++ } else { in_block = 1 }; next }
    in_section && in_block && count + 1 == want { print }
  ' "$1/docs/SCALING.md"
}

# The doc shows tools/slurm/sweep.sbatch as its first block and the submit + merge lines as its
# second, whose first line holds the production sizes (the test runs the rest with its own).
check_doc() {
  local source_dir=$1
  if ! cmp -s <(doc_block "$source_dir" 1) "$source_dir/tools/slurm/sweep.sbatch"; then
    diff <(doc_block "$source_dir" 1) "$source_dir/tools/slurm/sweep.sbatch" >&2 || true
    fail "docs/SCALING.md's first Slurm block is not tools/slurm/sweep.sbatch verbatim"
  fi
  submit_lines=$(doc_block "$source_dir" 2)
  [ "$(head -n 1 <<<"$submit_lines")" = "$doc_sizes" ] ||
    fail "docs/SCALING.md's submit block must begin with the line '$doc_sizes'"
  grep -q '^jobid=$(sbatch --parsable --array=1-$N .*sweep.sbatch $N)$' <<<"$submit_lines" ||
    fail "docs/SCALING.md's submit block does not submit sweep.sbatch as an array of N tasks"
  grep -q '^sbatch --dependency=afterok:$jobid --wrap "stickslip merge ' <<<"$submit_lines" ||
    fail "docs/SCALING.md's submit block does not submit the merge as a dependent job"
}

doc_sizes='N=64 CPUS=4'
if [ "${1:-}" = --check-doc ]; then
  [ $# -eq 2 ] || fail "usage: array_sweep.sh --check-doc SOURCE_DIR"
  check_doc "$2"
  say "docs/SCALING.md quotes tools/slurm/sweep.sbatch and the tested submit lines verbatim"
  exit 0
fi
[ $# -eq 3 ] || fail "usage: array_sweep.sh STICKSLIP_BINARY SOURCE_DIR SCRATCH_DIR"
stickslip=$(realpath "$1")
source_dir=$(realpath "$2")
scratch=$3
check_doc "$source_dir"

slurmctld_bin=${SLURMCTLD:-/usr/sbin/slurmctld}
slurmd_bin=${SLURMD:-/usr/sbin/slurmd}
munged_bin=${MUNGED:-/usr/sbin/munged}

# The daemons' output, once this run has started them (older logs are not this run's).
logs_of_this_run=false
log_tails() {
  local log
  [ "$logs_of_this_run" = true ] || return 0
  for log in "$scratch"/log/*.out; do
    [ -s "$log" ] || continue
    echo "---- last lines of $log" >&2
    tail -n 25 "$log" >&2
  done
}

# Slurm could not be started: skipped on a developer's machine, a failure in CI.
cannot_start() {
  if [ "${CI:-}" = true ]; then
    echo "array_sweep: FAILED: Slurm could not be started (CI=true): $*" >&2
    log_tails
    exit 1
  fi
  log_tails
  echo "SKIPPED: $*"
  exit 0
}

[ "$(id -u)" -eq 0 ] || cannot_start "not root: slurmd must run as root to start the jobs"
missing="is not installed (tools/install-deps.sh installs slurm-wlm and munge)"
for tool in "$slurmctld_bin" "$slurmd_bin" "$munged_bin"; do
  [ -x "$tool" ] || cannot_start "$tool $missing"
done
for tool in mungekey sbatch squeue scontrol sinfo; do
  command -v "$tool" >/dev/null || cannot_start "$tool $missing"
done

# As root, the test runs as process 1 of a PID namespace of its own: slurmstepd detaches from
# slurmd, and its orphans are then this shell's to reap instead of the machine's init; whatever
# is still alive when the test ends, even when it is killed (--kill-child), dies with the
# namespace. Where namespaces are unavailable it runs as it is.
if [ "$(id -u)" -eq 0 ] && [ -z "${STICKSLIP_SLURM_NAMESPACE:-}" ] &&
  unshare --pid --fork --mount-proc true 2>/dev/null; then
  exec unshare --pid --fork --mount-proc --kill-child \
    env STICKSLIP_SLURM_NAMESPACE=1 bash "$0" "$stickslip" "$source_dir" "$scratch"
fi

# 4 shards of one CPU each: two waves on a 2-core machine, well inside the time limit.
test_shards=4
test_cpus=1
start_seconds=$SECONDS
# Every wait below ends by this point, so that the test fails with its own message and its exit
# trap (at most 15 s) stops the daemons well before CTest's timeout of 180 s kills it.
budget_end=$((SECONDS + 150))
# Seconds to wait: $1, or less if the budget ends sooner.
within_budget() {
  local left=$((budget_end - SECONDS))
  echo $(($1 < left ? $1 : left))
}

mkdir -p "$scratch"
scratch=$(realpath "$scratch")
# Every process this test starts carries this variable: the leftover check finds them by it.
marker="STICKSLIP_SLURM_TEST=$scratch"

# Whether process $1 exists and has not exited (a child of ours that exited stays a zombie until
# it is reaped). The state follows the command name in parentheses, which may hold spaces.
running() {
  local stat state
  read -r stat 2>/dev/null <"/proc/$1/stat" || return 1
  state=${stat##*) }
  [ "${state%% *}" != Z ]
}

# Processes carrying the marker: the daemons, slurmstepd and the jobs (this shell does not).
marked_processes() {
  grep -lzxF "$marker" /proc/[0-9]*/environ 2>/dev/null |
    sed -n 's|^/proc/\([0-9]*\)/environ$|\1|p' || true
}

# Ends the given processes: SIGTERM, up to 15 s in all for a clean exit (slurmctld saves its
# state), then SIGKILL. Our own children are reaped so that they do not linger as zombies.
stop_processes() {
  local pid until=$((SECONDS + 15))
  for pid in "$@"; do kill -TERM "$pid" 2>/dev/null || true; done
  for pid in "$@"; do
    while running "$pid"; do
      if [ $SECONDS -ge $until ]; then
        kill -KILL "$pid" 2>/dev/null || true
        break
      fi
      sleep 0.1
    done
    wait "$pid" 2>/dev/null || true
  done
}

# Outside a PID namespace, a run killed before its trap could run leaves its daemons behind: they
# carry this scratch directory's marker, so they are this test's own and are stopped first.
mapfile -t stale < <(marked_processes)
if [ ${#stale[@]} -gt 0 ]; then
  say "stopping processes left by an earlier run in $scratch: ${stale[*]}"
  stop_processes "${stale[@]}"
fi
rm -rf "$scratch"
mkdir -p "$scratch"/{etc,munge,run,state,spool,log,bin,work}
logs_of_this_run=true
chmod 700 "$scratch/munge"
# munged requires its socket directory to be reachable by every user (the key directory not).
chmod 755 "$scratch/run"
conf=$scratch/etc/slurm.conf

daemon_pids=()
cleanup() {
  local status=$? left
  trap - EXIT
  # In reverse order of start: slurmd first, so that no job starts while the controller stops.
  if [ ${#daemon_pids[@]} -gt 0 ]; then
    local reversed=() i
    for ((i = ${#daemon_pids[@]} - 1; i >= 0; i--)); do reversed+=("${daemon_pids[i]}"); done
    stop_processes "${reversed[@]}"
  fi
  mapfile -t left < <(marked_processes)
  if [ ${#left[@]} -gt 0 ]; then
    echo "array_sweep: FAILED: processes still running after the daemons stopped:" >&2
    ps -o pid=,args= -p "$(IFS=,; echo "${left[*]}")" >&2 || true
    stop_processes "${left[@]}"
    status=1
  fi
  [ -z "${munge_socket_dir:-}" ] || rm -rf "$munge_socket_dir"
  exit "$status"
}
trap cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

# The recordings and the single-process run of the very points sweep.sbatch sweeps: its sweep
# options are the words between "stickslip" and "--threads".
ln -s "$stickslip" "$scratch/bin/stickslip"
export PATH="$scratch/bin:$PATH"
cd "$scratch/work"
for kind in wideband lorry; do
  stickslip generate --kind $kind --rms 0.35 --duration 2 --dt 0.001 --output $kind.csv >/dev/null
done
cp "$source_dir/tools/slurm/sweep.sbatch" sweep.sbatch
sweep_text=$(sed -n '/^stickslip sweep /,/[^\\]$/p' sweep.sbatch | sed 's/\\$//' | tr '\n' ' ')
sweep_text=${sweep_text#stickslip }
sweep_text=${sweep_text%%--threads*}
read -r -a sweep_args <<<"$sweep_text"
[ "${sweep_args[0]:-}" = sweep ] && [ ${#sweep_args[@]} -gt 4 ] ||
  fail "could not read the sweep options from tools/slurm/sweep.sbatch"
stickslip "${sweep_args[@]}" --output single.csv >/dev/null
points=$(($(wc -l <single.csv) - 1))
say "single-process run: ${sweep_args[*]} -> $points points"

# Two distinct TCP ports that nothing listens on now (/proc/net/tcp*: state 0A is LISTEN).
listening=$(awk 'FNR > 1 && $4 == "0A" { split($2, a, ":"); print a[2] }' \
  /proc/net/tcp /proc/net/tcp6 |
  while read -r hex; do echo $((16#$hex)); done | sort -u)
free_port() {
  local port
  while :; do
    port=$((20000 + RANDOM % 40000))
    grep -qx "$port" <<<"$listening" || { echo "$port"; return; }
  done
}
ctld_port=$(free_port)
slurmd_port=$(free_port)
while [ "$slurmd_port" = "$ctld_port" ]; do slurmd_port=$(free_port); done

# A unix socket path holds at most 107 bytes: a deep build tree gets a short directory in /tmp.
munge_socket=$scratch/run/munge.socket
if [ ${#munge_socket} -gt 100 ]; then
  munge_socket_dir=$(mktemp -d /tmp/stickslip-munge-XXXXXX)
  munge_socket=$munge_socket_dir/munge.socket
fi
mungekey --create --keyfile="$scratch/munge/munge.key" >/dev/null 2>&1 ||
  cannot_start "mungekey could not create a key"

# The node as slurmd finds the hardware (CPUs, sockets, cores, threads, memory), named localhost.
node_line=$("$slurmd_bin" -C 2>/dev/null | head -n 1) || true
[[ $node_line == NodeName=* ]] || cannot_start "'slurmd -C' does not describe this machine"
node_line="NodeName=localhost NodeAddr=127.0.0.1 ${node_line#NodeName=* }"
cat >"$conf" <<EOF
# A private one-node cluster for this test only.
ClusterName=stickslip-test
SlurmctldHost=localhost
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$munge_socket
StateSaveLocation=$scratch/state
SlurmdSpoolDir=$scratch/spool
SlurmctldPidFile=$scratch/state/slurmctld.pid
SlurmdPidFile=$scratch/spool/slurmd.pid
SlurmctldLogFile=$scratch/log/slurmctld.log
SlurmdLogFile=$scratch/log/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/builtin
MpiDefault=none
MailProg=/bin/true
ReturnToService=2
# A failed shard cancels the merge at once instead of leaving it pending for ever.
DependencyParameters=kill_invalid_depend
$node_line State=UNKNOWN
PartitionName=test Nodes=localhost Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF=$conf

# Waits up to $1 seconds (less if the budget ends sooner) for the command $4... to succeed
# while the daemon $2, named $3, runs.
wait_for() {
  local seconds pid=$2 name=$3
  seconds=$(within_budget "$1")
  shift 3
  local tries=$((seconds * 4))
  until "$@" >/dev/null 2>&1; do
    running "$pid" || cannot_start "$name exited at start"
    tries=$((tries - 1))
    [ $tries -gt 0 ] || cannot_start "$name did not come up within $seconds s"
    sleep 0.25
  done
}

env "$marker" "$munged_bin" --foreground --socket="$munge_socket" \
  --key-file="$scratch/munge/munge.key" --pid-file="$scratch/munge/munged.pid" \
  --log-file="$scratch/log/munged.log" --seed-file="$scratch/munge/munged.seed" \
  >"$scratch/log/munged.out" 2>&1 &
daemon_pids+=($!)
wait_for 20 $! munged test -S "$munge_socket"

env "$marker" "$slurmctld_bin" -D -c -f "$conf" >"$scratch/log/slurmctld.out" 2>&1 &
daemon_pids+=($!)
wait_for 30 $! slurmctld bash -c 'scontrol ping | grep -q "is UP"'

env "$marker" "$slurmd_bin" -D -f "$conf" -N localhost >"$scratch/log/slurmd.out" 2>&1 &
daemon_pids+=($!)
wait_for 30 $! slurmd bash -c '[ "$(sinfo -h -n localhost -o %t)" = idle ]'
say "munged, slurmctld (port $ctld_port), slurmd (port $slurmd_port) up after" \
  "$((SECONDS - start_seconds)) s: $(sinfo -h -N -o '%N %c CPUs %m MB %t')"

# The doc's submit and merge lines, with the test's sizes in place of the production ones.
{
  echo "N=$test_shards CPUS=$test_cpus"
  tail -n +2 <<<"$submit_lines"
} >submit.sh
say "submitting: $(tr '\n' ';' <submit.sh)"
env "$marker" bash -euo pipefail submit.sh

# Bounded wait until the queue is empty: the array tasks and the merge have all ended.
jobs_start=$SECONDS
jobs_limit=$(within_budget 90) # the sweep itself takes about 2 s of CPU
while [ -n "$(squeue -h -o %i)" ]; do
  if [ $((SECONDS - jobs_start)) -ge $jobs_limit ]; then
    squeue -t all -o '%.10i %.20j %.10T %r' >&2
    log_tails
    fail "the jobs did not finish within $jobs_limit s"
  fi
  sleep 0.5
done
say "all jobs ended $((SECONDS - jobs_start)) s after submission:"
squeue -t all -h -o '%i %j %T' | sort -V | sed 's/^/  /'

states=$(squeue -t all -h -o '%i %T')
expected_jobs=$((test_shards + 1))
if [ "$(grep -c ' COMPLETED$' <<<"$states")" -ne $expected_jobs ]; then
  for log in logs/* slurm-*.out; do
    [ -s "$log" ] && { echo "---- $log" >&2; tail -n 20 "$log" >&2; }
  done
  log_tails
  fail "expected $expected_jobs completed jobs ($test_shards shards and the merge)"
fi
[ -f sweep.csv ] || fail "the merge job wrote no sweep.csv"
cmp single.csv sweep.csv || fail "the merged array sweep differs from the single-process run"
say "the $test_shards-task Slurm array merged by its dependent job equals the single run" \
  "($points points), byte for byte; $((SECONDS - start_seconds)) s"
