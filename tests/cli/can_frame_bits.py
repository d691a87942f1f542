#!/usr/bin/env python3
"""Bits on the wire of every classic frame of a candump log, one number per line.

An oracle for lib/include/stickslip/can/frame_bits.hpp written another way: the frame is built
as a string of '0'/'1' characters, the CRC-15 is the remainder of a polynomial long division
of that string (times x^15) by x^15 + x^14 + x^10 + x^8 + x^7 + x^4 + x^3 + 1, and the stuff
bits are found by scanning the string for runs (ISO 11898-1). python-can reads the log.

usage: can_frame_bits.py LOG
"""
import sys

import can

CRC15 = "1100010110011001"  # x^15 + x^14 + x^10 + x^8 + x^7 + x^4 + x^3 + 1, 16 coefficients


def crc15(bits):
    work = list(bits + "0" * 15)
    for i in range(len(bits)):
        if work[i] == "1":
            for j, c in enumerate(CRC15):
                work[i + j] = "0" if work[i + j] == c else "1"
    return "".join(work[-15:])


def stuffed(bits):
    out, run, last = [], 0, None
    for b in bits:
        out.append(b)
        run = run + 1 if b == last else 1
        last = b
        if run == 5:
            s = "1" if b == "0" else "0"
            out.append(s)
            last, run = s, 1
    return "".join(out)


def frame_bits(msg):
    rtr = "1" if msg.is_remote_frame else "0"
    if msg.is_extended_id:
        head = "0" + format(msg.arbitration_id >> 18, "011b") + "11"
        head += format(msg.arbitration_id & 0x3FFFF, "018b") + rtr + "00"
    else:
        head = "0" + format(msg.arbitration_id, "011b") + rtr + "00"
    head += format(msg.dlc, "04b")
    data = "" if msg.is_remote_frame else "".join(format(b, "08b") for b in msg.data)
    body = head + data
    return len(stuffed(body + crc15(body))) + 1 + 1 + 1 + 7 + 3


def main():
    for msg in can.CanutilsLogReader(sys.argv[1]):
        if msg.is_error_frame or msg.is_fd:
            continue
        print(frame_bits(msg))


if __name__ == "__main__":
    main()
