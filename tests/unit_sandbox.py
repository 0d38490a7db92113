#!/usr/bin/env python3
"""unit_sandbox.py - the systemd unit's sandbox fits what roadscand does.

The unit (packaging/roadscand.service) restricts roadscand to a set of system
calls (SystemCallFilter) and socket families (RestrictAddressFamilies). A
call outside the set fails with EPERM under systemd: a daemon that needs one
would break on the first deployment, and nothing here runs systemd as PID 1.
So this test traces the real daemon with strace while it does what it does in
service (a replay with the background, clustering, tracking and counting;
publishing over LCM udpm:// in a private network namespace; live capture on
the loopback with packets arriving), and checks that every system call it made
is in the unit's allowed set (systemd's own definition of the groups, from
`systemd-analyze syscall-filter`) and not in a denied one, and every socket
family it opened is allowed. It also checks the exposure level that
`systemd-analyze security --offline` gives the unit.

    unit_sandbox.py BIN_DIR UNIT_FILE TMP_DIR

Runs itself again in a private network namespace (unshare). Exit 77
(skipped) without strace, systemd-analyze or a network namespace.
"""
import os
import re
import shutil
import socket
import subprocess
import sys
import time

MAX_EXPOSURE = 2.5  # systemd-analyze security: 1.7 measured, 6.0 before hardening


def skip(why):
    print(f"unit_sandbox: skipped: {why}")
    sys.exit(77)


def fail(why):
    print(f"unit_sandbox: FAIL: {why}")
    sys.exit(1)


def unit_settings(path):
    """Key -> list of values (a key may repeat) of the [Service] section."""
    out, section = {}, None
    for line in open(path):
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        if line.startswith("["):
            section = line
            continue
        if section == "[Service]" and "=" in line:
            k, v = line.split("=", 1)
            out.setdefault(k, []).append(v)
    return out


def syscall_groups():
    """@group -> set of members (names or @groups), from systemd itself."""
    text = subprocess.run(["systemd-analyze", "syscall-filter"], capture_output=True, text=True, check=True).stdout
    groups, cur = {}, None
    for line in text.splitlines():
        s = line.strip()
        if not s or s.startswith("#"):
            continue
        if not line.startswith(" ") and s.startswith("@"):
            cur = s
            groups[cur] = set()
        elif cur:
            groups[cur].add(s.split()[0])
    return groups


def expand(names, groups, seen=None):
    seen = set() if seen is None else seen
    out = set()
    for n in names:
        if n.startswith("@"):
            if n in seen:
                continue
            seen.add(n)
            if n not in groups:
                fail(f"unknown system call group {n}")
            out |= expand(groups[n], groups, seen)
        else:
            out.add(n)
    return out


def allowed_calls(settings, groups):
    allow, deny = set(), set()
    for v in settings.get("SystemCallFilter", []):
        if v.startswith("~"):
            deny |= expand(v[1:].split(), groups)
        else:
            allow |= expand(v.split(), groups)
    return allow, deny


def traced(log):
    """System calls and socket families of an strace -f log."""
    calls, fams = set(), set()
    for line in open(log):
        m = re.match(r"^\d+\s+([a-z_0-9]+)\(", line)
        if m:
            calls.add(m.group(1))
        m = re.search(r"\bsocket\((AF_[A-Z0-9]+)", line)
        if m:
            fams.add(m.group(1))
    return calls, fams


def data_payloads(path):
    """The 1206-byte UDP payloads of a classic pcap written by roadscan-synth (Ethernet)."""
    d = open(path, "rb").read()
    out, at = [], 24
    while at + 16 <= len(d):
        n = int.from_bytes(d[at + 8:at + 12], "little")
        rec = d[at + 16:at + 16 + n]
        if n == 42 + 1206:
            out.append(rec[42:])
        at += 16 + n
    return out


def wait_for(pred, timeout):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if pred():
            return True
        time.sleep(0.05)
    return False


def file_has(path, text):
    try:
        return text in open(path).read()
    except OSError:
        return False


