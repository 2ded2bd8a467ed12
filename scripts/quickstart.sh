#!/usr/bin/env bash
# dipc quickstart on Debian 12: installs the missing packages, builds, then either runs the
# default scene on 2 ranks (no argument) or runs the whole test suite (--test).
#
#   scripts/quickstart.sh           # build and run the default scene -> output/dipc.xmf
#   scripts/quickstart.sh --test    # build and run every test (what CI runs)
#
# Environment: BUILD_DIR (default build), JOBS (default: number of cores), DIPC_WITH_CUDA=OFF
# to skip the CUDA kernels where nvcc is installed.
set -euo pipefail

mode=run
case "${1:-}" in
  "") ;;
  --test) mode=test ;;
  -h|--help) sed -n '2,9p' "$0"; exit 0 ;;
  *) echo "quickstart: unknown argument '$1' (use --test or nothing)" >&2; exit 2 ;;
esac

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${BUILD_DIR:-$root/build}
jobs=${JOBS:-$(nproc)}

# --- 1. packages ------------------------------------------------------------
packages=(cmake g++ make pkg-config openmpi-bin libopenmpi-dev petsc-dev libhypre-dev libmetis-dev
          libhdf5-openmpi-dev nlohmann-json3-dev libgtest-dev python3-numpy python3-h5py python3-matplotlib
          python3-dev pybind11-dev python3-mpi4py)
# The test suite also opens the output with ParaView itself (tests/tools/paraview_open_test.py)
# and runs the Python module's tests with pytest.
[[ $mode == test ]] && packages+=(python3-paraview python3-pytest)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "quickstart: installing ${missing[*]}"
  sudo=""
  if [[ $(id -u) -ne 0 ]]; then
    command -v sudo >/dev/null || { echo "quickstart: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
    sudo=sudo
  fi
  $sudo apt-get update -q
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

# --- 2. build ---------------------------------------------------------------
# With a CUDA compiler present the kernels are built too (CI compiles them even without a GPU;
# at run time -dipc_backend auto falls back to the CPU where no device is found).
cuda=()
nvcc=$(command -v nvcc || true)
[[ -z $nvcc && -x /usr/local/cuda/bin/nvcc ]] && nvcc=/usr/local/cuda/bin/nvcc
if [[ -n $nvcc && ${DIPC_WITH_CUDA:-auto} != OFF ]]; then
  echo "quickstart: building the CUDA kernels with $nvcc"
  cuda=(-DDIPC_WITH_CUDA=ON -DCMAKE_CUDA_COMPILER="$nvcc")
fi
# ccache, where installed, keeps rebuilds (and fresh clones on the same machine) fast; paths
# are taken relative to the checkout so that clones in other folders share the cache.
launcher=()
if command -v ccache >/dev/null; then
  export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$root}
  launcher=(-DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  [[ ${#cuda[@]} -gt 0 ]] && launcher+=(-DCMAKE_CUDA_COMPILER_LAUNCHER=ccache)
fi
# The Python module is built for Debian's interpreter, whose packages (numpy, h5py, mpi4py) it
# uses, also where another python3 comes first in PATH.
python=()
[[ -x /usr/bin/python3 ]] && python=(-DPython3_EXECUTABLE=/usr/bin/python3)
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release "${cuda[@]}" "${launcher[@]}" "${python[@]}"
cmake --build "$build" -j "$jobs"

# `import dipc` from anywhere: a .pth file in this user's site-packages names the build's
# python folder (no root needed; delete the file to undo).
if [[ -d $build/python/dipc ]]; then
  site=$(/usr/bin/python3 -c 'import site; print(site.getusersitepackages())')
  mkdir -p "$site" && echo "$build/python" > "$site/dipc.pth"
  echo "quickstart: python3 -c 'import dipc' finds $build/python/dipc (through $site/dipc.pth)"
fi

# Open MPI refuses to run as root and to start more ranks than cores unless told to.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1

# --- 3. run or test -----------------------------------------------------------
if [[ $mode == test ]]; then
  cd "$build"
  ctest --output-on-failure -j "$jobs"
else
  cd "$root"
  mpirun -n 2 "$build/src/app/dipc" "$@"
  echo "quickstart: output in $root/output (open output/dipc.xmf in ParaView; per-step table in output/stats.csv)"
fi
