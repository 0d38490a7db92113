#!/usr/bin/env python3
"""web.py - roadscan-web in a real browser, and under bad HTTP clients.

The daemon replays a simulated rush of a VLP-32C site (paced, with counting
lines and a zone) into an LCM log; roadscan-web serves it (--log, at its own
pace); Debian's chromium, headless, driven by selenium (PyPI) with
chromium-driver, opens the page:
  - it loads with no console error and goes live;
  - the confirmed tracks it draws within 60 m at a frame are the true objects
    the sensor saw in that frame within 60 m (the truth labels), within a
    tolerance;
  - the running counts advance;
  - the last crossings it lists are the daemon's own (--crossings-out of the
    same run: the same track, line, way, place, class, speed and how), newest
    first, and those of the last seconds are marked on their lines;
  - a screenshot is written (out/web/screenshot.png in the source tree: CI
    keeps it).
Then the server under bad clients: unknown paths, other methods, malformed
request lines, an oversized header, 40 event streams at once, a client that
opens the stream and never reads: the others are still served, and memory
stays bounded.

    web.py BIN_DIR SOURCE_DIR TMP_DIR
Exit 77 (skipped) without chromium, chromedriver or selenium.
"""
import csv
import json
import math
import os
import re
import shutil
import socket
import subprocess
import sys
import threading
import time

from testutil import fail, free_port, named, raw, skip

named("web")

try:
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service
    from selenium.webdriver.support.ui import WebDriverWait
except ImportError:
    webdriver = None


def rss_kib(pid):
    for line in open(f"/proc/{pid}/status"):
        if line.startswith("VmRSS:"):
            return int(line.split()[1])
    return 0


LINES = ["east 41.5 4.5 41.5 18.5", "west -18.5 4.5 -18.5 18.5", "north 4.5 41.5 18.5 41.5", "south 4.5 -18.5 18.5 -18.5"]
ZONE = "centre 4.5 4.5 18.5 4.5 18.5 18.5 4.5 18.5"


