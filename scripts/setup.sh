#!/usr/bin/env bash
# Installs every Debian 12 package that the build, the tests, the plots and the studies need.
# Idempotent; run as root (or through sudo) on a fresh Debian 12 machine.
set -euo pipefail
pkgs=(cmake g++ make ninja-build pkg-config
      libeigen3-dev libceres-dev libnlopt-cxx-dev
      catch2 libtomlplusplus-dev libcli11-dev
      gnuplot-nox libboost-dev openmpi-bin libopenmpi-dev)
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  SUDO=""; [ "$(id -u)" = 0 ] || SUDO=sudo
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
  echo "setup: installed ${missing[*]}"
else
  echo "setup: all packages present"
fi
