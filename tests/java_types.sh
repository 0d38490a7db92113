#!/bin/sh
# java_types.sh - the Java types (roadscan-lcmtypes.jar) through lcm-spy's own
# decoding path (tests/SpyDecode.java): every message roadscand wrote to an LCM
# log is found by its fingerprint and decoded. Run by CTest:
#   java_types.sh SOURCE_DIR BUILD_DIR TMP_DIR
# Exit 77 (skipped) without a JDK, LCM's jar or the built jar.
set -u
src=$1 build=$2 t=$3/java
fail() { echo "java_types: FAIL: $*"; exit 1; }
jar=$build/roadscan-lcmtypes.jar lcmjar=/usr/share/java/lcm.jar
for x in javac java; do command -v $x >/dev/null || { echo "java_types: no $x; skipped"; exit 77; }; done
[ -e "$lcmjar" ] || { echo "java_types: no $lcmjar (Debian: liblcm-java); skipped"; exit 77; }
[ -e "$jar" ] || { echo "java_types: no $jar (built when a JDK and liblcm-java are there); skipped"; exit 77; }
rm -rf "$t" && mkdir -p "$t"
"$build/bin/roadscan-synth" -o "$t/cap.pcap" --model VLP-16 --seconds 2 >/dev/null 2>&1 || fail "roadscan-synth"
"$build/bin/roadscan-learn" "$t/cap.pcap" -o "$t/cap.model" >/dev/null 2>&1 || fail "roadscan-learn"
ROADSCAN_ALLOW_ROOT=1 "$build/bin/roadscand" --pcap "$t/cap.pcap" --fast --background "$t/cap.model" \
  --count-line "l 0 -30 0 30" --count-interval 1 --lcm-url "file://$t/run.lcmlog?mode=w" >"$t/daemon.txt" 2>&1 ||
  fail "roadscand: $(tail -3 "$t/daemon.txt")"
lists=$(sed -n 's/^  lcm: \([0-9]*\) object lists.*/\1/p' "$t/daemon.txt")
stats=$(sed -n 's/^  lcm: [0-9]* object lists on [A-Z_]*, \([0-9]*\) statistics.*/\1/p' "$t/daemon.txt")
tracks=$(sed -n 's/^  lcm: \([0-9]*\) track lists.*/\1/p' "$t/daemon.txt")
javac -d "$t" -cp "$lcmjar:$jar" "$src/tests/SpyDecode.java" 2>"$t/javac.txt" || fail "javac: $(cat "$t/javac.txt")"
cp="$lcmjar:$jar:$t"; [ -e /usr/share/java/jchart2d.jar ] && cp="$cp:/usr/share/java/jchart2d.jar"
java -cp "$cp" SpyDecode "$t/run.lcmlog" >"$t/out.txt" 2>"$t/err.txt" || fail "SpyDecode: $(cat "$t/err.txt")"
grep -qx "ROADSCAN_OBJECTS roadscan.object_list_t $lists" "$t/out.txt" || fail "object lists: $(cat "$t/out.txt"), sent $lists"
grep -qx "ROADSCAN_STATS roadscan.frame_stats_t $stats" "$t/out.txt" || fail "statistics: $(cat "$t/out.txt"), sent $stats"
grep -qx "ROADSCAN_TRACKS roadscan.track_list_t $tracks" "$t/out.txt" || fail "track lists: $(cat "$t/out.txt"), sent $tracks"
grep -q "^ROADSCAN_COUNTS roadscan.counts_t [1-9]" "$t/out.txt" || fail "counts: $(cat "$t/out.txt")"
grep -qx "unknown 0" "$t/out.txt" || fail "messages of unknown types: $(cat "$t/out.txt")"
grep -q "^sample roadscan frame [0-9]* objects [0-9]*$" "$t/out.txt" || fail "no object list decoded: $(cat "$t/out.txt")"
echo "java_types: every message decoded through the spy's type database:"
cat "$t/out.txt"
