#!/usr/bin/env python3
"""Splits the static false alarms of a `slamkit vio --images --feature-log CSV` run into motion-model
errors and track errors (docs/frontend.md, sessions 25 and 28).

For every scored feature whose patch is static at both ends (truth 0) and that was flagged dynamic, the
epipolar distance is recomputed with the TRUE relative pose of its two frames (the renders'
groundtruth.tum, IMU poses at the camera times, and cam0's T_cam_imu from camchain.yaml): f times the
angle between b2 and the epipolar plane of b1, with the Kannala-Brandt (equidistant) unprojection.
Above the test's threshold (threshold * b^exponent for the long baseline b > 1, threshold for b = 1)
the track itself is off (a track error); under it, a correct model would have passed it (a model
error). The same is reported for a sample of the true negatives.

Usage: bench/epipolar_true_pose_check.py RENDER_DIR FEATURE_LOG.csv [THRESHOLD_PX] [EXPONENT]
(numpy only; RENDER_DIR is the folder of `slamkit simulate --images`).
"""
import csv
import random
import re
import sys

import numpy as np


def read_cam0(path):
    text = open(path).read().split("cam1:")[0]
    rows = re.findall(r"-\s*\[([^\]]+)\]", text.split("T_cam_imu:")[1])[:4]
    T_cam_imu = np.array([[float(x) for x in r.split(",")] for r in rows])
    k = [float(x) for x in re.search(r"distortion_coeffs:\s*\[([^\]]+)\]", text).group(1).split(",")]
    intr = [float(x) for x in re.search(r"intrinsics:\s*\[([^\]]+)\]", text).group(1).split(",")]
    return T_cam_imu, intr, k


def quat_to_R(q):
    x, y, z, w = q / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    render, log = sys.argv[1], sys.argv[2]
    threshold = float(sys.argv[3]) if len(sys.argv) > 3 else 1.0
    exponent = float(sys.argv[4]) if len(sys.argv) > 4 else 0.5
    T_cam_imu, (fx, fy, cx, cy), k = read_cam0(render + "/camchain.yaml")
    T_imu_cam = np.linalg.inv(T_cam_imu)
    poses = []  # T_world_cam per frame
    for row in np.loadtxt(render + "/groundtruth.tum"):
        T = np.eye(4)
        T[:3, :3], T[:3, 3] = quat_to_R(row[4:8]), row[1:4]
        poses.append(T @ T_imu_cam)

    def bearing(u, v):  # Kannala-Brandt: r_d = θ(1 + k1θ² + k2θ⁴ + k3θ⁶ + k4θ⁸), θ by Newton
        x, y = (u - cx) / fx, (v - cy) / fy
        rd = np.hypot(x, y)
        th = rd
        for _ in range(10):
            f = th * (1 + k[0] * th**2 + k[1] * th**4 + k[2] * th**6 + k[3] * th**8) - rd
            th -= f / (1 + 3 * k[0] * th**2 + 5 * k[1] * th**4 + 7 * k[2] * th**6 + 9 * k[3] * th**8)
        s = np.sin(th) / rd if rd > 1e-12 else 1.0
        return np.array([x * s, y * s, np.cos(th)])

    def check(rows):  # (true-pose distance, threshold, measured distance) per row
        out = []
        for r in rows:
            kf, b = int(r["frame"]), int(r["baseline"])
            T21 = np.linalg.inv(poses[kf]) @ poses[kf - b]  # x_c2 = R x_c1 + t
            R, t = T21[:3, :3], T21[:3, 3]
            b1, b2 = bearing(float(r["u_then"]), float(r["v_then"])), bearing(float(r["u"]), float(r["v"]))
            n = np.cross(t, R @ (b1 / np.linalg.norm(b1)))
            d = fx * np.arcsin(min(1.0, abs((b2 / np.linalg.norm(b2)) @ n) / np.linalg.norm(n)))
            out.append((d, threshold * b**exponent if b > 1 else threshold, float(r["distance_px"])))
        return np.array(out).reshape(-1, 3)

    rows = list(csv.DictReader(open(log)))
    alarms = check([r for r in rows if r["truth"] == "0" and r["motion"] == "dynamic"])
    negatives = [r for r in rows if r["truth"] == "0" and r["motion"] == "static"]
    random.seed(0)
    tn = check(random.sample(negatives, min(3000, len(negatives))))
    track = int((alarms[:, 0] > alarms[:, 1]).sum())
    print(f"{log}: {len(alarms)} static false alarms: {track} track errors (true-pose distance above the threshold), "
          f"{len(alarms) - track} model errors; true-pose distance median {np.median(alarms[:, 0]):.2f} px, measured "
          f"{np.median(alarms[:, 2]):.2f} px; true negatives above the threshold with the true pose: "
          f"{(tn[:, 0] > tn[:, 1]).mean():.3f} of {len(tn)}")


if __name__ == "__main__":
    main()
