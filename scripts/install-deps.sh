#!/usr/bin/env bash
# Installs every Debian package roadscan needs to build, test and run.
# Used by the README commands and by .ci/run; safe to run again.
set -euo pipefail
pkgs=(build-essential cmake ninja-build pkg-config
      libpcap-dev check libyaml-dev libinih-dev libpng-dev
      liblcm-dev liblcm-bin libglib2.0-dev
      tcpdump iproute2 util-linux python3-venv
      strace systemd
      liblcm-java libjchart2d-java libmicrohttpd-dev curl
      libmosquitto-dev libjansson-dev mosquitto mosquitto-clients
      chromium chromium-driver)
# a JDK for the Java types (lcm-spy); kept when one is there
command -v javac >/dev/null || pkgs+=(default-jdk-headless)
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -q
  $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
fi
