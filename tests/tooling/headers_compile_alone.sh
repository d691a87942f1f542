#!/usr/bin/env bash
# Every public header of the core compiles on its own, as an MCU build compiles the core: a
# header that leans on an include its user happened to write first breaks the next user. The
# headers are found now, not at configure time, so a header added later is covered too.
#   headers_compile_alone.sh <C++ compiler> <lib/include> [extra compiler flags...]
# Names each header that fails, with the compiler's first lines for it; exit 1 if any fails.
set -uo pipefail
compiler="$1"
include_dir="$2"
shift 2
flags=(-std=c++17 -fno-exceptions -fno-rtti -Wall -Wextra -Wpedantic -Wshadow -Wdouble-promotion
       -Werror "$@")

mapfile -t headers < <(cd "$include_dir" && find . -type f \( -name '*.hpp' -o -name '*.h' \) |
  sed 's|^\./||' | sort)
if [ ${#headers[@]} -eq 0 ]; then
  echo "FAIL: no header found under $include_dir"
  exit 1
fi

failed=()
for header in "${headers[@]}"; do
  # The header as the only include of a translation unit, by the name its users write.
  if ! output="$(printf '#include "%s"\n' "$header" |
      "$compiler" "${flags[@]}" -I "$include_dir" -x c++ -fsyntax-only - 2>&1)"; then
    failed+=("$header")
    echo "FAIL: $header does not compile on its own:"
    printf '%s\n' "$output" | head -n 12 | sed 's/^/  /'
  fi
done
if [ ${#failed[@]} -gt 0 ]; then
  echo "${#failed[@]} of ${#headers[@]} headers fail: ${failed[*]}"
  exit 1
fi
echo "PASS: ${#headers[@]} headers compile on their own"
