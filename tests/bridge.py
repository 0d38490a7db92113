#!/usr/bin/env python3
"""bridge.py - roadscan-bridge against a real MQTT broker.

A mosquitto broker on the loopback (a free port, persistence in a scratch
folder), a real subscriber (mosquitto_sub, QoS 1, a persistent session),
roadscand's messages of a 6 s capture in an LCM log, and the bridge replaying
it:
  1. every frame's object list, track list and statistics arrive, and counts;
     every payload is valid against docs/bridge-schema.json (PyPI jsonschema)
     and on the topic of its kind;
  2. the broker stopped and restarted while the bridge runs (at the sensor's
     pace): nothing is lost, every frame arrives;
  3. the same with a buffer of 5 messages: what the bridge says it dropped is
     what the subscriber misses.

    bridge.py BIN_DIR SOURCE_DIR TMP_DIR
Exit 77 (skipped) without mosquitto, mosquitto_sub or jsonschema.
"""
import json
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import time

from testutil import fail, free_port, named, wait_for, skip

named("bridge")

try:
    import jsonschema
except ImportError:
    jsonschema = None

KINDS = ("objects", "tracks", "track_ends", "counts", "stats", "crossings")


class Broker:
    def __init__(self, tmp, port):
        self.conf, self.port, self.p = f"{tmp}/mosquitto.conf", port, None
        os.makedirs(f"{tmp}/mqdb", exist_ok=True)
        with open(self.conf, "w") as f:
            f.write(f"listener {port} 127.0.0.1\nallow_anonymous true\npersistence true\n"
                    f"persistence_location {tmp}/mqdb/\nmax_queued_messages 100000\n")
        self.log = f"{tmp}/mosquitto.log"

    def start(self):
        self.p = subprocess.Popen(["mosquitto", "-c", self.conf], stdout=open(self.log, "a"), stderr=subprocess.STDOUT)

        def up():
            try:
                socket.create_connection(("127.0.0.1", self.port), timeout=1).close()
                return True
            except OSError:
                return False
        wait_for(up, 30, "the broker to listen")

    def stop(self):
        self.p.send_signal(signal.SIGTERM)  # it saves its persistent sessions
        self.p.wait(30)


class Subscriber:
    """mosquitto_sub, QoS 1, a persistent session (-c): what it prints, line by line."""

    def __init__(self, tmp, port, name):
        self.out = f"{tmp}/{name}.txt"
        self.p = subprocess.Popen(["mosquitto_sub", "-h", "127.0.0.1", "-p", str(port), "-t", "roadscan/#", "-v",
                                   "-q", "1", "-c", "-i", f"bridge-test-{name}"], stdout=open(self.out, "w"),
                                  stderr=subprocess.STDOUT)

    def ready(self, port):
        """until a probe published on the loopback comes back: it has subscribed"""
        probe = f"roadscan/probe/{os.path.basename(self.out)}"
        end = time.monotonic() + 30
        while time.monotonic() < end:
            subprocess.run(["mosquitto_pub", "-h", "127.0.0.1", "-p", str(port), "-t", probe, "-m", "probe", "-q", "1"],
                           capture_output=True)
            if any(t == probe for t, _ in self.messages()):
                return
            time.sleep(0.1)
        fail("the subscriber did not subscribe")

    def messages(self):
        out = []
        for line in open(self.out):
            topic, _, payload = line.rstrip("\n").partition(" ")
            out.append((topic, payload))
        return out

    def stop(self):
        self.p.terminate()
        self.p.wait(30)


def bridge(bindir, log, port, speed, extra=()):
    return subprocess.Popen([f"{bindir}/roadscan-bridge", "--lcm-url", f"file://{log}?speed={speed}", "--broker",
                             f"127.0.0.1:{port}", "--site", "test-site", *extra],
                            stderr=subprocess.PIPE, text=True)


def inject_crossing(log, builddir):
    """a crossing event written into the middle of the daemon's log (the synthetic scene has no traffic
    to cross its line); 1, or 0 without PyPI's lcm"""
    try:
        import lcm
        sys.path.insert(0, f"{builddir}/python")
        from roadscan import crossing_t
    except ImportError:
        print("bridge: no PyPI lcm here: no crossing event written into the log, none checked")
        return 0
    events = [(e.timestamp, e.channel, e.data) for e in lcm.EventLog(log, "r")]
    x = crossing_t()
    x.utime, x.sensor_id, x.line, x.t_cross = events[0][0], "roadscan", "l", 1700000000500000
    x.direction, x.at, x.class_id, x.track_id, x.speed, x.how = 1, 12.5, 3, 7, 8.5, 0
    out = lcm.EventLog(log + ".tmp", "w", overwrite=True)
    for i, (ts, ch, data) in enumerate(events):
        out.write_event(ts, ch, data)
        if i == len(events) // 2:
            out.write_event(ts, "ROADSCAN_CROSSINGS", x.encode())
    out.close()
    os.replace(log + ".tmp", log)
    return 1


