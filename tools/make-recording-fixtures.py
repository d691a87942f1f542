#!/usr/bin/env python3
"""Writes vehicle-style CAN recordings with tools this project did not write, and what those
tools decode from them: the oracle for stickslip's log and DBC readers (tests/host, group
RecordingFixtures).

    make-recording-fixtures.py OUT_DIR

OUT_DIR receives
  vehicle.dbc                 a J1939-style DBC: the cab-floor acceleration AccZ in CabFloor
                              (extended id 0x0CFF1231, 0.001 g per bit, Motorola, signed, 500 Hz),
                              other traffic at 1 kHz (EEC1 extended, Intel; Body standard id)
  vehicle.{log,asc,blf,trc}   the same bus (2 s) written by python-can's candump, ASC, BLF and
                              TRC writers (plus remote, error and CAN FD frames, which each
                              writer keeps or drops as it does)
  frames-FORMAT.txt           every classic data frame python-can reads back from that file:
                              "id extended dlc hexdata"
  signals-FORMAT.txt          "MESSAGE.SIGNAL time value" for every signal of every frame the
                              DBC knows, as python-can reads the file and canmatrix decodes it
                              (repr of the doubles, so exact)
Needs Debian's python3-can and python3-canmatrix; exits 77 naming what is missing.
"""
import math
import os
import struct
import sys

try:
    import can
    import canmatrix
    import canmatrix.formats
except ImportError as error:  # pragma: no cover
    print(f"SKIPPED: python3-can or python3-canmatrix missing ({error})")
    sys.exit(77)

DBC = """VERSION ""

NS_ :
\tCM_
\tVAL_

BS_:

BU_: Logger Engine Cab

BO_ 2365526577 CabFloor: 8 Cab
 SG_ AccZ : 7|16@0- (0.001,0) [-32.768|32.767] "g" Logger
 SG_ AccX : 23|16@0- (0.001,0) [-32.768|32.767] "g" Logger
 SG_ Status : 39|4@0+ (1,0) [0|15] "" Logger

BO_ 2364540158 EEC1: 8 Engine
 SG_ EngineSpeed : 24|16@1+ (0.125,0) [0|8031.875] "rpm" Logger
 SG_ DriverDemandTorque : 8|8@1+ (1,-125) [-125|125] "%" Logger

BO_ 291 Body: 8 Cab
 SG_ DoorOpen : 0|1@1+ (1,0) [0|1] "" Logger
 SG_ CabTilt : 8|12@1- (0.05,-10) [-112.4|92.35] "deg" Logger

CM_ BO_ 2365526577 "Cab floor accelerometer, 500 Hz";
CM_ SG_ 2365526577 AccZ "Vertical cab-floor acceleration";
VAL_ 2365526577 Status 0 "ok" 15 "not available" ;
"""

CAB_FLOOR_ID = 0x0CFF1231
EEC1_ID = 0x0CF004FE
BODY_ID = 0x123
START = 1700000000.0
SECONDS = 2


def accz_g(t):
    return 0.35 * math.sin(2 * math.pi * 2.0 * t) + 0.12 * math.sin(2 * math.pi * 13.0 * t + 0.4)


def bus(db):
    """Every message in time order: CabFloor at 500 Hz, EEC1, Body and an
    unknown id at 1 kHz, and one remote,
    error and CAN FD frame every 100 ms."""
    cab = db.frame_by_id(canmatrix.ArbitrationId(id=CAB_FLOOR_ID, extended=True))
    messages = []
    for k in range(SECONDS * 1000):
        t = START + k * 0.001
        if k % 2 == 0:
            # Packed here with struct: canmatrix 0.9's encode() gets signed Motorola signals
            # wrong (it wrote 0x0000FFFF for AccZ=47, AccX=-1000). Its decode() is the oracle,
            # and it must give back the raw values packed.
            raw_z = round(accz_g(k * 0.001) / 0.001)
            raw_x = (k * 37) % 2001 - 1000
            status = k % 3
            data = struct.pack(">hhB3x", raw_z, raw_x, status << 4)
            decoded = cab.decode(data)
            assert (decoded["AccZ"].raw_value, decoded["AccX"].raw_value,
                    decoded["Status"].raw_value) == (raw_z, raw_x, status), decoded
            messages.append(can.Message(timestamp=t, arbitration_id=CAB_FLOOR_ID,
                                        is_extended_id=True, data=data, channel=0))
        # EEC1, Intel: EngineSpeed in bytes 3-4 (0.125 rpm/bit), torque in byte 1 (offset -125).
        data = struct.pack("<BBBHBBB", 0, (k % 200) + 25, 0, 6400 + k % 3200, 0, 0, 0)
        messages.append(can.Message(timestamp=t + 0.0002, arbitration_id=EEC1_ID,
                                    is_extended_id=True, data=data, channel=0))
        messages.append(can.Message(timestamp=t + 0.0004, arbitration_id=BODY_ID,
                                    is_extended_id=False,
                                    data=bytes([k % 2, k % 256, (k // 256) & 0x0F, 0, 0, 0, 0, 0]),
                                    channel=0, is_rx=k % 3 != 0))
        # Traffic the DBC does not describe, of every classic length.
        messages.append(can.Message(timestamp=t + 0.0005, arbitration_id=0x124,
                                    is_extended_id=False, data=bytes(range(k % 9)), channel=0))
        if k % 100 == 50:
            messages.append(can.Message(timestamp=t + 0.0006, arbitration_id=0x321,
                                        is_extended_id=False, is_remote_frame=True, dlc=2,
                                        channel=0))
            messages.append(can.Message(timestamp=t + 0.0007, is_error_frame=True, channel=0))
            messages.append(can.Message(timestamp=t + 0.0008, arbitration_id=0x456,
                                        is_extended_id=False, is_fd=True, data=bytes(range(12)),
                                        channel=0))
    return messages


def main():
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    dbc_path = os.path.join(out, "vehicle.dbc")
    with open(dbc_path, "w", encoding="ascii") as f:
        f.write(DBC)
    db = canmatrix.formats.loadp_flat(dbc_path)
    cab = db.frame_by_id(canmatrix.ArbitrationId(id=CAB_FLOOR_ID, extended=True))
    messages = bus(db)
    for suffix in ("log", "asc", "blf", "trc"):
        path = os.path.join(out, "vehicle." + suffix)
        with can.Logger(path) as logger:
            for message in messages:
                logger.on_message_received(message)
        frames = []
        values = []
        for message in can.LogReader(path):
            if message.is_error_frame or message.is_remote_frame or message.is_fd:
                continue
            frames.append("%X %d %d %s" % (message.arbitration_id, message.is_extended_id,
                                           message.dlc, bytes(message.data).hex().upper()))
            frame = db.frame_by_id(canmatrix.ArbitrationId(id=message.arbitration_id,
                                                           extended=message.is_extended_id))
            if frame is None:
                continue
            for name, decoded in frame.decode(bytes(message.data)).items():
                values.append("%s.%s %r %r" % (frame.name, name, float(message.timestamp),
                                               float(decoded.phys_value)))
        with open(os.path.join(out, "frames-%s.txt" % suffix), "w") as f:
            f.write("\n".join(frames) + "\n")
        with open(os.path.join(out, "signals-%s.txt" % suffix), "w") as f:
            f.write("\n".join(values) + "\n")

if __name__ == "__main__":
    main()
