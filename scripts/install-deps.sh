#!/usr/bin/env bash
# Installs exactly the Debian packages DeepContact needs to build, test, benchmark and plot.
# Idempotent: packages already present are skipped, and apt is not touched at all when
# everything is installed. Run as root (or with sudo available).
#
#   scripts/install-deps.sh            build + test + bench dependencies
#   scripts/install-deps.sh --torch    also python3-torch (only for benchmarks/compare/torch_compare.py)
#   scripts/install-deps.sh --fuzz     also clang + libFuzzer runtime (fuzz harnesses)
#   scripts/install-deps.sh --siconos  also Siconos numerics, its Python module and libfclib: only for
#                                      benchmarks/compare/siconos_compare (built when they are present)
#                                      and the FCLIB compatibility tests against libfclib (docs/lcp.md)
#   scripts/install-deps.sh --box2d    also Box2D 2.4.1 (libbox2d-dev): only for benchmarks/compare/box2d_compare
set -euo pipefail

packages=(
  build-essential cmake pkg-config git
  libeigen3-dev      # dense/sparse linear algebra (J, A, GEMM for the CNN)
  libccd-dev         # general convex collision (polygon and ellipse pairs, engine/src/collision/ccd_narrow.cpp)
  libgsl-dev         # portable random streams (scene generation, weight init)
  libhdf5-dev        # trajectories, data sets, models, bench results (C and C++ API)
  libcli11-dev       # command line of the deepcontact executable
  libtomlplusplus-dev # scene files
  libsuitesparse-dev # CHOLMOD: sparse Cholesky of the newton-sparse solver (lcp/src/solvers/newton_sparse/)
  libgtest-dev libgmock-dev googletest # unit tests
  libbenchmark-dev   # micro-benchmarks of the hot kernels
  libomp-dev         # OpenMP runtime headers (g++ uses libgomp; clang needs libomp)
  openmpi-bin libopenmpi-dev # MPI: generate, bench and train across ranks (mpirun/srun; docs/cluster.md)
  python3 python3-numpy python3-matplotlib python3-h5py # report plots
  python3-dev python3-pybind11 pybind11-dev python3-scipy python3-pytest # the Python module (python/) and its tests
  python3-pil ffmpeg # deepcontact render: GIF (Pillow) and MP4 (ffmpeg)
  python3-venv python3-setuptools python3-pip # pip install --no-build-isolation . (scripts/check-install.sh)
)
for arg in "$@"; do
  case "$arg" in
    --torch) packages+=(python3-torch) ;;
    --fuzz) packages+=(clang libclang-rt-dev) ;;
    --siconos) packages+=(libsiconos-numerics-dev python3-siconos libfclib-dev) ;;
    --box2d) packages+=(libbox2d-dev) ;;
    *) echo "install-deps.sh: unknown option '$arg'" >&2; exit 2 ;;
  esac
done

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
