#!/usr/bin/env python3
"""mkwheel.py - the Python package of roadscan's LCM types as a wheel, without
setuptools or the network (the build runs it after lcm-gen).

    mkwheel.py PYDIR VERSION OUTDIR

PYDIR holds the package `roadscan/` that lcm-gen -p wrote. The wheel
(roadscan_lcmtypes-VERSION-py3-none-any.whl, pure Python, requires PyPI's lcm)
goes to OUTDIR; `pip install` takes it from the build tree or from
/usr/share/roadscan/python where the .deb puts it. Byte-identical for the same
inputs (fixed times and order in the zip).
"""
import base64
import hashlib
import os
import sys
import zipfile

NAME = "roadscan_lcmtypes"


def record_line(path, data):
    digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
    return f"{path},sha256={digest},{len(data)}"


def main():
    if len(sys.argv) != 4:
        print(__doc__, file=sys.stderr)
        return 2
    pydir, version, outdir = sys.argv[1:]
    pkg = os.path.join(pydir, "roadscan")
    files = sorted(f for f in os.listdir(pkg) if f.endswith(".py"))
    if "__init__.py" not in files:
        print(f"mkwheel.py: {pkg} has no __init__.py (run lcm-gen -p first)", file=sys.stderr)
        return 1
    info = f"{NAME}-{version}.dist-info"
    entries = [(f"roadscan/{f}", open(os.path.join(pkg, f), "rb").read()) for f in files]
    entries.append((f"{info}/METADATA", (
        "Metadata-Version: 2.1\n"
        "Name: roadscan-lcmtypes\n"
        f"Version: {version}\n"
        "Summary: roadscan's LCM messages (object lists, track lists, track ends, counts, frame statistics)\n"
        "License: MIT\n"
        "Requires-Dist: lcm\n"
        "\n"
        "The Python types lcm-gen generates from roadscan's lcmtypes/roadscan.lcm. Check untrusted bytes\n"
        "before decoding them (the generated decoders trust the wire): see examples/listen.py.\n").encode()))
    entries.append((f"{info}/WHEEL", (
        "Wheel-Version: 1.0\nGenerator: roadscan mkwheel.py\nRoot-Is-Purelib: true\nTag: py3-none-any\n").encode()))
    entries.append((f"{info}/top_level.txt", b"roadscan\n"))
    record = "\n".join(record_line(p, d) for p, d in entries) + f"\n{info}/RECORD,,\n"
    entries.append((f"{info}/RECORD", record.encode()))
    os.makedirs(outdir, exist_ok=True)
    out = os.path.join(outdir, f"{NAME}-{version}-py3-none-any.whl")
    tmp = out + ".tmp"
    with zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as z:
        for path, data in entries:
            zi = zipfile.ZipInfo(path, date_time=(1980, 1, 1, 0, 0, 0))
            zi.external_attr = 0o644 << 16
            zi.compress_type = zipfile.ZIP_DEFLATED
            z.writestr(zi, data)
    os.replace(tmp, out)
    print(out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
