#!/usr/bin/env bash
# Installs the Debian packages sdv builds against (SPEC §2), plus Chromium and Node.js for the
# browser tests of `sdv view`, python3-protobuf for the co-simulation clients, Slurm with
# munge for the test of `sdv sweep --slurm` on a local cluster, and clang with libFuzzer
# (libclang-rt-14-dev) and llvm-symbolizer (llvm) for the fuzz stage (only with --tests). Run as
# root on Debian 12.
set -euo pipefail
pkgs=(build-essential cmake antlr4 libantlr4-runtime-dev libeigen3-dev libpugixml-dev libcli11-dev
      doctest-dev nlohmann-json3-dev libgeographiclib-dev libbenchmark-dev libprotobuf-dev protobuf-compiler libnlopt-cxx-dev)
if [ "${1:-}" = --tests ]; then
    pkgs+=(chromium python3-protobuf slurm-wlm munge clang libclang-rt-14-dev llvm)
    command -v npm >/dev/null || pkgs+=(nodejs npm)
fi
missing=()
for p in "${pkgs[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
    SUDO=""; [ "$(id -u)" -eq 0 ] || SUDO="sudo"
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${missing[@]}"
fi
