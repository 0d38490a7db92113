#!/usr/bin/env python3
"""exporter.py - roadscan-exporter scraped with a real HTTP client.

roadscand replays a capture with some corrupt packets and writes its LCM
messages to a log; roadscan-exporter reads the log and serves /metrics; curl
fetches it. The page must parse as the Prometheus text format (the
prometheus_client parser, PyPI) and carry the daemon's own figures: frames
processed (its summary), input errors by kind (the packets corrupted here), a
summary of stage times over every frame. Then the server under bad clients:
unknown paths (404), other methods (405), a malformed request line, an
oversized header, 40 clients at once, and clients that connect and never send
or never read: the others are still served.

    exporter.py BIN_DIR TMP_DIR
Exit 77 (skipped) without curl or prometheus_client.
"""
import os
import re
import shutil
import socket
import subprocess
import sys
import threading
import time

from testutil import fail, free_port, named, raw, skip

named("exporter")

try:
    from prometheus_client.parser import text_string_to_metric_families
except ImportError:
    text_string_to_metric_families = None


def curl(url, *extra):
    st = subprocess.run(["curl", "-s", "-S", "--max-time", "30", "-w", "\n%{http_code}", *extra, url],
                        capture_output=True, text=True)
    if st.returncode != 0:
        fail(f"curl {url}: {st.stderr}")
    body, _, code = st.stdout.rpartition("\n")
    return int(code), body


