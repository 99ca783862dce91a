#!/usr/bin/python3
"""positions_diff.py A B [T ...] -- RMS over vertices of the distance between the positions of
two run folders' positions.bin (or two files) at common sample times, in metres.

Prints one line per common time `t rms_m max_m`; with times T given, only those (nearest record
within 1e-9 s).  Reads whole records only (a killed run may end in a partial one)."""
import os
import sys

import numpy as np


def records(path):
    """The whole records of a positions.bin (or of a run folder's): their times (s, n) and
    positions (m, n x nv x dim), in the order written."""
    if os.path.isdir(path):
        path = os.path.join(path, "positions.bin")
    raw = open(path, "rb").read()
    if raw[:8] != b"SWPOS001":
        sys.exit(f"{path}: not a positions.bin (magic SWPOS001 expected)")
    nv, dim = np.frombuffer(raw[8:16], dtype=np.int32)
    rec = 1 + int(nv) * int(dim)
    n = (len(raw) - 16) // (8 * rec)
    data = np.frombuffer(raw[16:16 + 8 * rec * n], dtype=np.float64).reshape(n, rec)
    return data[:, 0], data[:, 1:].reshape(n, int(nv), int(dim))


def read(path):
    """The records by time (rounded to 1e-9 s; of records at one time, the last)."""
    times, x = records(path)
    return {round(t, 9): p for t, p in zip(times, x)}


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    a, b = read(sys.argv[1]), read(sys.argv[2])
    times = sorted(set(a) & set(b))
    if len(sys.argv) > 3:
        want = [round(float(t), 9) for t in sys.argv[3:]]
        times = [t for t in times if t in want]
    for t in times:
        d = np.linalg.norm(a[t] - b[t], axis=1)
        print(f"{t:g} {np.sqrt(np.mean(d * d)):.6e} {d.max():.6e}")


if __name__ == "__main__":
    main()
