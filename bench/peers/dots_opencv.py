#!/usr/bin/python3
"""Peer for the measurement benchmark (docs/benchmarks.md): the textbook
per-frame colour-dot pipeline in Python with OpenCV, as a lab would port the
thesis's MATLAB (section 4.1.3): decode to BGR, cvtColor to HSV, inRange for
red (two ranges across hue 0), morphologyEx opening and closing with a disk,
connectedComponentsWithStats, and the centroids of dot-sized components.

Uses Debian's python3-opencv; run with /usr/bin/python3.
Usage: dots_opencv.py VIDEO  -> prints "frames seconds fps dots_per_frame".
"""
import sys
import time

import cv2
import numpy as np


def main():
    path = sys.argv[1]
    capture = cv2.VideoCapture(path)
    if not capture.isOpened():
        sys.exit(f"{path}: cannot open")
    disk = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (7, 7))
    frames = dots = 0
    start = time.perf_counter()
    while True:
        ok, bgr = capture.read()
        if not ok:
            break
        hsv = cv2.cvtColor(bgr, cv2.COLOR_BGR2HSV)
        mask = cv2.inRange(hsv, (170, 100, 50), (179, 255, 255)) | cv2.inRange(
            hsv, (0, 100, 50), (10, 255, 255))
        mask = cv2.morphologyEx(mask, cv2.MORPH_OPEN, disk)
        mask = cv2.morphologyEx(mask, cv2.MORPH_CLOSE, disk)
        n, _, stats, centroids = cv2.connectedComponentsWithStats(mask)
        area = stats[1:, cv2.CC_STAT_AREA]
        dots += int(np.count_nonzero((area > 40) & (area < 4000)))
        frames += 1
    seconds = time.perf_counter() - start
    print(f"{frames} {seconds:.4f} {frames / seconds:.2f} {dots / max(frames, 1):.2f}")


if __name__ == "__main__":
    main()
