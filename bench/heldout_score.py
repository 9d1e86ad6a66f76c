#!/usr/bin/python3
"""Scores renders of a synthetic capture's held-out camera against its truth.

Usage: heldout_score.py RENDERS HELDOUT K LAST
RENDERS holds render_fNNNNN.png for frames 0..LAST (fvv render's names);
HELDOUT is the capture's truth/heldout directory, K the held-out camera.
Prints "PSNR SSIM": RGB PSNR (dB) over the truth's actor silhouette, pooled
over the frames, and the mean over frames of luma SSIM (7x7 windows) over the
same pixels.
"""
import subprocess
import sys

import numpy as np


def image(path):
    probe = subprocess.run(["ffprobe", "-v", "error", "-select_streams", "v:0", "-show_entries",
                            "stream=width,height", "-of", "csv=p=0", path],
                           capture_output=True, check=True, text=True).stdout.strip().split(",")
    w, h = int(probe[0]), int(probe[1])
    out = subprocess.run(["ffmpeg", "-v", "error", "-i", path, "-f", "rawvideo", "-pix_fmt",
                          "rgb24", "-"], capture_output=True, check=True).stdout
    return np.frombuffer(out, np.uint8).astype(float).reshape(h, w, 3)


def box(a, r=3):
    c = np.pad(a, r + 1, mode="edge").cumsum(0).cumsum(1)
    n = 2 * r + 1
    return (c[n:, n:] - c[:-n, n:] - c[n:, :-n] + c[:-n, :-n])[:a.shape[0], :a.shape[1]] / n / n


def ssim_map(a, b):
    ya, yb = a @ [0.299, 0.587, 0.114], b @ [0.299, 0.587, 0.114]
    c1, c2 = (0.01 * 255) ** 2, (0.03 * 255) ** 2
    ma, mb = box(ya), box(yb)
    va, vb, cov = box(ya * ya) - ma * ma, box(yb * yb) - mb * mb, box(ya * yb) - ma * mb
    return ((2 * ma * mb + c1) * (2 * cov + c2)) / ((ma * ma + mb * mb + c1) * (va + vb + c2))


def main():
    renders, held, k, last = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
    sq = n = 0.0
    ssim = []
    for f in range(last + 1):
        a = image(f"{renders}/render_f{f:05d}.png")
        b = image(f"{held}/held0{k}/{f:06d}.png")
        inside = image(f"{held}/silhouettes/held0{k}/{f:06d}.png")[:, :, 0] > 127
        d = (a - b)[inside]
        sq += (d * d).sum()
        n += d.size
        ssim.append(ssim_map(a, b)[inside].mean())
    print(f"{10 * np.log10(255 ** 2 / (sq / n)):.2f} {np.mean(ssim):.4f}")


if __name__ == "__main__":
    main()
