#!/usr/bin/env bash
# Builds the libFuzzer targets (the `fuzz` preset: clang, ASan + UBSan) and runs them, one per core
# at a time, each from its seed corpus fuzz/corpus/<target>/ (new inputs go to
# build/fuzz/corpus/<target>/, the repository's seeds stay small). Crashes land in
# build/fuzz/artifacts/ and fail the script.
#   tools/fuzz.sh --short                 15 s per target (CI: a smoke run of every target)
#   tools/fuzz.sh --long [SECONDS]        SECONDS per target (default 3600)
#   tools/fuzz.sh --runs N [TARGET...]    N executions per target (e.g. --runs 10000000)
set -euo pipefail
cd "$(dirname "$0")/.."
mode=${1:---short}
shift || true
limit=()
case "$mode" in
  --short) limit=(-max_total_time=15) ;;
  --long) limit=(-max_total_time="${1:-3600}"); shift || true ;;
  --runs) limit=(-runs="${1:?--runs needs a count}"); shift ;;
  *) echo "fuzz: unknown mode '$mode' (--short, --long [SECONDS], --runs N)" >&2; exit 2 ;;
esac
bash tools/install-deps.sh --fuzz
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz -j "$(nproc)"
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  for path in fuzz/corpus/*/; do targets+=("$(basename "$path")"); done
fi
mkdir -p build/fuzz/artifacts

# One target: its log in build/fuzz/<target>.log, one line on stderr, exit 1 on a finding.
run_target() {
  local target=$1
  shift
  local work=build/fuzz/corpus/$target log=build/fuzz/$target.log start runs
  mkdir -p "$work"
  echo "fuzz: $target $*" >&2
  start=$(date +%s)
  # -detect_leaks=0: libFuzzer's per-input leak check (rerunning every input whose malloc and free
  # counts differ under LeakSanitizer) costs 30x here; leaks are LeakSanitizer's job in the asan
  # suite (tools/sanitize.sh), and ASan still checks the whole run at exit.
  if ! build/fuzz/fuzz/fuzz_"$target" "$@" -detect_leaks=0 -print_final_stats=1 \
      -artifact_prefix=build/fuzz/artifacts/"$target"- "$work" fuzz/corpus/"$target" >"$log" 2>&1; then
    tail -n 40 "$log" >&2
    echo "fuzz: $target FAILED (log $log)" >&2
    return 1
  fi
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
  echo "fuzz: $target ok, $runs executions in $(( $(date +%s) - start )) s" >&2
}
export -f run_target

# Each target is one process on one core: as many at once as there are cores, every one of them
# run to its end; xargs exits non-zero if any failed.
if ! printf '%s\n' "${targets[@]}" |
    xargs -P "$(nproc)" -I '{}' bash -c 'run_target "$@"' _ '{}' "${limit[@]}"; then
  echo "fuzz: a target failed (artifacts in build/fuzz/artifacts/)" >&2
  exit 1
fi
