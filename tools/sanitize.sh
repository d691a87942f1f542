#!/usr/bin/env bash
# Builds the `asan` preset (AddressSanitizer + UndefinedBehaviorSanitizer, Debug -O1) and runs the
# whole CTest suite under it but the MCU cross builds; any sanitizer report fails the test that
# raised it.
#   tools/sanitize.sh [ctest options...]
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
start=$(date +%s)
cmake --preset asan >/dev/null
cmake --build --preset asan -j "$(nproc)"
# The embedded tests cross-compile for the MCUs with their own toolchain and flags: the host's
# sanitizers do not reach them, and the release suite runs them already.
ctest --preset asan -j "$(nproc)" -LE embedded "$@"
echo "sanitize: build and suite under ASan+UBSan in $(( $(date +%s) - start )) s" >&2
