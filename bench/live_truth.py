#!/usr/bin/env python3
"""Error of a live trajectory against the lidar emulator's truth (bench/live.sh).

    live_truth.py TRUTH TRAJECTORY

TRUTH: "t x y yaw" per scan the emulator served; TRAJECTORY: pm-slam-app's (or pm-icp-slam's) trajectory.txt.
Each pose is paired with the truth served nearest in time (the driver stamps a scan within one period of when
it was cast). Prints: poses, mean and max translational error of relations 1 s apart (m), their mean rotational
error (deg), and the largest drift from the first pose (m), space-separated.
"""
import bisect
import math
import sys


def load(path):
    out = []
    for line in open(path):
        if line.strip() and not line.startswith('#'):
            t, x, y, a = map(float, line.split()[:4])
            out.append((t, x, y, a))
    return out


def rel(a, b):
    dx, dy = b[1] - a[1], b[2] - a[2]
    c, s = math.cos(a[3]), math.sin(a[3])
    return c * dx + s * dy, -s * dx + c * dy, math.remainder(b[3] - a[3], 2 * math.pi)


def main():
    truth, est = load(sys.argv[1]), load(sys.argv[2])
    stamps = [t[0] for t in truth]
    gt = []
    for e in est:
        i = bisect.bisect_left(stamps, e[0])
        j = min((k for k in (i - 1, i) if 0 <= k < len(stamps)), key=lambda k: abs(stamps[k] - e[0]))
        gt.append(truth[j])
    trans, rot, j = [], [], 0
    for i in range(len(est)):
        while j < len(est) and est[j][0] < est[i][0] + 1.0:
            j += 1
        if j >= len(est):
            break
        re, rg = rel(est[i], est[j]), rel(gt[i], gt[j])
        trans.append(math.hypot(re[0] - rg[0], re[1] - rg[1]))
        rot.append(abs(math.degrees(math.remainder(re[2] - rg[2], 2 * math.pi))))
    drift = max(math.hypot(rel(est[0], e)[0] - rel(gt[0], g)[0], rel(est[0], e)[1] - rel(gt[0], g)[1])
                for e, g in zip(est, gt))
    print(len(est), "%.4f" % (sum(trans) / len(trans)), "%.4f" % max(trans), "%.3f" % (sum(rot) / len(rot)),
          "%.3f" % drift)


if __name__ == '__main__':
    main()
