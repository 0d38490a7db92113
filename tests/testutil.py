"""testutil.py - what the Python tests of the programs (exporter.py, web.py,
bridge.py) share: the CTest exit codes (77 skipped, 1 failed) with the test's
name, a free loopback port, a raw HTTP exchange, and waiting for a condition
with a timeout (never a fixed sleep)."""
import socket
import sys
import time

NAME = "test"


def named(name):
    """The name skip() and fail() print."""
    global NAME
    NAME = name


def skip(why):
    print(f"{NAME}: skipped: {why}")
    sys.exit(77)


def fail(why):
    print(f"{NAME}: FAIL: {why}")
    sys.exit(1)


def free_port():
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    s.close()
    return port


def raw(port, data, read=True, timeout=30):
    """Sends bytes to the loopback port; with read, everything until the peer
    closes (or the timeout)."""
    s = socket.create_connection(("127.0.0.1", port), timeout=timeout)
    s.sendall(data)
    out = b""
    if read:
        try:
            while True:
                b = s.recv(65536)
                if not b:
                    break
                out += b
        except socket.timeout:
            pass
    s.close()
    return out


def wait_for(pred, timeout, what):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if pred():
            return
        time.sleep(0.05)
    fail(f"waited {timeout} s for {what}")