def distinct(msgs, kind):
    """(frame or time key) of each distinct message of a kind (QoS 1: duplicates may come)"""
    keys = set()
    for topic, payload in msgs:
        if topic.endswith("/" + kind):
            m = json.loads(payload)
            # per frame; else when it was published and what it is about (one frame's track ends and
            # crossings share a publication time)
            keys.add(m.get("frame_seq", (m["published_us"], m.get("id"), m.get("track_id"), m.get("line"))))
    return keys


def main():
    if len(sys.argv) != 4:
        print(__doc__)
        return 2
    bindir, srcdir, tmp = sys.argv[1], sys.argv[2], os.path.join(sys.argv[3], "bridge")
    for tool in ("mosquitto", "mosquitto_sub"):
        if shutil.which(tool) is None and not os.path.exists(f"/usr/sbin/{tool}"):
            skip(f"{tool} is not installed (Debian: mosquitto, mosquitto-clients)")
    if shutil.which("mosquitto") is None:
        os.environ["PATH"] += ":/usr/sbin"
    if jsonschema is None:
        skip(f"{sys.executable} has no jsonschema (PyPI; scripts/test.sh installs it)")
    schema = json.load(open(f"{srcdir}/docs/bridge-schema.json"))
    jsonschema.Draft202012Validator.check_schema(schema)
    shutil.rmtree(tmp, ignore_errors=True)
    os.makedirs(tmp)
    # the daemon's messages of 6 s of a VLP-16 (60 frames), with tracking and a counting line
    cap, log = f"{tmp}/cap.pcap", f"{tmp}/run.lcmlog"
    subprocess.run([f"{bindir}/roadscan-synth", "-o", cap, "--model", "VLP-16", "--seconds", "6"], check=True,
                   capture_output=True)
    subprocess.run([f"{bindir}/roadscan-learn", cap, "-o", f"{tmp}/cap.model"], check=True, capture_output=True)
    env = dict(os.environ, ROADSCAN_ALLOW_ROOT="1")
    # paced (the log's times are the frames' pace: the replays below last the capture's 6 s, so the
    # outage falls inside them whatever the machine's speed)
    d = subprocess.run([f"{bindir}/roadscand", "--pcap", cap, "--speed", "1", "--background", f"{tmp}/cap.model",
                        "--count-line", "l 0 -30 0 30", "--count-zone", "box -20 -20 20 -20 20 20 -20 20",
                        "--count-interval", "1", "--lcm-url",
                        f"file://{log}?mode=w"], env=env, capture_output=True, text=True)
    if d.returncode != 0:
        fail(f"roadscand: {d.stderr}")
    injected = inject_crossing(log, os.path.dirname(bindir))
    # the frames whose lists the daemon published (a paced run may drop one on a loaded machine)
    lst = subprocess.run([f"{bindir}/roadscan-listen", "--log", log, "--json"], capture_output=True, text=True)
    all_frames = {json.loads(l)["frame_seq"] for l in lst.stdout.splitlines() if '"roadscan.objects/1"' in l}
    frames = len(all_frames)
    if frames < 50:
        fail(f"the daemon published {frames} lists: {d.stderr}")
    port = free_port()
    broker = Broker(tmp, port)
    broker.start()
    try:
        # 1. everything, valid
        sub = Subscriber(tmp, port, "sub1")
        sub.ready(port)
        b = bridge(bindir, log, port, 0)
        _, err = b.communicate(timeout=120)
        if b.returncode != 0:
            fail(f"the bridge ended with {b.returncode}: {err}")
        wait_for(lambda: distinct(sub.messages(), "stats") == all_frames, 60, "every frame's statistics")
        msgs = sub.messages()
        sub.stop()
        for kind in ("objects", "tracks", "stats"):
            if distinct(msgs, kind) != all_frames:
                fail(f"{kind}: frames {sorted(all_frames - distinct(msgs, kind))} missing")
        if not distinct(msgs, "counts"):
            fail("no counts")
        # one crossing message per crossing counted (the counts' sums, once per interval)
        counted, seen_iv = 0, set()
        for topic, payload in msgs:
            if topic.endswith("/counts"):
                m = json.loads(payload)
                if m["t_start_us"] in seen_iv:
                    continue
                seen_iv.add(m["t_start_us"])
                counted += sum(sum(ln[w].values()) for ln in m["lines"] for w in ("forward", "backward"))
        if len(distinct(msgs, "crossings")) != counted + injected:
            fail(f"{len(distinct(msgs, 'crossings'))} crossing messages for {counted} crossings counted and "
                 f"{injected} written into the log")
        n = 0
        for topic, payload in msgs:
            kind = topic.rsplit("/", 1)[1]
            if topic.startswith("roadscan/probe/"):
                continue
            if topic == "roadscan/test-site/bridge/status":
                if payload not in ("online", "offline"):
                    fail(f"status {payload!r}")
                continue
            if not topic.startswith("roadscan/test-site/roadscan/") or kind not in KINDS:
                fail(f"topic {topic}")
            m = json.loads(payload)
            if m["schema"] != f"roadscan.{kind}/1":
                fail(f"{topic} carries {m['schema']}")
            try:
                jsonschema.validate(m, {"$ref": f"#/$defs/{kind}", **schema})
            except jsonschema.ValidationError as e:
                fail(f"{topic}: {e.message} at {list(e.absolute_path)}")
            n += 1
        print(f"bridge: 1. {n} messages of {frames} frames received ({len(distinct(msgs, 'crossings'))} crossings), "
              "every one valid against the schema")

        # 2. the broker restarted while the bridge runs at the sensor's pace: nothing lost
        sub = Subscriber(tmp, port, "sub2")
        sub.ready(port)
        b = bridge(bindir, log, port, 1)
        wait_for(lambda: len(distinct(sub.messages(), "objects")) >= 10, 60, "the first lists")
        broker.stop()
        time.sleep(2)  # an outage of 2 s at least: 20 frames' messages wait in the bridge
        broker.start()
        _, err = b.communicate(timeout=120)
        if b.returncode != 0:
            fail(f"the bridge ended with {b.returncode}: {err}")
        if "the broker went away" not in err or "dropped 0 " not in err:
            fail(f"the bridge did not see the outage or dropped: {err}")
        wait_for(lambda: distinct(sub.messages(), "stats") == all_frames, 60,
                 f"every frame after the broker's restart (bridge: {err.strip().splitlines()[-1]})")
        msgs = sub.messages()
        sub.stop()
        for kind in ("objects", "tracks", "stats"):
            if distinct(msgs, kind) != all_frames:
                fail(f"after the restart, {kind}: frames {sorted(all_frames - distinct(msgs, kind))} missing")
        resent = re.search(r"(\d+) in flight at", err).group(1)
        print(f"bridge: 2. the broker restarted mid-stream: all {frames} frames arrived ({resent} messages in flight "
              "at the break, sent again)")

        # 3. a buffer of 5 messages through the same outage: what it dropped is what is missing
        sub = Subscriber(tmp, port, "sub3")
        sub.ready(port)
        b = bridge(bindir, log, port, 1, ("--buffer", "5"))
        wait_for(lambda: len(distinct(sub.messages(), "objects")) >= 10, 60, "the first lists")
        broker.stop()
        time.sleep(2)
        broker.start()
        _, err = b.communicate(timeout=120)
        if b.returncode != 0:
            fail(f"the bridge ended with {b.returncode}: {err}")
        dropped = int(re.search(r"dropped (\d+) \(buffer full\)", err).group(1))
        received = re.search(r"received (\d+) object lists, (\d+) track lists, (\d+) track ends, (\d+) counts, "
                             r"(\d+) statistics, (\d+) crossings", err)
        sent_total = sum(int(x) for x in received.groups())
        wait_for(lambda: sum(len(distinct(sub.messages(), k)) for k in KINDS) >= sent_total - dropped, 60,
                 "the messages that fitted the buffer")
        got = sum(len(distinct(sub.messages(), k)) for k in KINDS)
        sub.stop()
        if dropped <= 0:
            fail(f"a buffer of 5 through a 2 s outage dropped nothing: {err}")
        if got != sent_total - dropped:
            fail(f"{got} distinct messages arrived, {sent_total} were received and {dropped} dropped")
        print(f"bridge: 3. with a buffer of 5: {dropped} dropped and counted, the other {got} arrived")
    finally:
        try:
            broker.stop()
        except Exception:
            pass
    return 0


if __name__ == "__main__":
    sys.exit(main())
