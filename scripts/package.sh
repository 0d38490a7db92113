#!/usr/bin/env bash
# Builds the Debian package (CPack) in build-deb/ and checks what it holds:
# programs in /usr/bin, the sample config as a conffile in /etc/roadscan,
# the systemd unit, man pages, LCM types. Prints the .deb's path.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build-deb -G Ninja -DCMAKE_BUILD_TYPE=Release -DRS_BUILD_TESTS=OFF \
  -DCMAKE_INSTALL_PREFIX=/usr -DCMAKE_INSTALL_SYSCONFDIR=/etc >/dev/null
cmake --build build-deb -j "$(nproc)" >/dev/null
(cd build-deb && cpack >/dev/null)
deb=$(ls build-deb/roadscan_*.deb)
contents=$(dpkg-deb -c "$deb" | awk '{print $6}')
for f in ./usr/bin/roadscand ./usr/bin/roadscan-listen ./usr/bin/roadscan-learn ./etc/roadscan/roadscand.ini \
         ./usr/lib/systemd/system/roadscand.service ./usr/share/man/man8/roadscand.8 \
         ./usr/share/roadscan/lcmtypes/roadscan.lcm ./usr/share/roadscan/python/roadscan/object_list_t.py \
         ./usr/include/roadscan/lcmtypes/roadscan_object_list_t.h ./usr/share/doc/roadscan/examples/listen.py; do
  grep -qx "$f" <<<"$contents" || { echo "package.sh: $deb lacks $f" >&2; exit 1; }
done
dpkg-deb -f "$deb" Depends | grep -q liblcm1 || { echo "package.sh: Depends lacks liblcm1" >&2; exit 1; }
dpkg-deb --ctrl-tarfile "$deb" | tar -xO ./conffiles | grep -qx /etc/roadscan/roadscand.ini ||
  { echo "package.sh: the config is not a conffile" >&2; exit 1; }
tmp=$(mktemp -d)
dpkg-deb -x "$deb" "$tmp"
grep -q '^ExecStart=/usr/bin/roadscand --config /etc/roadscan/roadscand.ini --syslog$' "$tmp/usr/lib/systemd/system/roadscand.service" ||
  { echo "package.sh: the unit does not start /usr/bin/roadscand with /etc/roadscan/roadscand.ini" >&2; exit 1; }
if command -v systemd-analyze >/dev/null; then
  # syntax and directives; the binary itself is not installed on this machine
  msgs=$(SYSTEMD_LOG_LEVEL=warning systemd-analyze verify --man=no "$tmp/usr/lib/systemd/system/roadscand.service" 2>&1 |
         grep -v "Command /usr/bin/roadscand is not executable" || true)
  [ -z "$msgs" ] || { echo "package.sh: systemd-analyze verify: $msgs" >&2; exit 1; }
fi
rm -rf "$tmp"
echo "$deb"
