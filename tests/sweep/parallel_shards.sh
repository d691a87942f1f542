#!/usr/bin/env bash
# A sweep run as 4 shards through GNU parallel, merged, must equal the single-process run byte
# for byte. Usage: parallel_shards.sh STICKSLIP_BINARY
set -euo pipefail
stickslip=$1
if ! parallel --version 2>/dev/null | grep -q "GNU parallel"; then
  echo "parallel_shards: GNU parallel is not installed (tools/install-deps.sh installs it)" >&2
  exit 1
fi
work=$(mktemp -d "${TMPDIR:-/tmp}/stickslip-shards-XXXXXX")
trap 'rm -rf "$work"' EXIT
cd "$work"
"$stickslip" generate --kind wideband --rms 0.35 --duration 20 --dt 0.001 --seed 1 --output wideband.csv >/dev/null
"$stickslip" generate --kind EM6 --duration 20 --dt 0.001 --seed 2 --output em6.csv >/dev/null
sweep=(sweep --input wideband.csv --input em6.csv --method signum:euler,stick-slip:exact,stick-slip:rk4
       --damping 504,200 --k-range 0:1.5:16 --quiet)
"$stickslip" "${sweep[@]}" --output single.csv >/dev/null
parallel --halt now,fail=1 "$stickslip" "${sweep[@]}" --threads 1 --shard {}/4 --output shard{}.csv ::: 1 2 3 4 >/dev/null
"$stickslip" merge shard1.csv shard2.csv shard3.csv shard4.csv --output merged.csv >/dev/null
rows=$(($(wc -l < single.csv) - 1))
[ "$rows" -eq 192 ] || { echo "parallel_shards: expected 192 points, got $rows" >&2; exit 1; }
cmp single.csv merged.csv
echo "parallel_shards: 4 shards through GNU parallel merge into the single run ($rows points), byte for byte"
