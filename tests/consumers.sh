#!/bin/sh
# consumers.sh - the consumer libraries as a user gets them: the build installed
# into a scratch prefix (cmake --install), a C subscriber (examples/subscriber.c)
# compiled with nothing but pkg-config against it, linked shared and static,
# and the Python types pip-installed from the installed wheel, each reading
# the object lists roadscand wrote to an LCM log. Run by CTest:
#   consumers.sh SOURCE_DIR BUILD_DIR TMP_DIR
# Exit 77 (skipped) without a C compiler or pkg-config.
set -u
src=$1 build=$2 t=$3/consumers
fail() { echo "consumers: FAIL: $*"; exit 1; }
command -v cc >/dev/null && command -v pkg-config >/dev/null || { echo "consumers: no cc or pkg-config; skipped"; exit 77; }
rm -rf "$t" && mkdir -p "$t"
cmake --install "$build" --prefix "$t/prefix" >"$t/install.txt" 2>&1 || fail "cmake --install: $(tail -3 "$t/install.txt")"
pc=$(dirname "$(find "$t/prefix" -name roadscan-lcmtypes.pc | head -1)")
[ -n "$pc" ] || fail "no roadscan-lcmtypes.pc installed"
export PKG_CONFIG_PATH=$pc
libdir=$(pkg-config --variable=libdir roadscan-lcmtypes)
[ -e "$libdir/libroadscan-lcmtypes.so.0" ] && [ -e "$libdir/libroadscan-lcmtypes.a" ] ||
  fail "pkg-config's libdir $libdir lacks the shared or static library"
# the daemon's object lists, into a log
"$build/bin/roadscan-synth" -o "$t/cap.pcap" --model VLP-16 --seconds 2 >/dev/null 2>&1 || fail "roadscan-synth"
"$build/bin/roadscan-learn" "$t/cap.pcap" -o "$t/cap.model" >/dev/null 2>&1 || fail "roadscan-learn"
ROADSCAN_ALLOW_ROOT=1 "$build/bin/roadscand" --pcap "$t/cap.pcap" --fast --background "$t/cap.model" \
  --lcm-url "file://$t/run.lcmlog?mode=w" >"$t/daemon.txt" 2>&1 || fail "roadscand: $(tail -3 "$t/daemon.txt")"
lists=$(sed -n 's/^  lcm: \([0-9]*\) object lists.*/\1/p' "$t/daemon.txt")
[ -n "$lists" ] && [ "$lists" -gt 0 ] || fail "the daemon published no list: $(cat "$t/daemon.txt")"
# C, shared: only what pkg-config says
cc -Wall -Wextra -Werror "$src/examples/subscriber.c" $(pkg-config --cflags --libs roadscan-lcmtypes) -o "$t/sub-shared" \
  2>"$t/cc.txt" || fail "the C subscriber does not build against the package: $(cat "$t/cc.txt")"
ldd "$t/sub-shared" | grep -q "libroadscan-lcmtypes.so.0 => $libdir" || LD_LIBRARY_PATH=$libdir ldd "$t/sub-shared" |
  grep -q "libroadscan-lcmtypes.so.0 => $libdir" || fail "the shared subscriber does not use the installed library"
LD_LIBRARY_PATH=$libdir "$t/sub-shared" "file://$t/run.lcmlog?speed=0" >"$t/shared.out" 2>"$t/shared.err" ||
  fail "the shared subscriber: $(cat "$t/shared.err")"
grep -q "^subscriber: lists $lists, .*refused 0$" "$t/shared.err" || fail "shared: $(cat "$t/shared.err"), the daemon sent $lists"
# C, static: the archive, then what lcm needs
cc -Wall -Wextra -Werror "$src/examples/subscriber.c" $(pkg-config --cflags roadscan-lcmtypes) "$libdir/libroadscan-lcmtypes.a" \
  $(pkg-config --libs lcm) -o "$t/sub-static" 2>"$t/cc.txt" || fail "the static subscriber does not build: $(cat "$t/cc.txt")"
ldd "$t/sub-static" | grep -q roadscan-lcmtypes && fail "the static subscriber needs the shared library"
"$t/sub-static" "file://$t/run.lcmlog?speed=0" >"$t/static.out" 2>"$t/static.err" || fail "the static subscriber: $(cat "$t/static.err")"
cmp -s "$t/shared.out" "$t/static.out" || fail "the static and shared subscribers printed different lists"
# Python: the wheel the package installs, pip-installed
py=${RS_PYTHON:-python3}
if "$py" -c 'import lcm' 2>/dev/null; then
  whl=$(find "$t/prefix" -name 'roadscan_lcmtypes-*.whl' | head -1)
  [ -n "$whl" ] || fail "no wheel installed"
  "$py" -m pip install -q --disable-pip-version-check --no-deps --target "$t/pysite" "$whl" >"$t/pip.txt" 2>&1 ||
    fail "pip install $whl: $(cat "$t/pip.txt")"
  PYTHONPATH=$t/pysite "$py" -c 'import roadscan, os, sys; sys.exit(0 if os.path.dirname(roadscan.__file__).startswith(sys.argv[1]) else 1)' \
    "$t/pysite" || fail "Python imports roadscan from elsewhere than the pip-installed copy"
  # and the same wheel from the build tree
  "$py" -m pip install -q --disable-pip-version-check --no-deps --target "$t/pysite-build" "$build"/python/dist/roadscan_lcmtypes-*.whl \
    >"$t/pip2.txt" 2>&1 || fail "pip install from the build tree: $(cat "$t/pip2.txt")"
  PYTHONPATH=$t/pysite-build "$py" -c 'from roadscan import object_list_t, frame_stats_t, track_list_t' ||
    fail "the build tree's wheel does not import"
  PYTHONPATH=$t/pysite "$py" "$src/examples/listen.py" --url "file://$t/run.lcmlog?speed=0" --count "$lists" \
    >"$t/py.out" 2>"$t/py.err" || fail "examples/listen.py on the pip-installed types: $(cat "$t/py.err")"
  n=$(grep -c . "$t/py.out")
  [ "$n" -ge "$lists" ] || fail "examples/listen.py printed $n lines for $lists lists"
else
  echo "consumers: $py cannot import lcm (PyPI): the Python part is skipped"
fi
echo "consumers: $lists lists read by the C subscriber (shared and static) and the Python example, from the installed package"
