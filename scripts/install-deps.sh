#!/usr/bin/env bash
# Installs everything clpt needs to build, test and render on Debian 12.
# Idempotent: packages already present are left as they are.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  ocl-icd-opencl-dev opencl-headers pocl-opencl-icd clinfo
  libglm-dev libtinygltf-dev nlohmann-json3-dev libcli11-dev
  # Image files: OpenEXR, libpng, libjpeg-turbo and libwebp (host/io/*_codec), xxHash
  # (util/hash.h). OpenImageIO and its tools are for the tests only: an independent reader
  # and writer of the same formats.
  libopenexr-dev libpng-dev libjpeg-dev libwebp-dev libxxhash-dev
  libopenimageio-dev openimageio-tools
  libdraco-dev libmeshoptimizer-dev
  libgtest-dev libboost-math-dev
  # The vendor compile checks (scripts/kernel_compile_check.py, ctest label portability):
  # clang-15 and libclc for NVIDIA PTX and AMD GCN, Intel's offline compiler ocloc (it comes
  # with Intel's OpenCL ICD, which also registers /etc/OpenCL/vendors/intel.icd; the test
  # scripts keep sanitized processes away from it, scripts/test-sanitize.sh says why).
  python3 clang-15 libclc-15 intel-opencl-icd
  # The Python module (host/python, docs/python.md): pybind11 and NumPy for Debian's python3.
  python3-dev python3-numpy python3-pybind11
  # Open MPI: mpirun -n K clpt ... splits a render across processes and machines
  # (host/app/mpi_cluster.cpp, docs/scaling.md); clpt builds without it too (CLPT_MPI).
  openmpi-bin libopenmpi-dev
  # Oclgrind: a simulated OpenCL device with memory checks (scripts/oclgrind-check.sh).
  oclgrind bc
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages already installed"
  exit 0
fi

sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "install-deps: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  sudo_cmd=(sudo)
fi

echo "install-deps: installing ${missing[*]}"
"${sudo_cmd[@]}" apt-get update -qq
DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
