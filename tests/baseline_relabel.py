#!/usr/bin/env python3
"""scripts/baseline/relabel.py on a hand-made run with known answers.

Three frames (the foreground column: 3, 0 and 2 returns). Frame 0: two returns of object 1 and one
of noise; frame 2: one return of object 1 and one of object 2. The association gives object 1 of
frame 0 to track 5 (tentative) and object 1 of frame 2 to track 5 (confirmed); object 2 of frame 2 to
no track. All tracks: 7, 7, 2 / 7, 2. Only confirmed: 2, 2, 2 / 7, 2. A label file with a return
too many is refused. Exit 0 when every label is as wanted, 1 otherwise."""
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCRIPT = os.path.join(ROOT, "scripts", "baseline", "relabel.py")


def run(tmp, labels, which):
    lab, frm, asc, out = (os.path.join(tmp, n) for n in ("l.csv", "f.csv", "a.csv", "o.csv"))
    with open(lab, "w") as f:
        f.write("# roadscand point labels\npacket,block,channel,label\n" + "".join(f"{i},0,0,{l}\n" for i, l in enumerate(labels)))
    with open(frm, "w") as f:
        f.write("frame,foreground\n0,3\n1,0\n2,2\n")
    with open(asc, "w") as f:
        f.write("frame,object,track,state\n0,1,5,tentative\n2,1,5,confirmed\n")
    p = subprocess.run([sys.executable, SCRIPT, lab, frm, asc, out] + ([which] if which else []), capture_output=True, text=True)
    if p.returncode:
        return None, p.stderr
    with open(out) as f:
        return [int(ln.rstrip().split(",")[3]) for ln in f if ln[0].isdigit()], ""


def main():
    with tempfile.TemporaryDirectory() as tmp:
        for which, want in (("", [7, 7, 2, 7, 2]), ("confirmed", [2, 2, 2, 7, 2])):
            got, err = run(tmp, [3, 3, 2, 3, 4], which)
            if got != want:
                print(f"relabel {which or 'all'}: {got} {err}, wanted {want}")
                return 1
        got, err = run(tmp, [3, 3, 2, 3, 4, 3], "")
        if got is not None or "does not hold" not in err:
            print(f"a label file with a return too many: {got} {err}")
            return 1
    print("relabel: all tracks and only confirmed ones as wanted; a mismatched file refused")
    return 0


if __name__ == "__main__":
    sys.exit(main())