def main():
    if len(sys.argv) != 4:
        print(__doc__)
        sys.exit(2)
    bindir, unit, tmp = sys.argv[1:]
    for tool in ("strace", "systemd-analyze", "unshare", "ip"):
        if shutil.which(tool) is None:
            skip(f"{tool} is not installed")
    if os.environ.get("RS_IN_NETNS") != "1":  # again, in a private network namespace: nothing leaves
        env = dict(os.environ, RS_IN_NETNS="1")
        for pre in (["unshare", "-n"], ["unshare", "-rn"]):
            if subprocess.run(pre + ["true"], capture_output=True).returncode == 0:
                os.execvpe(pre[0], pre + [sys.executable] + sys.argv, env)
        skip("no network namespace (unshare -n / -rn)")
    subprocess.run(["ip", "link", "set", "lo", "up"], check=True)
    subprocess.run(["ip", "route", "add", "224.0.0.0/4", "dev", "lo"], check=True)
    settings = unit_settings(unit)
    groups = syscall_groups()
    allow, deny = allowed_calls(settings, groups)
    if not allow:
        fail("the unit has no SystemCallFilter allow list")
    families = set(" ".join(settings.get("RestrictAddressFamilies", [])).split())
    if not families:
        fail("the unit has no RestrictAddressFamilies")

    # 1. exposure level
    st = subprocess.run(["systemd-analyze", "security", "--offline=true", unit], capture_output=True, text=True)
    m = re.search(r"Overall exposure level for \S+: ([0-9.]+)", st.stdout + st.stderr)
    if not m:
        fail(f"systemd-analyze security said: {st.stdout}{st.stderr}")
    level = float(m.group(1))
    print(f"unit_sandbox: systemd-analyze security: exposure {level}")
    if level > MAX_EXPOSURE:
        fail(f"exposure {level} is above {MAX_EXPOSURE}")

    env = dict(os.environ, ROADSCAN_ALLOW_ROOT="1")
    env.pop("LCM_DEFAULT_URL", None)
    tool = lambda name: os.path.join(bindir, name)
    cap, model = f"{tmp}/sandbox.pcap", f"{tmp}/sandbox.model"
    subprocess.run([tool("roadscan-sim"), "--sensor", "VLP-16", "--seconds", "8", "--seed", "5", "-o", cap,
                    "--labels", f"{tmp}/sandbox-truth.csv"],
                   check=True, capture_output=True)
    subprocess.run([tool("roadscan-learn"), cap, "-o", model], check=True, capture_output=True)
    all_calls, all_fams = set(), set()
    # 2. a replay as the service runs it: background, clustering, tracking, counting, LCM udpm://
    log = f"{tmp}/sandbox-replay.strace"
    st = subprocess.run(["strace", "-f", "-qq", "-o", log, tool("roadscand"), "--pcap", cap, "--speed", "4",
                         "--background", model, "--count-line", "l 0 -30 0 30", "--summary-seconds", "0.5"],
                        env=env, capture_output=True, text=True)
    if st.returncode != 0 or "lcm: " not in st.stderr:
        fail(f"the replay failed or published nothing ({st.returncode}): {st.stderr}")
    calls, fams = traced(log)
    all_calls |= calls
    all_fams |= fams
    # learning once: the model learned, saved atomically (fsync, rename), then loaded
    if os.path.exists(f"{tmp}/sandbox-learned.model"):
        os.remove(f"{tmp}/sandbox-learned.model")
    for k in range(2):
        log = f"{tmp}/sandbox-learn{k}.strace"
        st = subprocess.run(["strace", "-f", "-qq", "-o", log, tool("roadscand"), "--pcap", cap, "--speed", "8",
                             "--learn-seconds", "2", "--learn-out", f"{tmp}/sandbox-learned.model", "--no-publish"],
                            env=env, capture_output=True, text=True)
        if st.returncode != 0 or ("saved to" not in st.stderr and "stored model" not in st.stderr):
            fail(f"learning once failed ({st.returncode}): {st.stderr}")
        calls, fams = traced(log)
        all_calls |= calls
        all_fams |= fams
    # 3. live capture on the loopback with the sensor's packets arriving, publishing
    log, out, csv = f"{tmp}/sandbox-live.strace", f"{tmp}/sandbox-live.txt", f"{tmp}/sandbox-live.csv"
    for f in (out, csv):
        if os.path.exists(f):
            os.remove(f)
    # as a notified service with a watchdog (Type=notify): the datagrams to $NOTIFY_SOCKET
    sock_path = f"{tmp}/sandbox-notify.sock"
    if os.path.exists(sock_path):
        os.remove(sock_path)
    notify = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
    notify.bind(sock_path)
    senv = dict(env, NOTIFY_SOCKET=sock_path, WATCHDOG_USEC="1000000")
    with open(out, "w") as o:
        p = subprocess.Popen(["strace", "-f", "-qq", "-o", log, tool("roadscand"), "--iface", "lo", "--background",
                              model, "--summary-seconds", "0.2", "--frames-out", csv], env=senv, stdout=o, stderr=o)
    if not wait_for(lambda: file_has(out, "capturing on lo") or p.poll() is not None, 60):
        p.kill()
        fail("the live daemon did not start")
    if p.poll() is not None:
        if "permission denied" in open(out).read():
            skip("live capture is not permitted here")
        fail(f"the live daemon ended: {open(out).read()}")
    s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    payloads = data_payloads(cap)
    for k, d in enumerate(payloads):
        s.sendto(d, ("127.0.0.1", 2368))
        if k % 50 == 49:
            time.sleep(0.02)
        if k > 3000 and file_has(csv, "\n5,"):
            break
    if not wait_for(lambda: file_has(csv, "\n5,"), 120):
        p.kill()
        fail(f"the live daemon processed no frames: {open(out).read()}")
    with open(f"/proc/{p.pid}/task/{p.pid}/children") as c:  # the daemon, strace's child
        for pid in c.read().split():
            os.kill(int(pid), 2)
    try:
        p.wait(60)
    except subprocess.TimeoutExpired:
        p.kill()
        fail("the live daemon did not stop on SIGINT")
    if "source: interface lo" not in open(out).read():
        fail(f"the live run did not end with its summary: {open(out).read()}")
    notify.settimeout(5)
    got = set()
    try:
        while not {"READY=1", "WATCHDOG=1"} <= got:
            got |= set(notify.recv(4096).decode().split("\n"))
    except socket.timeout:
        fail(f"the live daemon did not notify READY=1 and WATCHDOG=1: {got}")
    notify.close()
    calls, fams = traced(log)
    all_calls |= calls
    all_fams |= fams
    # strace starts the program with execve: the service manager does that, not the daemon
    outside = sorted(c for c in all_calls if (c not in allow or c in deny) and c != "execve")
    print(f"unit_sandbox: {len(all_calls)} distinct system calls traced; socket families {sorted(all_fams)}")
    if outside:
        fail(f"system calls the unit's SystemCallFilter refuses: {outside}")
    bad_fams = sorted(all_fams - families)
    if bad_fams:
        fail(f"socket families the unit's RestrictAddressFamilies refuses: {bad_fams}")
    print("unit_sandbox: every system call and socket family is inside the unit's sandbox")


if __name__ == "__main__":
    main()
