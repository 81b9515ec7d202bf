#!/usr/bin/env python3
"""Counts what survived tests/bench/chaos.sh: the agent's spool against the server's SQLite file.

Every message the agent produced got a spool sequence number (1, 2, ... for a fresh spool; it
survives restarts). The server stores it under wire seq = spool seq - seq_base (session.json). A
message is
  stored    if its wire seq is in the inputs table,
  pending   if it is not stored yet but still in the spool (the agent resends it: not lost),
  lost      otherwise: the spool dropped it (the server had acknowledged it) and it is not stored.
A duplicate is a second stored row with the same content (kind, t, pose) in the session; a
mismatch is a stored row whose content differs from the spool record of the same seq.
Usage: chaos_count.py SPOOL_DIR DATABASE MAX_ACKED   (MAX_ACKED: highest ack the agent reported)
Prints one line of key=value pairs; exits 1 if anything was lost, duplicated or mismatched.
"""
import json
import pathlib
import sqlite3
import struct
import sys


def spool_records(directory):
    """(seq, kind, t, x, y, theta) of every intact record in the spool's segment files."""
    records = {}
    for segment in sorted(pathlib.Path(directory).glob("seg-*.spool")):
        data = segment.read_bytes()
        offset = 0
        while offset + 16 <= len(data):
            length, _crc, seq = struct.unpack_from("<IIQ", data, offset)
            payload = data[offset + 16 : offset + 16 + length]
            if len(payload) < length:
                break  # a torn tail, cut off by the agent on its next start
            kind = {ord("O"): 1, ord("S"): 2}.get(payload[0])
            t, x, y, theta = struct.unpack_from("<dddd", payload, 1)
            records[seq] = (kind, t, x, y, theta)
            offset += 16 + length
    return records


def main():
    spool_dir, database, max_acked = sys.argv[1], sys.argv[2], int(sys.argv[3])
    state = json.loads((pathlib.Path(spool_dir) / "session.json").read_text())
    session, base = state["session_id"], state["seq_base"]
    on_disk = spool_records(spool_dir)
    produced = max(on_disk) if on_disk else 0  # the newest segment is always kept

    db = sqlite3.connect(database)  # the server is stopped by now
    sessions = db.execute("SELECT count(DISTINCT session_id) FROM inputs").fetchone()[0]
    rows = {seq: (kind, t, x, y, theta) for seq, kind, t, x, y, theta in
            db.execute("SELECT seq, kind, t, x, y, theta FROM inputs WHERE session_id = ?", (session,))}
    duplicates = db.execute(
        "SELECT coalesce(sum(n - 1), 0) FROM (SELECT count(*) AS n FROM inputs WHERE session_id = ? "
        "GROUP BY kind, t, x, y, theta HAVING n > 1)", (session,)).fetchone()[0]

    stored = pending = lost = mismatched = 0
    for spool_seq in range(base + 1, produced + 1):
        wire = spool_seq - base
        if wire in rows:
            stored += 1
            if spool_seq in on_disk and on_disk[spool_seq] != rows[wire]:
                mismatched += 1
        elif spool_seq in on_disk:
            pending += 1
        else:
            lost += 1
    acked_not_stored = sum(1 for wire in range(1, max_acked + 1) if wire not in rows)
    extra = sum(1 for wire in rows if wire > produced - base)  # stored rows the agent never produced

    print(f"produced={produced - base} acked={max_acked} stored={len(rows)} pending={pending} lost={lost} "
          f"acked_not_stored={acked_not_stored} duplicated={duplicates} mismatched={mismatched} "
          f"unknown_rows={extra} sessions={sessions}")
    return 1 if lost or acked_not_stored or duplicates or mismatched or extra or sessions != 1 else 0


if __name__ == "__main__":
    sys.exit(main())
