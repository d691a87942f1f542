#!/usr/bin/env bash
# A newcomer's first session: every subcommand's --help, --version and a short demo, run from a
# fresh working directory with TMPDIR pointed at a fresh, empty directory. Afterwards TMPDIR must
# still be empty (no scratch space outlives the command) and the source tree's `git status` must
# not have changed (nothing is written into the checkout).
#   newcomer_session.sh STICKSLIP SOURCE_DIR
set -euo pipefail
stickslip=$1
source_dir=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir "$work/tmp" "$work/cwd"
export TMPDIR=$work/tmp
fail() { echo "newcomer_session: $*" >&2; exit 1; }

git_status() { git -C "$source_dir" status --porcelain 2>/dev/null || echo "(not a checkout)"; }
before=$(git_status)

cd "$work/cwd"
"$stickslip" --help >/dev/null
"$stickslip" --version | grep -q '^stickslip [0-9]' || fail "--version does not print the version"
# Bare `stickslip` lists the subcommands on stderr (status 2): the list this session walks.
set +e
list=$("$stickslip" 2>&1 >/dev/null)
status=$?
set -e
[ "$status" = 2 ] || fail "bare stickslip exited $status, expected 2"
names=$(echo "$list" | sed -e 's/.*required: //' -e 's/ (.*//' -e 's/,//g' -e 's/ or / /')
[ -n "$names" ] || fail "bare stickslip lists no subcommands: $list"
for name in $names; do
  "$stickslip" "$name" --help >/dev/null || fail "$name --help failed"
done
"$stickslip" demo --duration 5 >demo.txt || fail "the demo failed: $(cat demo.txt)"
[ -s stickslip-demo/lorry.csv ] || fail "the demo wrote no stickslip-demo/lorry.csv in the working directory"
grep -q "files: stickslip-demo" demo.txt || fail "the demo does not name its folder"

left=$(ls -A "$TMPDIR")
[ -z "$left" ] || fail "left behind in TMPDIR: $left"
after=$(git_status)
[ "$before" = "$after" ] || fail "the source tree changed: $after"
echo "newcomer_session: $(echo $names | wc -w) subcommands, demo in ./stickslip-demo, TMPDIR empty, source tree unchanged"
