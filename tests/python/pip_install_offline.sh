#!/usr/bin/env bash
# `pip install .` into a fresh venv (with the system's site packages: Debian's numpy), offline:
# no package index (--no-index) and, where the kernel lets us, no network at all (unshare -n).
# Everything - the copy of the source tree, the venv, the CMake build - stays in SCRATCH.
#   pip_install_offline.sh SOURCE_DIR SCRATCH_DIR PYTHON
set -euo pipefail
source_dir=$1 scratch=$2 python=$3
rm -rf "$scratch"
mkdir -p "$scratch/src"
# A clean copy, as a fresh clone would be (no build trees).
tar -C "$source_dir" --exclude=./build --exclude=./.git -cf - . | tar -C "$scratch/src" -xf -
"$python" -m venv --system-site-packages "$scratch/venv"
# The build tree where the project's own build has it (build/release in the source tree) and its
# warnings as errors, as in that build: the compile commands are then the same, and with ccache
# installed (CMakeLists.txt, STICKSLIP_CCACHE) the objects the project's build compiled are reused.
export CMAKE_ARGS="-DSTICKSLIP_WARNINGS_AS_ERRORS=ON"
install=("$scratch/venv/bin/pip" install --no-index --no-cache-dir
         --config-settings "build-dir=$scratch/src/build/release" "$scratch/src")
offline=()
if unshare -rn true 2>/dev/null; then offline=(unshare -rn); fi
echo "pip_install_offline: ${offline[*]} ${install[*]}"
"${offline[@]}" "${install[@]}"
cd "$scratch"  # not the source tree: the installed package must be the one imported
"$scratch/venv/bin/python" - <<'PY'
import numpy as np
import stickslip
assert "/venv/" in stickslip.__file__, stickslip.__file__
rec = stickslip.generate("lorry", rms=0.35, duration=2, dt=1e-3, seed=1)
trace, stats = stickslip.simulate(rec["a_u"], rec["dt"], model="stick-slip", ffk=45)
assert trace["a_x"].shape == rec["a_u"].shape and 0 < stats["T_ax"] < 2
print("pip_install_offline: imported", stickslip.__file__, "T_ax =", stats["T_ax"])
PY
