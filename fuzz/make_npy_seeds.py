#!/usr/bin/env python3
"""Writes the hand-made .npy seeds of the npy_samples fuzz target (no NumPy needed).

Each file is a valid or nearly valid NumPy 1.0/2.0 file that reaches a different branch of
faze4's reader: float64 and float32, little and big endian, C and Fortran order, the wrong
dimensions, the wrong dtype, too few rows, a non-finite value, a truncated body.
"""
import struct
from pathlib import Path

OUT = Path(__file__).parent / "seeds" / "npy_samples"


def npy(descr, shape, values, fortran=False, fmt=None, version=1):
    header = f"{{'descr': '{descr}', 'fortran_order': {fortran}, 'shape': {shape}, }}"
    lead = 10 if version == 1 else 12
    pad = (-(lead + len(header) + 1)) % 64
    header = (header + " " * pad + "\n").encode("latin1")
    size = struct.pack("<H", len(header)) if version == 1 else struct.pack("<I", len(header))
    body = struct.pack(fmt or ("<%dd" % len(values)), *values)
    return b"\x93NUMPY" + bytes([version, 0]) + size + header + body


def main():
    OUT.mkdir(parents=True, exist_ok=True)
    six = [0.1 * i for i in range(6)]
    seeds = {
        "f8_c_2x3.npy": npy("<f8", (2, 3), six),
        "f4_fortran_3x2.npy": npy("<f4", (3, 2), six, fortran=True, fmt="<6f"),
        "f8_big_endian_2x2.npy": npy(">f8", (2, 2), six[:4], fmt=">4d"),
        "f4_big_endian_v2_2x1.npy": npy(">f4", (2, 1), six[:2], fmt=">2f", version=2),
        "one_row.npy": npy("<f8", (1, 3), six[:3]),
        "one_d.npy": npy("<f8", (6,), six),
        "three_d.npy": npy("<f8", (1, 2, 3), six),
        "int_dtype.npy": npy("<i8", (2, 3), list(range(6)), fmt="<6q"),
        "nan_value.npy": npy("<f8", (2, 2), [0.0, float("nan"), 1.0, 2.0]),
        "zero_columns.npy": npy("<f8", (2, 0), []),
        "truncated.npy": npy("<f8", (4, 3), six)[:-5],
    }
    for name, data in seeds.items():
        (OUT / name).write_bytes(data)


if __name__ == "__main__":
    main()