def main():
    if len(sys.argv) != 3:
        print(__doc__)
        return 2
    bindir, tmp = sys.argv[1], os.path.join(sys.argv[2], "exporter")
    if shutil.which("curl") is None:
        skip("curl is not installed")
    if text_string_to_metric_families is None:
        skip(f"{sys.executable} has no prometheus_client (PyPI; scripts/test.sh installs it)")
    shutil.rmtree(tmp, ignore_errors=True)
    os.makedirs(tmp)
    cap, log = f"{tmp}/cap.pcap", f"{tmp}/run.lcmlog"
    subprocess.run([f"{bindir}/roadscan-synth", "-o", cap, "--model", "VLP-16", "--seconds", "2"], check=True,
                   capture_output=True)
    # 25 data packets with a block flag broken (records of 16 + 42 + 1206 bytes after the 24-byte header)
    b = bytearray(open(cap, "rb").read())
    at, data, broken = 24, 0, 0
    while at + 16 <= len(b):
        n = int.from_bytes(b[at + 8:at + 12], "little")
        if n == 42 + 1206:
            data += 1
            if data % 30 == 5 and broken < 25:
                b[at + 16 + 42] = 0x00  # block 0's 0xFF of 0xFFEE
                broken += 1
        at += 16 + n
    open(cap, "wb").write(b)
    env = dict(os.environ, ROADSCAN_ALLOW_ROOT="1")
    d = subprocess.run([f"{bindir}/roadscand", "--pcap", cap, "--fast", "--sensor-id", 'north"1"\\a',
                        "--lcm-url", f"file://{log}?mode=w"], env=env, capture_output=True, text=True)
    if d.returncode != 0:
        fail(f"roadscand: {d.stderr}")
    frames = int(re.search(r"frames: (\d+) processed", d.stderr).group(1))
    port = free_port()
    ex = subprocess.Popen([f"{bindir}/roadscan-exporter", "--lcm-url", f"file://{log}?speed=0", "--listen",
                           f"127.0.0.1:{port}"], stderr=subprocess.PIPE, text=True)
    try:
        page = None
        for _ in range(300):  # until the whole log is read (30 s at most)
            time.sleep(0.1)
            try:
                code, body = curl(f"http://127.0.0.1:{port}/metrics")
            except SystemExit:
                continue
            if code == 200 and f"roadscan_frames_processed_total{{sensor_id=\"north\\\"1\\\"\\\\a\"}} {frames}" in body:
                page = body
                break
        if page is None:
            fail(f"/metrics never showed {frames} frames processed")
        fams = {f.name: f for f in text_string_to_metric_families(page)}
        for name, typ in (("roadscan_frames_processed", "counter"), ("roadscan_input_errors", "counter"),
                          ("roadscan_stage_seconds", "summary"), ("roadscan_frame_points", "gauge"),
                          ("roadscan_tracks", "gauge"), ("roadscan_kernel_dropped_packets", "counter")):
            if name not in fams or fams[name].type != typ:
                fail(f"{name} ({typ}) is not in the page")
        sid = 'north"1"\\a'
        val = {(s.name, tuple(sorted(s.labels.items()))): s.value for f in fams.values() for s in f.samples}
        if val.get(("roadscan_frames_processed_total", (("sensor_id", sid),))) != frames:
            fail("frames processed: not the daemon's")
        errs = val.get(("roadscan_input_errors_total", (("kind", "block-flag"), ("sensor_id", sid))))
        if errs != broken:
            fail(f"block-flag errors: {errs}, {broken} packets were broken")
        cnt = val.get(("roadscan_stage_seconds_count", (("sensor_id", sid), ("stage", "processing"))))
        if cnt != frames:
            fail(f"processing time counted {cnt} times for {frames} frames")
        q99 = val.get(("roadscan_stage_seconds", (("quantile", "0.99"), ("sensor_id", sid), ("stage", "processing"))))
        q50 = val.get(("roadscan_stage_seconds", (("quantile", "0.5"), ("sensor_id", sid), ("stage", "processing"))))
        if q50 is None or q99 is None or not 0 < q50 <= q99:
            fail(f"processing quantiles {q50} {q99}")
        # bad clients
        if curl(f"http://127.0.0.1:{port}/nothing")[0] != 404:
            fail("an unknown path is not 404")
        if curl(f"http://127.0.0.1:{port}/metrics", "-X", "POST", "-d", "x=1")[0] != 405:
            fail("POST is not 405")
        for bad in (b"GARBAGE / HTTP/9.9\r\n\r\n", b"GET\r\n\r\n", b"\x00\x01\xff garbage\r\n\r\n"):
            r = raw(port, bad)
            if not (r == b"" or r.startswith(b"HTTP/1.1 4") or r.startswith(b"HTTP/1.1 505")):
                fail(f"the malformed request {bad!r} got {r[:40]!r}")
        r = raw(port, b"GET /metrics HTTP/1.1\r\nHost: x\r\nX-Big: " + b"a" * 200000 + b"\r\n\r\n")
        if r.startswith(b"HTTP/1.1 200"):
            fail("a 200 kB header was served")
        idle = [socket.create_connection(("127.0.0.1", port)) for _ in range(5)]  # connect, never send
        slow = socket.create_connection(("127.0.0.1", port))  # asks, never reads
        slow.sendall(b"GET /metrics HTTP/1.1\r\nHost: x\r\n\r\n" * 50)
        codes = []

        def one():
            codes.append(curl(f"http://127.0.0.1:{port}/metrics")[0])
        ts = [threading.Thread(target=one) for _ in range(40)]
        for t in ts:
            t.start()
        for t in ts:
            t.join()
        if codes.count(200) != 40:
            fail(f"40 clients at once beside idle and slow ones: {codes}")
        for s in idle + [slow]:
            s.close()
        if curl(f"http://127.0.0.1:{port}/metrics")[0] != 200:
            fail("not served after the bad clients")
    finally:
        ex.send_signal(2)
        try:
            ex.wait(30)
        except subprocess.TimeoutExpired:
            ex.kill()
            fail("the exporter did not stop on SIGINT")
    if ex.returncode != 0:
        fail(f"the exporter ended with {ex.returncode}: {ex.stderr.read()}")
    print(f"exporter: {frames} frames, {broken} block-flag errors and the stage times served and parsed; "
          "bad clients refused, 40 at once served")
    return 0


if __name__ == "__main__":
    sys.exit(main())
