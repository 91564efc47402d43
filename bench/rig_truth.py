#!/usr/bin/env python3
"""A rig recording against the emulator's truth (docs/RELIABILITY.md).

    python3 bench/rig_truth.py GYROFLIP RUN.gfr SENT.csv

GYROFLIP is the gyroflip program (its `export` reads RUN.gfr), SENT.csv the `--log` of the
`gyroflip emulate` the recording was made from. Prints one JSON object:

  sent         DWELLs the device sent (every row of SENT.csv)
  in_file      of them, stored in RUN.gfr (a FRAME record with the same boot's number, cycle,
               position, n and code sum)
  exported     rows of `export` (each matched to the DWELL it came from by its number, cycle,
               position and value: a number restarts at each boot)
  mislabelled  exported rows whose angle is not where the table truly stood (SENT.csv's
               table_deg)
  mislabels    each of them: its boot, seq, cycle, position, exported angle, table_deg and how
               long after the dwell's end the emulator first sent it (an emulator before issue
               32's third session logged a DWELL first sent on RESEND at the angle of the table
               then, the next dwell's: docs/EMULATOR.md; a large figure here points at that)
  unlabelled   DWELLs in the file that `export` does not use (a run whose start or homing is
               not known, a step fault)
  not_in_file  DWELLs sent and not stored
  gap_missing  frames the file's GAP records count as lost
  counted      every DWELL sent is in the file or in a GAP count, boot by boot: for each of the
               device's boots (SENT.csv's `boot`; in the file, the segments between GAP reset
               records, each paired with its boot by the boot count of its first INFO record, so
               that a boot that left no trace in the file (two resets close together, a reset
               before the run started) does not shift the pairing; a segment without an INFO
               record takes the next boot in order), the DWELLs of that boot not stored <= the frames the boot's
               GAP (missing) records count, less the frames of other kinds (STATUS, ACK ...)
               the boot numbered and the file does not hold (each number from the lowest the
               file holds of the boot to the highest its stored frames or sent DWELLs reach
               that is neither stored nor a DWELL sent, less one for each INFO record after the
               boot's first frame: an INFO frame received is stored as a record, without its
               number): a GAP count that covers a lost STATUS does not cover a lost DWELL
  uncounted    DWELLs short of a GAP count, summed over the boots where they are
  boot_mismatch  stored DWELLs in a file segment other than their boot's (a reset the file
               does not record; must be 0)
  foreign      exported rows that match no DWELL sent (must be 0)
  duplicates   exported rows of a DWELL sent that an earlier row already gave (must be 0)
  time_inconsistent  exported rows whose time_s is not the run's (export's `segment`) first
               row's plus the device's clock since its start, within 2 ticks (must be 0)
  max_time_dev_s  the largest such deviation, s
  data_s       the data `export` gives: per run (its `segment`), from its first dwell's start to
               its last one's end on the device's clock (the DWELL frames' ticks), summed (what
               `record --duration` counts, docs/RECORDER.md)
  early_s      each run after the first (in time_s order) against the run before it: the true
               gap from the last dwell's end to the first dwell's start (the emulator's clock runs
               on through a reset) less the gap `export` gives; > 0: placed early (seconds)
  resets       device resets the file records (GAP reset)
  start_unacked  runs whose START ACK never reached the recorder (the START record names the
               CONFIGURE's ACK: the device showed the run, or it reset before a retry)
  stop         the reason of the file's last STOP record (1 duration, 2 signal, 3 link lost,
               4 another device, 5 device failed, 6 disk full), or null: not closed
  torn         bytes after the last whole record (a record cut short; 0 in a closed file)

Exit 0 when mislabelled, foreign, duplicates and time_inconsistent are 0 and counted; else 1.
"""
import csv
import io
import json
import struct
import subprocess
import sys

LSB_V = 5.0 / 16777216.0  # AD7739 +-2.5 V over 2^24 codes (INFO range 4)


