#!/usr/bin/env bash
# Installs the Debian packages the project needs, only those that are missing (idempotent, quiet).
set -euo pipefail
packages=(build-essential cmake ccache libcgal-dev libgmp-dev libmpfr-dev libboost-dev libeigen3-dev
          libgtest-dev libgmock-dev libbenchmark-dev
          libcli11-dev nlohmann-json3-dev
          python3)
# Pictures (render/): POV-Ray renders the 3D figures headless, libpng reads PNGs back for the
# content checks, rsvg-convert makes PNG previews of the 2D SVGs.
packages+=(povray libpng-dev librsvg2-bin)
# TetGen 1.5 (AGPL-3+): constrained Delaunay tets for conforming 3D meshes (dim3/conforming_mesh3.cpp).
packages+=(libtet1.5-dev)
# CHOLMOD (SuiteSparse): the sparse Cholesky of deform/ (ARAP, FEM, weights), several times faster
# than Eigen's own on tet meshes; deform/ falls back to Eigen's without it.
packages+=(libsuitesparse-dev)
# OpenBLAS (single-threaded build, deterministic): the BLAS CHOLMOD's supernodal factor runs on.
# Debian's default reference BLAS makes the factorizations of deform/ 2-8x slower.
packages+=(libopenblas0-serial)
packages+=(pybind11-dev python3-dev python3-numpy)  # the Python module (python/) and its tests
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
echo "installing: ${missing[*]}" >&2
SUDO=""
[ "$(id -u)" -ne 0 ] && SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q >/dev/null
$SUDO apt-get install -y -q --no-install-recommends "${missing[@]}" >/dev/null
