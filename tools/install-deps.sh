#!/usr/bin/env bash
# Installs the Debian packages stickslip needs, only those missing (apt-get when root, sudo when
# available); prints what it does and fails clearly when it cannot install.
#   tools/install-deps.sh            build and test dependencies (the arm-none-eabi cross toolchain too)
#   tools/install-deps.sh --report   also what the measurement reports need (plots, callgrind,
#                                    python3 for tools/embedded-report.sh)
#   tools/install-deps.sh --figures  also what tools/paper-figures.sh needs (gnuplot)
#   tools/install-deps.sh --fuzz     also clang and libFuzzer (tools/fuzz.sh)
set -euo pipefail

packages=(cmake g++ make ccache cpputest libcli11-dev nlohmann-json3-dev libfmt-dev libbenchmark-dev libboost-dev
          libtomlplusplus-dev libmatio-dev pkg-config parallel
          # Ceres Solver: the least squares of `stickslip fit` (run/fit_solver.cpp).
          libceres-dev
          # gnuplot: the PNGs of `fit --plot` and `closed-loop --plot` (their tests draw them).
          gnuplot-nox
          gcc-arm-none-eabi libnewlib-arm-none-eabi libstdc++-arm-none-eabi-newlib
          # qemu-system-arm: the firmware on QEMU's mps2 boards against the host build of its node
          # (CTest label embedded); gdb-multiarch turns QEMU's instruction log on for one frame
          # (tools/qemu-frame-profile.sh, CTest embedded.instruction_trace_matches_the_systick_count).
          qemu-system-arm gdb-multiarch
  # clang-format (version 14 in Debian 12): tools/format.sh and the CTest test format.check.
  clang-format
  # can-utils: the candump-log cross-check (log2asc) and the vcan guest's tools. The vcan guest
  # test (tests/vcan) boots a Debian kernel under qemu with an initramfs built by cpio and depmod.
  can-utils qemu-system-x86 busybox-static iproute2 cpio kmod
  # slurm-wlm and munge: the Slurm job-array test (tests/slurm) runs its own private daemons.
  slurm-wlm munge
  # Vector BLF log containers are zlib streams; python-can and canmatrix write and decode the
  # recordings the log and DBC readers are checked against (tools/make-recording-fixtures.py).
  zlib1g-dev python3-can python3-canmatrix
  # libsoxr: recordings resampled to the model's step (sim_host/src/signals/resample.cpp).
  libsoxr-dev
  # The Python module (python/) and its tests (tests/python: pytest, pip install into a venv,
  # the matplotlib example).
  python3-dev python3-pybind11 python3-numpy python3-pytest python3-venv python3-matplotlib)
for group in "$@"; do
  case "$group" in
    --report) packages+=(gnuplot-nox valgrind python3) ;;
    --figures) packages+=(gnuplot-nox) ;;
    --fuzz) packages+=(clang-14 libclang-rt-14-dev) ;;
    *) echo "install-deps: unknown group '$group' (known: --report, --figures, --fuzz)" >&2; exit 2 ;;
  esac
done

missing=()
for package in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$package")
  fi
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "install-deps: installing ${missing[*]}" >&2
if [ "$(id -u)" -eq 0 ]; then
  apt_get=(apt-get)
elif command -v sudo >/dev/null 2>&1; then
  apt_get=(sudo apt-get)
else
  echo "install-deps: missing Debian packages (${missing[*]}) and not root; install them with apt-get" >&2
  exit 1
fi
export DEBIAN_FRONTEND=noninteractive
"${apt_get[@]}" update -qq
"${apt_get[@]}" install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