def gfr_walk(path):
    """(offset, kind, body) of every intact record, in file order, and last the offset where
    whole records end (kind None)."""
    data = open(path, "rb").read()
    i = 16
    while i + 8 <= len(data):
        length, check = struct.unpack_from("<II", data, i)
        if length ^ 0xFFFFFFFF != check or i + 8 + length + 4 > len(data):
            break
        yield i, data[i + 8], data[i + 17 : i + 8 + length]
        i += 8 + length + 4
    yield i, None, b""


def gfr_records(path):
    """(kind, body) of every intact record, in file order."""
    for _, kind, body in gfr_walk(path):
        if kind is not None:
            yield kind, body


def whole_end(path):
    """Where the file's whole records end."""
    return [at for at, kind, _ in gfr_walk(path) if kind is None][0]


def stored_dwells(path):
    """The file's DWELL frames as (seq, cycle, position, n, code_sum), its GAP missing count,
    META's scale factor, its resets and its START records without their ACK; and per segment
    (boots in file order: the GAP reset records part them) the sequence numbers of its frames,
    its DWELL keys and its GAP missing count."""
    dwells, gap_missing, scale = set(), 0, None
    resets, start_acks, unacked = 0, set(), 0
    segments = [{"seqs": set(), "dwells": set(), "gap": 0, "infos": 0, "boot": None}]
    ticks, tick_hz = {}, None
    for kind, body in gfr_records(path):
        if kind == 2 and tick_hz is None and len(body) >= 16:
            tick_hz = struct.unpack_from("<I", body, 12)[0]  # INFO: fw 3, protocol, serial, mclk
        if kind == 6 and body[0] == 3:
            resets += 1
            start_acks = set()
            segments.append({"seqs": set(), "dwells": set(), "gap": 0, "infos": 0, "boot": None})
        elif kind == 5 and body[0] == 0x14 and body[5] == 0x22:
            start_acks.add(struct.unpack_from("<H", body, 6)[0])  # ACK of START: its at_seq
        elif kind == 4 and len(body) >= 2:
            unacked += 0 if struct.unpack_from("<H", body, 0)[0] in start_acks else 1
        if kind == 1:
            scale = json.loads(body.decode("utf-8", "replace"))["scale_factor_v_per_dps"]
        elif kind == 5 and body[0] == 0x10:
            seq = body[1] | body[2] << 8
            p = body[3:]
            cycle, position = struct.unpack_from("<IB", p, 0)
            n = struct.unpack_from("<H", p, 14)[0]
            code_sum = int.from_bytes(p[16:22], "little", signed=True)
            dwells.add((seq, cycle, position, n, code_sum))
            ticks[(seq, cycle, position, n, code_sum)] = struct.unpack_from("<II", p, 6)
            segments[-1]["dwells"].add((seq, cycle, position, n, code_sum))
        if kind == 2 and segments[-1]["boot"] is None and len(body) >= 24:
            segments[-1]["boot"] = struct.unpack_from("<H", body, 22)[0]  # INFO's boot count
        if kind == 2 and segments[-1]["seqs"]:
            segments[-1]["infos"] += 1  # an INFO frame received, stored as a record: its number
        if kind == 5 and len(body) >= 3:
            segments[-1]["seqs"].add(body[1] | body[2] << 8)
        if kind == 6 and body[0] == 2:
            gap_missing += struct.unpack_from("<I", body, 1)[0]
            segments[-1]["gap"] += struct.unpack_from("<I", body, 1)[0]
    return dwells, gap_missing, scale, resets, unacked, segments, ticks, tick_hz or 32768


def segments_by_boot(segments):
    """The file's segments merged per boot count: a segment's boot is its first INFO record's
    boot count; one without takes the boot after the previous segment's."""
    by_boot, last = {}, 0
    for seg in segments:
        boot = seg["boot"] if seg["boot"] is not None else last + 1
        last = boot
        m = by_boot.setdefault(boot, {"seqs": set(), "dwells": set(), "gap": 0, "infos": 0})
        for k in ("seqs", "dwells"):
            m[k] |= seg[k]
        for k in ("gap", "infos"):
            m[k] += seg[k]
    return by_boot


