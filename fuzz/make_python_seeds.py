#!/usr/bin/env python3
"""Writes fuzz/seeds/python_conversion: inputs of the `python_conversion` fuzz target in its byte
format (faze4::fuzzing::python_conversion): keyword values as trees of Python values, and a
replay's arrays. Run from the repository's root: python3 fuzz/make_python_seeds.py"""
import pathlib
import struct

OUT = pathlib.Path("fuzz/seeds/python_conversion")


def text(s):
    raw = s.encode()
    assert len(raw) < 64
    return bytes([4 * len(raw)]) + raw


def obj(v):
    """A Python value in the target's tags (b % 16): 0 None, 1 bool, 4 float, 6 str, 8 path,
    9 dict, 11 list, 13 array (floats (b - 128) / 8), 15 cut/other."""
    if v is None:
        return bytes([0])
    if v is True or v is False:
        return bytes([1 | (16 if v else 0)])
    if isinstance(v, (int, float)):
        return bytes([4]) + struct.pack("<d", float(v))
    if isinstance(v, str):
        return bytes([6]) + text(v)
    if isinstance(v, pathlib.PurePath):
        return bytes([8]) + text(str(v))
    if isinstance(v, dict):
        return bytes([9, len(v)]) + b"".join(text(k) + obj(x) for k, x in v.items())
    if isinstance(v, list):
        return bytes([11, len(v)]) + b"".join(obj(x) for x in v)
    raise TypeError(v)


def keywords(command, **given):
    commands = ["wave", "replay", "shape", "retime"]
    out = bytes([0, commands.index(command)])
    for name, value in given.items():
        out += bytes([255]) + text(name) + value
    return out


def array_2d(rows):
    """A numpy array (tag 13) of small values: (v - 128) / 8 from bytes."""
    out = bytes([13, 1, len(rows), len(rows[0])])
    for row in rows:
        out += bytes(int(v * 8 + 128) for v in row)
    return out


stepper = {"name": "joint_1", "kind": "stepper", "gear_ratio": 20.0, "curve": [[0.0, 1.0], [10.0, 0.5]]}
dc = {"kind": "dc", "stall_torque": 2.0, "no_load_speed": 30.0}
deep = [1.0]
for _ in range(33):
    deep = [deep]
seeds = {
    "motors-dict": keywords("wave", motors=obj({"joint": [stepper, dc]})),
    "motors-deep": keywords("wave", motors=obj({"joint": deep})),
    "per-joint": keywords("wave", kp=obj([1.0, None, 2.0, 3.0, 4.0, 5.0]), dt=obj(0.001)),
    "per-joint-2d-array": keywords("wave", kp=array_2d([[1, 2], [3, 4]])),
    "paths": keywords("replay", q_traj=obj(pathlib.PurePath("a.npy")), duration=obj("x")),
    "count-cut": keywords("shape", motors=bytes([15 | 16])),
    # arrays: 3 frames of 2 joints as samples; then timed, with t and named joints
    "samples": bytes([1, 3, 2, 8, 16, 24, 32, 40, 48, 0]),
    "timed": bytes([1, 3, 2, 8, 16, 24, 32, 40, 48, 1, 3, 0, 8, 16, 1, 8, 8, 8, 8, 8, 8, 0, 1]),
}
OUT.mkdir(parents=True, exist_ok=True)
for name, data in seeds.items():
    (OUT / name).write_bytes(data)
