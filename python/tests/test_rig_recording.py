"""A rig recording (.gfr) read from Python (issue 32 item 2): a 3-day run on the board's
32 768 Hz clock, whose 32-bit tick counter wraps (the difference from the start passes 2^31 after
18.2 h), reads with every dwell at its time. The file is written here, byte by byte from
docs/FORMATS.md and docs/PROTOCOL.md, independently of the library's writer."""
import struct
import zlib

import gyroflip

TICK_HZ = 32768
DWELL_S = 9.0  # one dwell every 9 s: 28 800 dwells in three days
DWELLS = 28800


def record(kind, host_us, body):
    length = 9 + len(body)
    head = struct.pack("<IIBQ", length, length ^ 0xFFFFFFFF, kind, host_us) + body
    return head + struct.pack("<I", zlib.crc32(head))


def configure_payload():
    # n_avg, n_temp, settle_ms, n_positions, pos_steps[8], pos_cdeg[8], steps_per_rev,
    # step_rate_sps, start_rate_sps, ramp_sps2, filter_word, flags, flip_motor, other_motor,
    # gyro_channel, temp_channel, status_period_ms
    return struct.pack("<HBHB8h8HHHHHBBBBBBH", 256, 4, 80, 2, 0, 100, 0, 0, 0, 0, 0, 0,
                       0, 18000, 0, 0, 0, 0, 0, 0, 200, 400, 200, 2000, 94, 1, 0, 0, 0, 1, 1000)


def info_payload():
    # fw version, protocol 2, serial, mclk_hz, tick_hz, adc_revision, max_n_avg, max_raw_codes,
    # range, reset_cause, boot_count, history_bytes, board, then the configuration
    return struct.pack("<BBBBIIIBHBBBHHB", 0, 3, 0, 2, 4711, 6144000, TICK_HZ, 0, 1024, 32, 4, 1,
                       1, 400, 0) + configure_payload()


def dwell_payload(cycle, position, t_start, t_end, code):
    code_sum = (256 * code) & 0xFFFFFFFFFFFF  # i48
    return (struct.pack("<IBBIIH", cycle, position, 0, t_start, t_end, 256) +
            code_sum.to_bytes(6, "little") + (0).to_bytes(3, "little") +
            (0).to_bytes(3, "little") + struct.pack("<BiIIII", 0, 0, 0, 0, 0, 0))


def three_day_file(path):
    meta = (b'{"sensor":"synthetic","scale_factor_v_per_dps":0.0125,'
            b'"temp_v_per_c":0.0084,"temp_at_0v_c":24.85}')
    out = bytearray(b"\x89GFR\r\n\x1a\n" + struct.pack("<HH", 4, 0))
    out += struct.pack("<I", zlib.crc32(bytes(out)))
    out += record(1, 0, meta)
    out += record(2, 1, info_payload())
    out += record(3, 2, configure_payload())
    out += record(4, 3, struct.pack("<H", 0))  # START after frame 0, of format 2 (no CRC)
    first = 0xFFFFFFFF - 10 * TICK_HZ  # the counter wraps 10 s in
    truth = []
    for k in range(DWELLS):
        start = (first + round(k * DWELL_S * TICK_HZ)) & 0xFFFFFFFF
        end = (start + round(0.6 * DWELL_S * TICK_HZ)) & 0xFFFFFFFF
        seq = (k + 1) & 0xFFFF
        body = struct.pack("<BH", 0x10, seq) + dwell_payload(k // 2, k % 2, start, end, 100 + k % 7)
        out += record(5, 10 + k, body)
        truth.append((k * DWELL_S + 0.3 * DWELL_S, 0.0 if k % 2 == 0 else 180.0))
    out += record(7, 10 + DWELLS, bytes([1]))
    with open(path, "wb") as f:
        f.write(out)
    return truth


def test_a_three_day_run_reads_on_the_devices_clock(tmp_path):
    path = tmp_path / "three_days.gfr"
    truth = three_day_file(path)
    rec = gyroflip.read_recording(str(path))
    assert len(rec["time_s"]) == DWELLS
    for k in (0, 1, 8000, 14000, DWELLS - 1):  # 14 000 dwells: 35 h, past the 2^31 ticks
        assert abs(rec["time_s"][k] - truth[k][0]) < 2.0 / TICK_HZ, k
        assert rec["angle_deg"][k] == truth[k][1]
    steps = rec["time_s"][1:] - rec["time_s"][:-1]
    assert abs(steps.min() - DWELL_S) < 1e-3 and abs(steps.max() - DWELL_S) < 1e-3
    assert rec["time_s"][-1] > 3 * 86400 - 10
