#!/usr/bin/env python3
"""Writes the small seed corpora of the libFuzzer targets into test/fuzz/corpus/<target>/
(committed; re-run after changing an input layout). Layouts: see each *_fuzzer.cpp."""
import os
import shutil
import struct

here = os.path.dirname(os.path.abspath(__file__))
root = os.path.dirname(os.path.dirname(here))


def put(target, name, data):
    d = os.path.join(here, "corpus", target)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, name), "wb") as f:
        f.write(data.encode() if isinstance(data, str) else data)


# cloud_decode_fuzzer: 32-byte header (width, height, point_step, row_step, flags, max_points
# selector, offsets, datatypes, counts) then the data.
def cloud(width, height, step, row, flags=0, maxsel=255, offs=(0, 4, 8), types=(7, 7, 7),
          counts=(0, 0, 0), data=b""):
    h = struct.pack("<4I", width, height, step, row) + bytes([flags, maxsel]) + bytes(offs) \
        + bytes(types) + bytes(counts) + b"\0" * 5
    assert len(h) == 32
    return h + data

pts = [(1.0, 2.0, 0.5), (float("nan"), 0.0, 0.0), (0.0, 0.0, 0.0), (5.0, -1.0, 1.5)]
f32 = b"".join(struct.pack("<3f", *p) for p in pts)
put("cloud_decode", "xyz_f32", cloud(4, 1, 12, 48, data=f32))
put("cloud_decode", "xyz_f32_2x2_padded", cloud(2, 2, 16, 40, flags=16,
    data=b"".join(struct.pack("<4f", *p, 0.7) for p in pts[:2]) + b"\0" * 8
    + b"".join(struct.pack("<4f", *p, 0.7) for p in pts[2:]) + b"\0" * 8))
put("cloud_decode", "xyz_f64", cloud(4, 1, 24, 96, flags=2, offs=(0, 8, 16),
    data=b"".join(struct.pack("<3d", *p) for p in pts)))
put("cloud_decode", "big_endian", cloud(4, 1, 12, 48, flags=1, data=f32))
put("cloud_decode", "truncated", cloud(4, 1, 12, 48, data=f32[:30]))
put("cloud_decode", "uint16_x", cloud(4, 1, 12, 48, flags=32, types=(4, 7, 7), data=f32))
# regression_transform_overflow (not written here): the fuzzer's crash input for finite
# coordinates near FLT_MAX that overflowed to inf in the transform, kept as found.

# kitti_labels_fuzzer: label_02 lines (17 fields, 18 with score).
put("kitti_labels", "tracking", (
    "0 -1 DontCare -1 -1 -10.000000 219.310000 188.490000 245.500000 218.560000 -1000.000000 -1000.000000 -1000.000000 -10.000000 -1.000000 -1.000000 -1.000000\n"
    "0 0 Van 0 0 -1.793451 296.744956 161.752147 455.226042 292.372804 2.000000 1.823255 4.433886 -4.552284 1.858523 13.410495 -2.115488\n"
    "1 2 Pedestrian 0 0 -0.5 700 150 750 300 1.7 0.6 0.8 1.5 1.6 8.0 0.1\n"))
put("kitti_labels", "with_score", "3 1 Car 1 2 0.1 10 20 30 40 1.5 1.6 3.9 2.0 1.7 20.0 1.57 0.93\n")
put("kitti_labels", "malformed", "0 0 Car 0 0 x 1 2 3 4 5 6 7 8 9 10 11\n\n0 1\n")
put("kitti_labels", "empty", "")

# scenario_fuzzer: the shipped scenario files and a minimal one.
for src in ["test/rostest/approach_front.yaml"] + sorted(
        os.path.join("config/scenarios", f) for f in os.listdir(os.path.join(root, "config/scenarios")))[:3]:
    d = os.path.join(here, "corpus", "scenario")
    os.makedirs(d, exist_ok=True)
    shutil.copy(os.path.join(root, src), os.path.join(d, os.path.basename(src)))
put("scenario", "minimal.yaml", "name: m\nduration_s: 1\nrate_hz: 10\nprofile: zebra\n")
# Found by the fuzzer: a huge duration made Scenario::frames() convert out of range.
put("scenario", "regression_huge_duration.yaml", "name: m\nduration_s: 1e300\nrate_hz: 100\nprofile: zebra\n")

# rosserial_parser_fuzzer: a max-payload byte, then [length, time step, bytes] chunks holding real
# frames (request topics; Bool on 100; time reply; TopicInfo of lamp_cmd in two chunks).
put("rosserial_parser", "request_topics", b"\x80\x08\x01\xff\xfe\x00\x00\xff\x00\x00\xff")
put("rosserial_parser", "bool", b"\x80\x09\x00\xff\xfe\x01\x00\xfe\x64\x00\x01\x9a")
put("rosserial_parser", "time", b"\x80\x10\x05\xff\xfe\x08\x00\xf7\x0a\x00\x00\xf1\x53\x65\x00\x65\xcd\x1d\xfd")
put("rosserial_parser", "topic_info",
    b"\x80\x06\x00\xff\xfe\x47\x00\xb8\x01\x49\x00\x00\x64\x00\x08\x00\x00\x00lamp_cmd\x0d\x00\x00\x00"
    b"std_msgs/Bool\x20\x00\x00\x008b94c1b53db61fb6aed406028ad6332a\x00\x02\x00\x00\x25")
