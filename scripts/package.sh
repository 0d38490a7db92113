#!/usr/bin/env bash
# Builds the Debian package (CPack) in build-deb/ and checks what it holds:
# programs in /usr/bin, the sample config as a conffile in /etc/roadscan,
# the systemd unit, man pages, LCM types, copyright, changelog and licence, the
# maintainer field; runs the maintainer scripts on the unpacked tree as dpkg
# would (DPKG_ROOT): enabled on installation, masked on removal, forgotten on
# purge. Prints the .deb's path.
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
# the live view: its page and its unit
for f in ./usr/bin/roadscan-web ./usr/share/roadscan/www/index.html ./usr/share/roadscan/www/app.js \
         ./usr/share/roadscan/www/style.css ./usr/lib/systemd/system/roadscan-web.service; do
  grep -qx "$f" <<<"$contents" || { echo "package.sh: $deb lacks $f" >&2; exit 1; }
done
# the consumer libraries: C (shared, static, pkg-config), Python (a wheel), Java (with a JDK and liblcm-java)
for f in libroadscan-lcmtypes.so.0 libroadscan-lcmtypes.a pkgconfig/roadscan-lcmtypes.pc; do
  grep -q "^./usr/lib/.*/$f\$" <<<"$contents" || { echo "package.sh: $deb lacks the consumer library's $f" >&2; exit 1; }
done
grep -q '^./usr/share/roadscan/python/roadscan_lcmtypes-.*-py3-none-any.whl$' <<<"$contents" ||
  { echo "package.sh: $deb lacks the Python wheel" >&2; exit 1; }
if [ -e /usr/share/java/lcm.jar ] && command -v javac >/dev/null; then
  grep -qx ./usr/share/java/roadscan-lcmtypes.jar <<<"$contents" || { echo "package.sh: $deb lacks the Java types" >&2; exit 1; }
fi
dpkg-deb --ctrl-tarfile "$deb" | tar -xO ./triggers 2>/dev/null | grep -q ldconfig ||
  { echo "package.sh: no ldconfig trigger for the shared library" >&2; exit 1; }
# Debian's requirements: copyright, changelog, licence, a maintainer written Name <address>
for f in ./usr/share/doc/roadscan/copyright ./usr/share/doc/roadscan/changelog.Debian.gz ./usr/share/doc/roadscan/LICENSE; do
  grep -qx "$f" <<<"$contents" || { echo "package.sh: $deb lacks $f" >&2; exit 1; }
done
zcat "$tmp/usr/share/doc/roadscan/changelog.Debian.gz" | head -1 | grep -q '^roadscan (' ||
  { echo "package.sh: changelog.Debian.gz is not a Debian changelog" >&2; exit 1; }
maint=$(dpkg-deb -f "$deb" Maintainer)
grep -Eq '^[^<>]+ <[^@<> ]+@[^<> ]+>$' <<<"$maint" || { echo "package.sh: Maintainer '$maint' is not 'Name <address>'" >&2; exit 1; }
grep -q 'invalid\.example' <<<"$maint" && { echo "package.sh: Maintainer '$maint' is the old placeholder" >&2; exit 1; }
# maintainer scripts: present, executable, valid shell; then run as dpkg runs them, on the
# extracted tree (DPKG_ROOT): installed = enabled, removed = masked, purged = forgotten
ctrl=$(mktemp -d)
dpkg-deb -e "$deb" "$ctrl"
for m in postinst prerm postrm; do
  [ -x "$ctrl/$m" ] || { echo "package.sh: no executable $m in the package" >&2; exit 1; }
  sh -n "$ctrl/$m" || { echo "package.sh: $m is not valid sh" >&2; exit 1; }
done
if command -v deb-systemd-helper >/dev/null; then
  wants="$tmp/etc/systemd/system/multi-user.target.wants/roadscand.service"
  mkdir -p "$tmp/lib/systemd/system" && cp "$tmp/usr/lib/systemd/system/roadscand.service" "$tmp/lib/systemd/system/"
  DPKG_ROOT=$tmp DPKG_MAINTSCRIPT_PACKAGE=roadscan DPKG_MAINTSCRIPT_NAME=postinst sh "$ctrl/postinst" configure
  [ -L "$wants" ] || { echo "package.sh: postinst configure did not enable roadscand.service" >&2; exit 1; }
  DPKG_ROOT=$tmp DPKG_MAINTSCRIPT_PACKAGE=roadscan DPKG_MAINTSCRIPT_NAME=prerm sh "$ctrl/prerm" remove
  DPKG_ROOT=$tmp DPKG_MAINTSCRIPT_PACKAGE=roadscan DPKG_MAINTSCRIPT_NAME=postrm sh "$ctrl/postrm" remove
  [ "$(readlink "$tmp/etc/systemd/system/roadscand.service")" = /dev/null ] ||
    { echo "package.sh: postrm remove did not mask roadscand.service" >&2; exit 1; }
  DPKG_ROOT=$tmp DPKG_MAINTSCRIPT_PACKAGE=roadscan DPKG_MAINTSCRIPT_NAME=postrm sh "$ctrl/postrm" purge
  { [ ! -e "$wants" ] && [ ! -L "$tmp/etc/systemd/system/roadscand.service" ]; } ||
    { echo "package.sh: postrm purge left roadscand.service enabled or masked" >&2; exit 1; }
  # a reinstallation after the purge enables it again
  DPKG_ROOT=$tmp DPKG_MAINTSCRIPT_PACKAGE=roadscan DPKG_MAINTSCRIPT_NAME=postinst sh "$ctrl/postinst" configure
  [ -L "$wants" ] || { echo "package.sh: postinst after a purge did not enable roadscand.service" >&2; exit 1; }
fi
rm -rf "$tmp" "$ctrl"
echo "$deb"
