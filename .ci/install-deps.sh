#!/usr/bin/env bash
# Install everything contactsweep needs to build, test and plot on Debian 12 (bookworm).
# Idempotent: when every package is already installed, apt is not touched at all, so CI and
# developers can call this on every run. Works as root (fresh containers have no sudo) or as a
# user with sudo.
set -euo pipefail

packages=(
  # build
  build-essential cmake git pkg-config
  # libraries (parallel HDF5 must match the MPI implementation: Open MPI)
  libeigen3-dev libopenmpi-dev openmpi-bin libhdf5-openmpi-dev hdf5-tools
  libgtest-dev libgmock-dev libbenchmark-dev libcli11-dev libtomlplusplus-dev libfmt-dev
  libginac-dev  # K in the spec: parsed to GiNaC expressions, derivatives for its traits
  # post-processing and tests/test_post.py (Debian's /usr/bin/python3)
  python3 python3-numpy python3-h5py python3-matplotlib python3-xarray python3-h5netcdf
  # the Python module (src/python/): pybind11, its tests (pytest), its progress bar (tqdm)
  pybind11-dev python3-pybind11 python3-dev python3-pytest python3-tqdm
  # tests: a second and third user for the security test (useradd, setpriv), taskset; strace
  # holds a run between two system calls in the fault test
  passwd util-linux strace
  # clang + its runtime (libFuzzer, sanitizers) for fuzzing
  clang libclang-rt-14-dev
  # the documentation site (docs/, mkdocs.yml): `mkdocs build --strict` in the docs test
  mkdocs
)

missing=()
for p in "${packages[@]}"; do
  # "install ok installed" is the only state that means the package is usable.
  if [[ "$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null)" != "install ok installed" ]]; then
    missing+=("$p")
  fi
done

if ((${#missing[@]} == 0)); then
  echo "install-deps: all ${#packages[@]} packages already installed"
  exit 0
fi
echo "install-deps: installing ${missing[*]}"

if ((EUID == 0)); then
  as_root=()
elif command -v sudo >/dev/null; then
  as_root=(sudo)
else
  echo "install-deps: need root or sudo to install: ${missing[*]}" >&2
  exit 1
fi

# --no-install-recommends keeps containers small; every runtime need of ours is a Depends
# (checked: xarray -> pandas, h5netcdf -> h5py-serial, openmpi-bin -> openssh-client).
"${as_root[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update
"${as_root[@]}" env DEBIAN_FRONTEND=noninteractive \
  apt-get install -y --no-install-recommends "${missing[@]}"

/usr/bin/python3 -c "import numpy, h5py, matplotlib, xarray, h5netcdf, pytest, tqdm"
echo "install-deps: done"
