#!/usr/bin/env bash
# Proves that `tools/format.sh --check` can fail: a formatted source copied into a scratch
# directory passes, the same copy with its indentation broken must fail naming the file.
# A missing or wrong clang-format makes the check exit 2, which fails this test too.
#   format_check_can_fail.sh <format.sh> <source dir> <scratch dir>
set -euo pipefail
format_sh="$1"
source_dir="$2"
scratch="$3"
# A file of the tests' own support: formatted, indented, and not moved by the library's layout.
sample=tests/support/test_main.cpp

rm -rf "$scratch"
mkdir -p "$scratch"
# The style travels with the copy: clang-format looks for .clang-format above each file.
cp "$source_dir/.clang-format" "$scratch/"
cp "$source_dir/$sample" "$scratch/sample.cpp"

status=0
output="$("$format_sh" --check "$scratch" 2>&1)" || status=$?
if [ $status -ne 0 ]; then
  printf '%s\n' "$output"
  echo "FAIL: --check on an unmodified formatted copy exited $status, expected 0"
  exit 1
fi

# Two-space indentation becomes five: never what .clang-format (Google, 2) writes.
sed -i 's/^  \([^ ]\)/     \1/' "$scratch/sample.cpp"
if cmp -s "$source_dir/$sample" "$scratch/sample.cpp"; then
  echo "FAIL: $sample has no indented line to mis-format"
  exit 1
fi

status=0
output="$("$format_sh" --check "$scratch" 2>&1)" || status=$?
printf '%s\n' "$output"
if [ $status -ne 1 ]; then
  echo "FAIL: --check on a mis-formatted copy exited $status, expected 1"
  exit 1
fi
if ! grep -qx "not formatted: sample.cpp" <<<"$output"; then
  echo "FAIL: --check did not name sample.cpp"
  exit 1
fi
echo "PASS: formatted copy 0, mis-formatted copy 1 naming sample.cpp"