def uncounted_by_boot(sent, segments, key):
    """DWELLs sent and neither stored nor in a GAP count of their own boot (docstring: counted),
    summed over the boots; and the stored DWELLs found in another boot's segment."""
    uncounted = mismatch = 0
    by_boot = segments_by_boot(segments)
    empty = {"seqs": set(), "dwells": set(), "gap": 0, "infos": 0}
    for b in sorted({int(s["boot"]) for s in sent}):
        seg = by_boot.get(b, empty)
        mine = [s for s in sent if int(s["boot"]) == b]
        lost = [s for s in mine if key(s) not in seg["dwells"]]
        mismatch += sum(1 for s in lost
                        if any(key(s) in o["dwells"] for ob, o in by_boot.items() if ob != b))
        dwell_seqs = {int(s["seq"]) for s in mine}
        top = max(seg["seqs"] | dwell_seqs, default=-1)
        low = min(seg["seqs"], default=top + 1)
        other_lost = sum(1 for q in range(low, top + 1)
                         if q not in seg["seqs"] and q not in dwell_seqs) - seg["infos"]
        uncounted += max(0, len(lost) - max(0, seg["gap"] - other_lost))
    return uncounted, mismatch


def compare(gyroflip, gfr, sent_csv):
    sent = list(csv.DictReader(open(sent_csv)))
    dwells, gap_missing, scale, resets, unacked, segments, ticks, tick_hz = stored_dwells(gfr)
    out = subprocess.run([gyroflip, "export", gfr, "-o", "-"], capture_output=True, text=True)
    if out.returncode != 0:
        raise SystemExit(f"export {gfr}: {out.stderr}")
    rows = [l for l in out.stdout.splitlines() if not l.startswith("#")]
    exported = list(csv.DictReader(io.StringIO("\n".join(rows))))
    by_key = {}
    for s in sent:
        by_key.setdefault((int(s["seq"]), int(s["cycle"]), int(s["position"])), []).append(s)
    key = lambda s: (int(s["seq"]), int(s["cycle"]), int(s["position"]), int(s["n"]),
                     int(s["code_sum"]))
    in_file = [s for s in sent if key(s) in dwells]
    mislabelled = foreign = unlabelled_exported = 0
    mislabels = []
    spans = {}  # per run (export's segment): first dwell start, last dwell end (device ticks)
    seen, duplicates = set(), 0
    offsets, time_bad, max_dev = {}, 0, 0.0  # per run: time_s less the device clock
    ends = {}  # per run: (time_s, sent row) of its first and of its last dwell exported
    wrap_s = 2.0**32 / tick_hz
    for r in exported:
        k = (int(r["seq"]), int(r["cycle"]), int(r["position"]))
        rate = float(r["rate_dps"])
        match = [s for s in by_key.get(k, [])
                 if abs(int(s["code_sum"]) / int(s["n"]) * LSB_V / scale - rate) <=
                 1e-12 * max(1.0, abs(rate))]
        if not match:
            foreign += 1
            continue
        sent_key = (match[0]["boot"],) + key(match[0])
        duplicates += sent_key in seen
        seen.add(sent_key)
        t_s = float(r["time_s"])
        first, last = ends.get(r["segment"], ((t_s, match[0]), (t_s, match[0])))
        ends[r["segment"]] = (min(first, (t_s, match[0]), key=lambda e: e[0]),
                              max(last, (t_s, match[0]), key=lambda e: e[0]))
        off = float(r["time_s"]) - int(match[0]["t_start_ticks"]) / tick_hz
        if r["segment"] in offsets:  # the clock's 32-bit wrap is no deviation
            dev = abs((off - offsets[r["segment"]] + wrap_s / 2) % wrap_s - wrap_s / 2)
            max_dev = max(max_dev, dev)
            time_bad += dev > 2.0 / tick_hz
        else:
            offsets[r["segment"]] = off
        t = ticks.get(key(match[0]))  # the stored frame's clock: its boot's, not a namesake's
        if t is not None:
            lo, hi = spans.get(r["segment"], (t[0], t[1]))
            spans[r["segment"]] = (min(lo, t[0]), max(hi, t[1]))
        if r["angle_deg"] == "":
            unlabelled_exported += 1
        elif abs(float(r["angle_deg"]) - float(match[0]["table_deg"])) > 1e-6:
            mislabelled += 1
            m = match[0]
            mislabels.append({"boot": int(m["boot"]), "seq": int(m["seq"]),
                              "cycle": int(m["cycle"]), "position": int(m["position"]),
                              "angle_deg": float(r["angle_deg"]),
                              "table_deg": float(m["table_deg"]),
                              "first_sent_after_end_s": round(float(m["sent_time_s"]) -
                                                              int(m["t_end_ticks"]) / tick_hz, 3)})
    labelled = len(exported) - foreign - unlabelled_exported
    not_in_file = len(sent) - len(in_file)
    uncounted, boot_mismatch = uncounted_by_boot(sent, segments, key)
    data_s = sum(((hi - lo) & 0xFFFFFFFF) / tick_hz for lo, hi in spans.values())
    # Each run after the first against the run before it: the emulator's clock runs on through a
    # reset, so the true gap from the last dwell's end to the first dwell's start is known.
    placement = []
    runs = sorted(ends, key=lambda g: ends[g][0][0])
    for a, b in zip(runs, runs[1:]):
        (t_last, last), (t_first, first) = ends[a][1], ends[b][0]
        half = lambda row: ((int(row["t_end_ticks"]) - int(row["t_start_ticks"])) & 0xFFFFFFFF) / tick_hz / 2
        true_s = ((int(first["t_start_ticks"]) - int(last["t_end_ticks"])) & 0xFFFFFFFF) / tick_hz
        placed_s = (t_first - half(first)) - (t_last + half(last))
        placement.append(round(true_s - placed_s, 4))
    return {
        "sent": len(sent),
        "in_file": len(in_file),
        "exported": len(exported),
        "mislabelled": mislabelled,
        "mislabels": mislabels,
        "unlabelled": len(in_file) - labelled,
        "not_in_file": not_in_file,
        "gap_missing": gap_missing,
        "counted": uncounted == 0 and boot_mismatch == 0,
        "uncounted": uncounted,
        "boot_mismatch": boot_mismatch,
        "foreign": foreign,
        "duplicates": duplicates,
        "time_inconsistent": time_bad,
        "max_time_dev_s": round(max_dev, 6),
        "resets": resets,
        "start_unacked": unacked,
        "data_s": round(data_s, 3),
        "early_s": placement,
        "stop": stop_reason(gfr),
        "torn": torn_bytes(gfr),
    }


def stop_reason(path):
    """The reason byte of the file's last STOP record (kind 7), or None."""
    reason = None
    for kind, body in gfr_records(path):
        if kind == 7 and len(body) == 1:
            reason = body[0]
    return reason


def torn_bytes(path):
    """Bytes after the last record that reads whole (a torn tail)."""
    return len(open(path, "rb").read()) - whole_end(path)


def main():
    if len(sys.argv) != 4 or sys.argv[1] in ("-h", "--help"):
        print(__doc__)
        return 0 if len(sys.argv) == 2 else 2
    r = compare(*sys.argv[1:])
    print(json.dumps(r))
    ok = r["mislabelled"] == 0 and r["foreign"] == 0 and r["counted"]
    return 0 if ok and r["duplicates"] == 0 and r["time_inconsistent"] == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
