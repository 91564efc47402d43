#!/usr/bin/env python3
"""The board's serial as an Intel HEX file for the MSP430F149's information flash (segment B,
0x1000), the record firmware/core/nv_record.hpp reads at boot:
    'G' 'F' kind=1 version=1 serial(u32 LE) crc(u16 LE)
the CRC-16/CCITT-FALSE of the first eight bytes. The lab that builds a board writes it once
(docs/HARDWARE.md, "Bring-up"):
    python3 firmware/ports/msp430f149/board_record.py 0x0F149001 -o board.hex
    mspdebug uif -d /dev/ttyUSB0 "erase segment 0x1000" "load board.hex" "md 0x1000 16"
  usage: board_record.py SERIAL [-o FILE]   (SERIAL decimal or 0x hex, 1..4294967295)
"""
import sys

SEGMENT_B = 0x1000
KIND_BOARD_SERIAL = 1
VERSION = 1


def crc16(data):
    crc = 0xFFFF
    for b in data:
        crc ^= b << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1021) & 0xFFFF if crc & 0x8000 else (crc << 1) & 0xFFFF
    return crc


def record(serial):
    body = bytes([ord("G"), ord("F"), KIND_BOARD_SERIAL, VERSION]) + serial.to_bytes(4, "little")
    return body + crc16(body).to_bytes(2, "little")


def ihex(address, data):
    def line(kind, addr, payload):
        raw = bytes([len(payload), addr >> 8, addr & 0xFF, kind]) + payload
        return ":" + raw.hex().upper() + "%02X" % ((-sum(raw)) & 0xFF)
    return "\n".join([line(0, address, data), line(1, 0, b"")]) + "\n"


def main(argv):
    args = [a for a in argv[1:]]
    out = None
    if "-o" in args:
        i = args.index("-o")
        if i + 1 >= len(args):
            sys.exit("board_record: -o needs a file")
        out = args[i + 1]
        del args[i:i + 2]
    if len(args) != 1 or args[0] in ("-h", "--help"):
        print(__doc__.strip())
        return 0 if args and args[0] in ("-h", "--help") else 2
    try:
        serial = int(args[0], 0)
    except ValueError:
        sys.stderr.write(f"board_record: serial {args[0]!r} is not a number\n")
        return 2
    if not 1 <= serial <= 0xFFFFFFFF:
        sys.stderr.write(f"board_record: serial {serial} is outside 1..4294967295\n")
        return 2
    text = ihex(SEGMENT_B, record(serial))
    if out is None:
        sys.stdout.write(text)
    else:
        with open(out, "w") as f:
            f.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
