#!/usr/bin/env python3
"""Checks plumb's Unitree CRC against an independent implementation.

Reads crc_vectors' JSON lines. For each message: its layout must have the size and the
field-by-field packing Unitree's SDK2 uses (Python struct formats, written here from the
IDL's field types with natural alignment), and plumb's CRC must equal CRC-32/MPEG-2 (from
the fastcrc package) of the layout's 32-bit little-endian words, each fed most significant
byte first, all but the last (the crc field), which is how Unitree's SDK computes it.
"""
import json
import struct
import sys

from fastcrc import crc32

MOTOR_GO_CMD = "B3x5f3I"
MOTOR_GO_STATE = "B3x7fB3x3I"
MOTOR_HG_CMD = "B3x5fI"
MOTOR_HG_STATE = "B3x4f2hf7I"
FORMATS = {
    "unitree_go::msg::dds_::LowCmd_": ("<4B4IH2x" + MOTOR_GO_CMD * 20 + "4B" + "55Bx2I", 812),
    "unitree_go::msg::dds_::LowState_": ("<4B4IH2x" + "13fB3x" + MOTOR_GO_STATE * 20
                                         + "4BiH4B15H" + "8hI41B3xf2B2x2f4H2I", 1180),
    "unitree_hg::msg::dds_::LowCmd_": ("<2B2x" + MOTOR_HG_CMD * 35 + "5I", 1004),
    "unitree_hg::msg::dds_::LowState_": ("<2I2B2xI" + "13fh2x" + MOTOR_HG_STATE * 35
                                         + "40B5I", 2092),
}


def main():
    failed = False
    for line in sys.stdin:
        v = json.loads(line)
        fmt, size = FORMATS[v["type"]]
        data = bytes.fromhex(v["hex"])
        problems = []
        if struct.calcsize(fmt) != size or len(data) != size:
            problems.append(f"size {len(data)}, format {struct.calcsize(fmt)}, expected {size}")
        else:
            # the padding ('x') must be zero: re-packing the unpacked fields gives the bytes
            fields = struct.unpack(fmt, data)
            if struct.pack(fmt, *fields) != data:
                problems.append("the layout's padding or field positions differ from Unitree's")
        words = [int.from_bytes(data[i:i + 4], "little") for i in range(0, len(data) - 4, 4)]
        expected = crc32.mpeg_2(b"".join(w.to_bytes(4, "big") for w in words))
        if expected != v["crc"]:
            problems.append(f"crc {v['crc']:#010x}, fastcrc says {expected:#010x}")
        print(f"{v['type']}: {size} bytes, crc {v['crc']:#010x}: "
              + ("ok" if not problems else "; ".join(problems)))
        failed = failed or bool(problems)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
