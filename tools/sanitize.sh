#!/usr/bin/env bash
# Builds the `asan` preset (AddressSanitizer + UndefinedBehaviorSanitizer, Debug -O1) and runs the
# CTest suite under it but the MCU cross builds and the qemu vcan guest; any sanitizer report
# fails the test that raised it.
#   tools/sanitize.sh [ctest options...]
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
start=$(date +%s)
cmake --preset asan >/dev/null
cmake --build --preset asan -j "$(nproc)"
# The embedded tests cross-compile for the MCUs with their own toolchain and flags: the host's
# sanitizers do not reach them, and the release suite runs them already. The vcan guest (label
# vcan) boots a kernel under qemu without KVM, four to five minutes of emulation, the sanitized
# suite's longest test, for the SocketCAN socket calls alone: the bus code above them runs under
# the sanitizers over the loopback bus (test_can, test_cli), the frame codec under the fuzzers,
# and the release suite runs the guest.
ctest --preset asan -j "$(nproc)" -LE 'embedded|vcan' "$@"
echo "sanitize: build and suite under ASan+UBSan in $(( $(date +%s) - start )) s" >&2
