#!/usr/bin/env python3
"""How a take directory is laid out, as `fvv capture import-calib` arguments.

A take holds its calibration in DIR/calibration (every *.qca.txt, *.toml,
*.yml and *.yaml there, read together) and its frames either as one video
per camera in DIR/videos, or as one folder of numbered images per camera in
DIR/images, each named as the calibration names the camera. Prints the
arguments one per line: the calibration files, then `--video PATTERN`, or
`--images PATTERN --first N` (the numbering read from the first camera's
first image). Exits 1 with a message naming what is missing.

Usage: bench/take_layout.py DIR
"""
import os
import re
import sys

CALIBRATION = (".qca.txt", ".toml", ".yml", ".yaml")
IMAGES = (".png", ".jpg", ".jpeg")


def fail(message):
    print("take_layout: " + message, file=sys.stderr)
    sys.exit(1)


def files(directory):
    return sorted(f for f in os.listdir(directory)
                  if os.path.isfile(os.path.join(directory, f)) and not f.startswith("."))


def layout(take):
    take = os.path.abspath(take)
    calibration_dir = os.path.join(take, "calibration")
    calibration = [os.path.join(calibration_dir, f) for f in files(calibration_dir)
                   if f.lower().endswith(CALIBRATION)] if os.path.isdir(calibration_dir) else []
    if not calibration:
        fail("no calibration in %s (*.qca.txt, *.toml, *.yml or *.yaml)" % calibration_dir)
    videos_dir = os.path.join(take, "videos")
    images_dir = os.path.join(take, "images")
    videos = files(videos_dir) if os.path.isdir(videos_dir) else []
    if videos:
        # Every camera's video has the first one's extension.
        extension = os.path.splitext(videos[0])[1]
        return calibration + ["--video", os.path.join(videos_dir, "{camera}" + extension)]
    cameras = sorted(d for d in os.listdir(images_dir)
                     if os.path.isdir(os.path.join(images_dir, d))) if os.path.isdir(images_dir) else []
    if not cameras:
        fail("no frames in %s: one video per camera in videos/, or one folder of numbered images "
             "per camera in images/, named as the calibration names the camera" % take)
    first_camera = os.path.join(images_dir, cameras[0])
    numbered = [re.match(r"^(.*?)(\d+)(\.[A-Za-z]+)$", f) for f in files(first_camera)]
    numbered = [m for m in numbered if m and m.group(3).lower() in IMAGES]
    if not numbered:
        fail("no numbered images (PNG or JPEG) in %s" % first_camera)
    # The lowest number: names sort by their text, "frame10" before "frame9".
    first = min(numbered, key=lambda m: int(m.group(2)))
    prefix, digits, extension = first.groups()
    # Numbers of one width are padded to it (000000.png); numbers that grow
    # (frame9.png, frame10.png) are not padded, and then none may start with 0.
    if all(len(m.group(2)) == len(digits) for m in numbered):
        width = "%0" + str(len(digits)) + "d"
    elif any(m.group(2).startswith("0") and len(m.group(2)) > 1 for m in numbered):
        fail("the images in %s are numbered with more than one width" % first_camera)
    else:
        width = "%d"
    pattern = os.path.join(images_dir, "{camera}", prefix.replace("%", "%%") + width + extension)
    return calibration + ["--images", pattern, "--first", str(int(digits))]


if __name__ == "__main__":
    if len(sys.argv) != 2:
        fail("usage: bench/take_layout.py DIR")
    print("\n".join(layout(sys.argv[1])))
