#!/usr/bin/env bash
# Installs the Debian 12 packages shapepress needs to build, test and run — only those missing.
# Quiet and fast when everything is there; idempotent; needs root only when something is missing.
#   scripts/install-deps.sh            build + test + run dependencies
#   scripts/install-deps.sh --peers    also the peer engines for benchmarks (LIGGGHTS, LAMMPS, MPI)
set -euo pipefail

packages=(
  g++ cmake ninja-build pkg-config git make
  libopencv-dev libcgal-dev libeigen3-dev libopenvdb-dev libhdf5-dev libtbb-dev
  libboost-iostreams-dev libtomlplusplus-dev libcli11-dev libspdlog-dev libfmt-dev
  nlohmann-json3-dev libgtest-dev libgmock-dev libbenchmark-dev gnuplot-nox clang-format
)
packages+=(libnlopt-dev)  # calibrate: BOBYQA (NLopt)
packages+=(libssl-dev)  # common: SHA-256 of a run's inputs (libcrypto)
packages+=(libtiff-dev)  # imaging: the SEM metadata tags of TIFF images
packages+=(libgif-dev)  # imaging: GIF input (ImageJ's samples; OpenCV 4.6 reads no GIF)
packages+=(clang libclang-rt-dev)  # CI's fuzzers (scripts/fuzz.sh): clang and its libFuzzer
packages+=(calculix-ccx)  # fem-plate: the finite element solver, run as a child process
packages+=(gmsh)  # fem-plate: the tetrahedral mesher of a [particle]'s volume, run as a child process
# A one-node Slurm for the cluster test (scripts/local-slurm.sh): installed when root; without
# root and without them, that one test skips and nothing else needs them.
optional=(slurmctld slurmd slurm-client munge)
if [[ "${1:-}" == "--peers" ]]; then
  packages+=(liggghts lammps openmpi-bin python3 time valgrind)
elif [[ -n "${1:-}" ]]; then
  echo "install-deps.sh: unknown option '$1' (only --peers)" >&2
  exit 2
fi

is_installed() {
  [[ "$(dpkg-query -W -f='${db:Status-Status}' "$1" 2>/dev/null || true)" == "installed" ]]
}
missing=()
for p in "${packages[@]}"; do
  is_installed "$p" || missing+=("$p")
done
if [[ $(id -u) -eq 0 ]]; then
  for p in "${optional[@]}"; do
    is_installed "$p" || missing+=("$p")
  done
fi
if [[ ${#missing[@]} -eq 0 ]]; then
  exit 0
fi

echo "install-deps.sh: installing ${#missing[@]} missing Debian package(s): ${missing[*]}"
if [[ $(id -u) -ne 0 ]]; then
  echo "install-deps.sh: these packages are missing and installing them needs root:" >&2
  echo "  sudo $0 ${1:-}" >&2
  exit 2
fi
export DEBIAN_FRONTEND=noninteractive
# An install fails with stale lists on a fresh machine; update once, quietly.
apt-get update -qq
apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "install-deps.sh: done"
