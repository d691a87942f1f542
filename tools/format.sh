#!/usr/bin/env bash
# The repository's .clang-format applied by clang-format 14 (Debian package clang-format, which
# tools/install-deps.sh installs); another major version formats some constructs differently.
#   tools/format.sh                formats every C/C++ source of this checkout in place
#   tools/format.sh --check [DIR]  names each C/C++ source of DIR (default: this checkout) that
#                                  differs from its formatted form; exit 1 when there is one
# The sources of DIR: in a git checkout, the files git tracks there (what a commit would carry);
# in a plain copy, or a directory where git tracks nothing (a scratch copy under a build tree),
# every file below it, build trees (a directory holding CMakeCache.txt) left out. Fuzz corpora (corpus/
# folders) are inputs, not sources, and are never touched. Exit 2 on a usage error or when
# clang-format 14 is missing, so a missing tool never reads as "all formatted".
set -euo pipefail

usage() {
  echo "usage: tools/format.sh [--check [DIR]]" >&2
  exit 2
}

check=0
dir=""
case "${1:-}" in
  "") ;;
  --check)
    check=1
    dir="${2:-}"
    [ $# -le 2 ] || usage
    ;;
  *) usage ;;
esac
[ -n "$dir" ] || dir="$(cd "$(dirname "$0")/.." && pwd)"
[ -d "$dir" ] || { echo "format.sh: $dir: not a directory" >&2; exit 2; }
dir="$(cd "$dir" && pwd)"

clang_format="${CLANG_FORMAT:-}"
if [ -z "$clang_format" ]; then
  for candidate in clang-format-14 clang-format; do
    if command -v "$candidate" >/dev/null 2>&1; then
      clang_format="$candidate"
      break
    fi
  done
fi
if [ -z "$clang_format" ] || ! command -v "$clang_format" >/dev/null 2>&1; then
  echo "format.sh: clang-format not found; install clang-format 14 (tools/install-deps.sh)" >&2
  exit 2
fi
version="$("$clang_format" --version)"
if ! [[ "$version" =~ version\ 14\. ]]; then
  echo "format.sh: $clang_format is '$version'; the tree is formatted by clang-format 14" >&2
  exit 2
fi

sources=()
if git -C "$dir" rev-parse --is-inside-work-tree >/dev/null 2>&1 &&
   ! git -C "$dir" check-ignore -q "$dir"; then
  while IFS= read -r -d '' file; do
    sources+=("$dir/$file")
  done < <(git -C "$dir" ls-files -z -- '*.c' '*.cc' '*.cpp' '*.cxx' '*.h' '*.hh' '*.hpp' '*.hxx' \
             '*.ipp' '*.inl' ':!:*corpus/*')
fi
# Not a checkout, or one where git tracks no source here (a scratch copy inside a work tree).
if [ ${#sources[@]} -eq 0 ]; then
  prune=(-name .git -o -name corpus)
  while IFS= read -r -d '' cache; do
    prune+=(-o -path "$(dirname "$cache")")
  done < <(find "$dir" -name CMakeCache.txt -print0)
  while IFS= read -r -d '' file; do
    sources+=("$file")
  done < <(find "$dir" \( "${prune[@]}" \) -prune -o -type f \
             \( -name '*.c' -o -name '*.cc' -o -name '*.cpp' -o -name '*.cxx' -o -name '*.h' \
                -o -name '*.hh' -o -name '*.hpp' -o -name '*.hxx' -o -name '*.ipp' -o -name '*.inl' \) \
             -print0 | sort -z)
fi
if [ ${#sources[@]} -eq 0 ]; then
  echo "format.sh: no C/C++ sources under $dir" >&2
  exit 2
fi

if [ $check -eq 0 ]; then
  "$clang_format" -i --style=file "${sources[@]}"
  exit 0
fi

# One clang-format run over every file (a process per file takes minutes on a loaded machine):
# --dry-run -Werror reports each file that would change, --ferror-limit=1 once per file.
status=0
report="$("$clang_format" --dry-run -Werror --ferror-limit=1 --style=file "${sources[@]}" 2>&1)" ||
  status=$?
mapfile -t unformatted < <(printf '%s\n' "$report" |
  sed -n 's/^\(.*\):[0-9]*:[0-9]*: error: code should be clang-formatted.*/\1/p' | sort -u)
if [ ${#unformatted[@]} -gt 0 ]; then
  printf 'not formatted: %s\n' "${unformatted[@]#"$dir"/}"
  echo "format.sh: ${#unformatted[@]} of ${#sources[@]} files differ from .clang-format; run tools/format.sh" >&2
  exit 1
fi
if [ $status -ne 0 ]; then
  # A failure that names no file (an unreadable file, a bad .clang-format): never "formatted".
  printf '%s\n' "$report" >&2
  echo "format.sh: clang-format failed (status $status)" >&2
  exit 2
fi
echo "format.sh: ${#sources[@]} files formatted"
