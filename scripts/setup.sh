#!/usr/bin/env bash
# Installs every build and test dependency of sphfem from Debian 12 packages. Idempotent:
# quiet and quick when everything is already there. Needs root (or sudo) only to install.
set -euo pipefail

packages=(
  cmake g++ ninja-build pkg-config
  libvtk9-dev            # VTK 9.1: VTU output, post-processing
  gmsh libgmsh-dev       # gmsh 4.8 C++ API: the mesher
  libeigen3-dev          # Eigen 3.4
  libopenmpi-dev openmpi-bin  # Open MPI 4.1: mpirun (-DSPHFEM_MPI, on when found)
  libtrilinos-zoltan-dev libptscotch-dev  # Zoltan (Trilinos 13.2): the decomposition's RCB;
                         # its CMake target links (PT-)Scotch's .so files
  libhdf5-dev hdf5-tools # HDF5 1.10 C++ API: model.h5, history.h5
  libgtest-dev libgmock-dev
  libyaml-cpp-dev libcli11-dev nlohmann-json3-dev
  clang-format
  python3                # scripts/validate.sh's page (standard library only)
  clang libclang-rt-14-dev libomp-14-dev  # scripts/hostile-input.sh: libFuzzer and sanitizers
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0

sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
echo "setup: installing ${missing[*]}"
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "setup: done"