def main():
    if len(sys.argv) != 4:
        print(__doc__)
        return 2
    bindir, srcdir, tmp = sys.argv[1], sys.argv[2], os.path.join(sys.argv[3], "web")
    chromium = shutil.which("chromium") or shutil.which("chromium-browser")
    driver_bin = shutil.which("chromedriver")
    if webdriver is None:
        skip(f"{sys.executable} has no selenium (PyPI; scripts/test.sh installs it)")
    if chromium is None or driver_bin is None:
        skip("no chromium or chromedriver (Debian: chromium, chromium-driver)")
    shutil.rmtree(tmp, ignore_errors=True)
    os.makedirs(tmp)
    cap, truth, model, log = f"{tmp}/site.pcap", f"{tmp}/truth.csv", f"{tmp}/site.bg", f"{tmp}/run.lcmlog"
    subprocess.run([f"{bindir}/roadscan-sim", "--sensor", "VLP-32C", "--scenario", "rush", "--seconds", "40", "--seed",
                    "23", "-o", cap, "--labels", truth], check=True, capture_output=True)
    subprocess.run([f"{bindir}/roadscan-learn", cap, "-o", model], check=True, capture_output=True)
    lines = sum((["--count-line", l] for l in LINES), [])
    env = dict(os.environ, ROADSCAN_ALLOW_ROOT="1")
    # paced (2x: 20 s of log): the log's times are the frames' pace, so the page's replay shows them as they came
    d = subprocess.run([f"{bindir}/roadscand", "--pcap", cap, "--speed", "2", "--background", model, *lines,
                        "--count-zone", ZONE, "--count-interval", "2", "--crossings-out", f"{tmp}/crossings.csv",
                        "--lcm-url", f"file://{log}?mode=w"], env=env,
                       capture_output=True, text=True)
    if d.returncode != 0:
        fail(f"roadscand: {d.stderr}")
    # the true objects of every frame (centroids of the truth's instances)
    subprocess.run([f"{bindir}/roadscan-eval", cap, truth, truth, "--objects", f"{tmp}/objects.csv"], check=True,
                   capture_output=True)
    objects = {}
    for r in csv.DictReader(open(f"{tmp}/objects.csv")):
        if int(r["points"]) >= 10 and math.hypot(float(r["x"]), float(r["y"])) <= 60:
            objects[int(r["frame"])] = objects.get(int(r["frame"]), 0) + 1
    port = free_port()
    opts = webdriver.ChromeOptions()
    opts.binary_location = chromium
    for a in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage", "--disable-quic",
              "--no-first-run", "--disable-background-networking", "--disable-component-update", "--disable-sync",
              f"--user-data-dir={tmp}/chrome", "--window-size=1400,900"):
        opts.add_argument(a)
    opts.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    # the browser first: the log's replay (20 s) starts with roadscan-web, and a browser starting on a
    # loaded machine must not take the part of it in which the counts are seen to advance
    drv = webdriver.Chrome(service=Service(driver_bin), options=opts)
    web = subprocess.Popen([f"{bindir}/roadscan-web", "--log", log, "--listen", f"127.0.0.1:{port}", *lines,
                            "--count-zone", ZONE], stderr=open(f"{tmp}/web.txt", "w"))
    try:
        for _ in range(100):  # the server listens
            try:
                socket.create_connection(("127.0.0.1", port), timeout=1).close()
                break
            except OSError:
                time.sleep(0.1)
        try:
            drv.get(f"http://127.0.0.1:{port}/")
            wait = WebDriverWait(drv, 90, poll_frequency=0.2)
            wait.until(lambda d: d.find_element("id", "conn").text == "live")
            wait.until(lambda d: int(d.find_element("id", "tracks-count").text) > 0)
            # the confirmed tracks it draws at a frame against the true objects the sensor saw in that
            # frame (roadscan-eval --objects: instances of the truth labels, 10 returns or more) within 60 m
            checks = []
            for _ in range(5):
                frame, tracks = drv.execute_script(
                    "return [Number(document.getElementById('frame-time').dataset.frame), state.tracks];")
                shown = sum(1 for k in tracks if k["state"] == "confirmed" and math.hypot(*k["position_m"][:2]) <= 60)
                true = objects.get(frame, 0)
                checks.append((frame, shown, true))
                time.sleep(0.7)
            for frame, shown, true in checks:
                if abs(shown - true) > max(4, 0.25 * true):
                    fail(f"frame {frame}: the page shows {shown} confirmed tracks within 60 m where the sensor saw "
                         f"{true} objects (all checks: {checks})")
            # the counts advance
            first = int(drv.find_element("id", "counts-total").text)
            wait.until(lambda d: int(d.find_element("id", "counts-total").text) > first)
            later = int(drv.find_element("id", "counts-total").text)
            # the last crossings: the daemon's own events (its --crossings-out of the same run), newest first
            daemon, order = {}, []
            for r in csv.DictReader(open(f"{tmp}/crossings.csv")):
                daemon[(int(r["track"]), r["line"], r["direction"])] = r
                order.append((int(r["track"]), r["line"], r["direction"]))
            if not daemon:
                fail("the daemon counted no crossing in the run: nothing to show")
            wait.until(lambda d: int(d.find_element("id", "crossings-seen").text) >= 2)
            shown = drv.execute_script("return state.crossings;")
            rows = drv.find_elements("css selector", "#crossings tr")
            if len(rows) != len(shown) + 1:
                fail(f"{len(shown)} crossings kept but {len(rows) - 1} rows listed")
            for c in shown:
                r = daemon.get((c["track_id"], c["line"], c["direction"]))
                if r is None:
                    fail(f"the page lists a crossing the daemon did not count: {c}")
                speed = None if r["speed"] == "" else float(r["speed"])
                if (abs(c["at_m"] - float(r["at"])) > 0.01 or c["class"] != r["class"] or c["how"] != r["how"] or
                        abs(c["t"] - float(r["t"])) > 0.002 or
                        (speed is None) != (c["speed_mps"] is None) or
                        (speed is not None and abs(c["speed_mps"] - speed) > 0.01)):
                    fail(f"the page's crossing {c} is not the daemon's {dict(r)}")
            # in the order the daemon tallied them (its file's), newest first
            keys = [(c["track_id"], c["line"], c["direction"]) for c in reversed(shown)]
            k0 = order.index(keys[0])
            if order[k0:k0 + len(keys)] != keys:
                fail(f"the crossings listed {keys} are not the daemon's in its order {order[k0:k0 + len(keys)]}")
            # health panel filled
            fps = drv.find_element("id", "fps").text
            if not re.match(r"^[0-9.]+ frames/s$", fps):
                fail(f"frame rate shown as {fps!r}")
            if not drv.find_elements("css selector", "#stages tbody tr"):
                fail("no stage times shown")
            os.makedirs(f"{srcdir}/out/web", exist_ok=True)
            shot = f"{srcdir}/out/web/screenshot.png"
            drv.save_screenshot(shot)
            if os.path.getsize(shot) < 10000:
                fail("the screenshot is nearly empty")
            severe = [e for e in drv.get_log("browser") if e["level"] == "SEVERE"]
            if severe:
                fail(f"console errors: {severe}")
            print(f"web: page live; (frame, confirmed tracks drawn, true objects seen) within 60 m: {checks}; counts {first} -> {later}; "
                  f"{len(shown)} last crossings listed, all the daemon's; screenshot {shot}")
        finally:
            drv.quit()

        # bad clients
        def get(path, method="GET"):
            r = raw(port, f"{method} {path} HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n".encode())
            return int(r.split(b" ", 2)[1]) if r.startswith(b"HTTP/1.1 ") else 0
        if get("/nothing") != 404 or get("/../etc/passwd") != 404 or get("/", "POST") != 405:
            fail("unknown paths or methods are not refused")
        for bad in (b"GARBAGE / HTTP/9.9\r\n\r\n", b"GET\r\n\r\n", b"\x00\x01\xff\r\n\r\n",
                    b"GET / HTTP/1.1\r\nHost: x\r\nX-Big: " + b"a" * 300000 + b"\r\n\r\n"):
            r = raw(port, bad)
            if r.startswith(b"HTTP/1.1 200"):
                fail(f"the bad request {bad[:30]!r} was served")
        before = rss_kib(web.pid)
        # a client that opens the stream and never reads, then 40 streams at once: each gets events
        stuck = socket.create_connection(("127.0.0.1", port))
        stuck.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
        stuck.sendall(b"GET /events HTTP/1.1\r\nHost: x\r\n\r\n")
        got = []

        def stream():
            s = socket.create_connection(("127.0.0.1", port), timeout=30)
            s.sendall(b"GET /events HTTP/1.1\r\nHost: x\r\n\r\n")
            data = b""
            while data.count(b"event: ") < 3:
                b = s.recv(65536)
                if not b:
                    break
                data += b
            s.close()
            got.append(data.count(b"event: "))
        ts = [threading.Thread(target=stream) for _ in range(20)]
        for t in ts:
            t.start()
        for t in ts:
            t.join(60)
        if len(got) != 20 or min(got) < 3:
            fail(f"20 event streams beside a stuck one: events each {got}")
        if get("/") != 200:
            fail("the page is not served beside the stuck client")
        stuck.close()
        time.sleep(1.5)  # (the stuck client's thread notices the close within its 1 s wait)
        after = rss_kib(web.pid)
        if after - before > 64 * 1024:
            fail(f"resident memory grew from {before} to {after} KiB with the clients")
        status = json.loads(raw(port, b"GET /status HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n").split(b"\r\n\r\n", 1)[1])
        print(f"web: bad requests refused, 20 streams served beside a client that never reads; memory {before} -> "
              f"{after} KiB; {status}")
    finally:
        web.send_signal(2)
        try:
            web.wait(30)
        except subprocess.TimeoutExpired:
            web.kill()
            fail("roadscan-web did not stop on SIGINT")
    if web.returncode != 0:
        fail(f"roadscan-web ended with {web.returncode}: {open(f'{tmp}/web.txt').read()}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
