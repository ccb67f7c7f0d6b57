#!/usr/bin/env python3
"""Writes the DDS harness's seeds (tests/fuzz/corpus/dds_conversion/): well-formed samples of each
message, and a few with the defects the harness is after, encoded as dds_conversion_fuzzer.cpp reads
them through FuzzBytes. Number: a selector byte (10..15: int16 * 0.25 follows; 0 NaN; 1 +inf).
String: a byte (31 mod 32 = null), a length byte, the bytes. Enum: a byte (not 7 mod 8), the value.
Sequence: a byte (not 3 mod 4), the length below 8; or 3, then a uint16 length.
Usage: tests/fuzz/make_dds_corpus.py"""
import os
import struct

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus", "dds_conversion")
MESSAGES = ["mission", "obstacle", "cancel", "fleet", "trajectory", "plan_status", "service_status", "fleet_status"]


def num(v):
    if v != v:
        return b"\x00"
    if v == float("inf"):
        return b"\x01"
    q = round(v * 4)
    assert -32768 <= q <= 32767 and q / 4 == v, v
    return b"\x0a" + struct.pack("<h", q)


def text(s):
    raw = s.encode()
    assert len(raw) <= 64
    return b"\x00" + bytes([len(raw)]) + raw  # not null, then the length


def enum(v):
    return b"\x00" + bytes([v])


def bad_enum(v):
    return b"\x07" + struct.pack("<i", v)


def seq(items, encode):
    n = len(items)
    head = b"\x00" + bytes([n]) if n < 8 else b"\x03" + struct.pack("<H", n)
    return head + b"".join(encode(i) for i in items)


def wgs84(lat, lon, alt):
    return enum(0) + num(lat) + num(lon) + num(alt) + num(0) * 3


def enu(e, n, u):
    return enum(1) + num(0) * 3 + num(e) + num(n) + num(u)


LIMITS = b"".join(num(v) for v in (20, 30, 4, 5, 4, 0, 30, 5000))


def mission(begin, points, end, limits=LIMITS, request="r1", vehicle="uav-1", planner=""):
    return (bytes([0]) + text(request) + text(vehicle) + begin + seq(points, lambda p: p) + end + limits +
            text(planner) + b"\x00")


def obstacle(shape, motion, speed=25, valid_until=0, remove=False, shape_enc=enum):
    vec = lambda x, y, z: num(x) + num(y) + num(z)
    return (bytes([1]) + struct.pack("<Q", 7) + shape_enc(shape) + vec(50, 50, 100) + vec(0, 0, 400) + enum(motion) +
            vec(5, 0, 0) + vec(0, 0, 400) + vec(1000, 0, 400) + num(speed) + b"\x01" + struct.pack("<i", 0) +
            (b"\x01" if valid_until == 0 else b"\x00" + struct.pack("<q", valid_until)) + (b"\x01" if remove else b"\x00"))


def fleet(vehicles, tasks):
    return (bytes([3]) + text("fleet-1") + seq(vehicles, text) + seq([wgs84(44.25, -71.25, 1000)] * len(vehicles), lambda p: p) +
            seq(tasks, lambda p: p) + seq([enu(0, 0, 800)] * len(vehicles), lambda p: p) + LIMITS + text(""))


def trajectory(samples):
    sample = lambda t: (num(t) + struct.pack("<q", 1704067200000000000 + int(t * 1e9)) + num(t) * 3 + num(1) * 3 +
                        num(0) * 3 + num(90) + num(44.25) + num(-71.25) + num(1000))
    return (bytes([4]) + text("uav-1") + text("plan-1") + struct.pack("<I", 2) + text("r1") +
            struct.pack("<q", 1704067200000000000) + seq([0, 2, 1, 3], lambda i: struct.pack("<I", i)) +
            seq([(0, 2, 0, 5), (2, 1, 5, 9)], lambda l: struct.pack("<II", l[0], l[1]) + num(l[2]) + num(l[3])) +
            seq(samples, sample))


SEEDS = {
    "mission_wgs84_and_enu": mission(wgs84(44.25, -71.25, 1000), [wgs84(44.5, -71.5, 1100), enu(1500, -200, 1200)],
                                     wgs84(44.25, -71, 1000)),
    "mission_nan_point": mission(wgs84(44.25, -71.25, 1000), [enu(float("nan"), 0, 1)], enu(0, 0, 1)),
    "mission_bad_frame": mission(bad_enum(-5) + num(0) * 6, [enu(1, 2, 3)], enu(0, 0, 1)),
    "mission_too_many_points": mission(enu(0, 0, 500), [enu(i, 0, 500) for i in range(70)], enu(0, 0, 500)),
    "mission_empty_ids": mission(enu(0, 0, 500), [enu(1, 0, 500)], enu(0, 0, 500), request="", vehicle=""),
    "mission_limits_out_of_range": mission(enu(0, 0, 500), [enu(1, 0, 500)], enu(0, 0, 500),
                                           limits=b"".join(num(v) for v in (40, 30, 4, 5, float("inf"), 0, 30, 5000))),
    "obstacle_back_and_forth": obstacle(3, 2),
    "obstacle_constant_velocity_until": obstacle(2, 1, valid_until=1704067260000000000),
    "obstacle_bad_shape": obstacle(9, 0, shape_enc=bad_enum),
    "obstacle_remove": obstacle(0, 0, remove=True),
    "cancel": bytes([2]) + text("r1") + text("uav-1"),
    "cancel_no_vehicle": bytes([2]) + text("r1") + text(""),
    "fleet_two_vehicles": fleet(["uav-1", "uav-2"], [enu(100, 100, 800), enu(-100, 50, 800), wgs84(44.25, -71.25, 900)]),
    "fleet_duplicate_vehicle": fleet(["uav-1", "uav-1"], [enu(100, 100, 800)]),
    "trajectory": trajectory([0, 0.5, 1]),
    "plan_status": bytes([5]) + text("r1") + text("uav-1") + enum(3) + enum(6) + text("points[0]") +
                   text("points[0]: outside the map") + num(0.25),
    "service_status": bytes([6]) + text("skyrouted") + struct.pack("<q", 1704067200000000000) + b"\x01" +
                      text("default_terrain.tif") + struct.pack("<III", 2, 5, 1) + text("0.1.0") + text("1"),
    "fleet_status": bytes([7]) + text("fleet-1") + enum(2) + enum(0) + text("") + text("") +
                    seq([("uav-1", [0, 2], 0), ("uav-2", [1], 1.5)],
                        lambda a: text(a[0]) + seq(a[1], lambda i: struct.pack("<I", i)) + num(a[2])) +
                    struct.pack("<i", 40) + num(120) + num(100) + num(150) + struct.pack("<I", 1) + num(2),
}

os.makedirs(OUT, exist_ok=True)
for name, data in SEEDS.items():
    with open(os.path.join(OUT, name + ".bin"), "wb") as f:
        f.write(data)
print(f"{len(SEEDS)} seeds in {OUT}")
