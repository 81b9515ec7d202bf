#!/usr/bin/env python3
"""Live fan-out through Redis, measured: two pslam-server nodes on one PostgreSQL and one Redis
(temporary, on loopback, from deploy/cluster/services.sh), pslam-agent replaying the Intel log
into node A at its real rate, one viewer on A and one on B.

A tile's latency is the time from A's viewer receiving a tile frame (tile x, y and revision) to
B's viewer receiving the same frame; A's viewer gets it as A publishes it to Redis (the same tick,
on loopback), so this is owner publish -> viewer on another node, plus A's own delivery. Only
frames both viewers received count (a viewer that falls behind gets the latest revision only).
Bytes to Redis are Redis's own counters (INFO stats) over the stream, for this one session.

Usage: tests/bench/fanout_bench.py [--scans N] [--rate X] [--particles N]
Builds nothing: needs build/bin/pslam-server and build/bin/pslam-agent. Not a test.
"""
import argparse
import base64
import json
import os
import re
import shutil
import socket
import struct
import subprocess
import sys
import tempfile
import threading
import time
import urllib.request

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
BIN = os.path.join(ROOT, "build", "bin")
SERVICES = os.path.join(ROOT, "deploy", "cluster", "services.sh")


class Viewer(threading.Thread):
    """A minimal WebSocket client on /api/sessions/{id}/live that timestamps every tile frame."""

    def __init__(self, port, session_id):
        super().__init__(daemon=True)
        self.sock = socket.create_connection(("127.0.0.1", port), timeout=30)
        key = base64.b64encode(os.urandom(16)).decode()
        self.sock.sendall((f"GET /api/sessions/{session_id}/live HTTP/1.1\r\nHost: 127.0.0.1\r\n"
                           f"Upgrade: websocket\r\nConnection: Upgrade\r\nSec-WebSocket-Key: {key}\r\n"
                           "Sec-WebSocket-Version: 13\r\n\r\n").encode())
        head = b""
        while b"\r\n\r\n" not in head:
            chunk = self.sock.recv(4096)
            if not chunk:
                raise RuntimeError("upgrade refused")
            head += chunk
        if b" 101 " not in head.split(b"\r\n", 1)[0]:
            raise RuntimeError("upgrade refused: " + head.split(b"\r\n", 1)[0].decode())
        self.buffer = head.split(b"\r\n\r\n", 1)[1]
        self.tiles = {}  # (tx, ty, revision) -> first arrival, monotonic ns
        self.messages = 0
        self.stop = False

    def read(self, n):
        while len(self.buffer) < n:
            chunk = self.sock.recv(1 << 16)
            if not chunk:
                raise EOFError
            self.buffer += chunk
        out, self.buffer = self.buffer[:n], self.buffer[n:]
        return out

    def pong(self, payload):
        mask = os.urandom(4)
        body = bytes(b ^ mask[i % 4] for i, b in enumerate(payload))
        self.sock.sendall(bytes([0x8A, 0x80 | len(payload)]) + mask + body)

    def run(self):
        message = b""
        try:
            while not self.stop:
                b0, b1 = self.read(2)
                n = b1 & 0x7F
                if n == 126:
                    n = struct.unpack("!H", self.read(2))[0]
                elif n == 127:
                    n = struct.unpack("!Q", self.read(8))[0]
                payload = self.read(n)
                opcode = b0 & 0x0F
                if opcode == 9:
                    self.pong(payload)
                    continue
                if opcode == 8:
                    return
                message += payload
                if not b0 & 0x80:
                    continue  # more fragments follow
                now = time.monotonic_ns()
                self.messages += 1
                if message[:4] == b"PSTL":
                    tx, ty = struct.unpack_from("<ii", message, 4)
                    revision = struct.unpack_from("<Q", message, 16)[0]
                    self.tiles.setdefault((tx, ty, revision), now)
                message = b""
        except (EOFError, OSError):
            return


def start_server(name, state, postgres, redis, particles):
    log = open(os.path.join(state, name + ".log"), "w")
    p = subprocess.Popen([os.path.join(BIN, "pslam-server"), "--listen", "127.0.0.1:0", "--data", os.path.join(state, name),
                          "--postgres", postgres, "--redis", redis, "--particles", str(particles)],
                         stdout=subprocess.PIPE, stderr=log, text=True)
    line = p.stdout.readline()
    m = re.search(r":(\d+)\s*$", line)
    if not m:
        raise RuntimeError(f"node {name} did not start: {line!r}")
    return p, int(m.group(1))


def redis_counters(url):
    out = subprocess.run(["redis-cli", "-u", url, "INFO", "stats"], capture_output=True, text=True, check=True).stdout
    values = dict(line.split(":", 1) for line in out.splitlines() if ":" in line)
    return int(values["total_net_input_bytes"]), int(values["total_net_output_bytes"])


def percentile(values, p):
    v = sorted(values)
    return v[min(len(v) - 1, int(round(p / 100 * (len(v) - 1))))] if v else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scans", type=int, default=1500, help="scans of the Intel log to replay (1500: ~5 min)")
    ap.add_argument("--rate", default="1", help="x real time (1)")
    ap.add_argument("--particles", type=int, default=30)
    ap.add_argument("--log", default=os.path.join(os.environ.get("PSLAM_DATA_DIR", os.path.join(ROOT, "..", "shared", "data")),
                                                   "intel", "intel.clf"))
    args = ap.parse_args()
    state = tempfile.mkdtemp(prefix="pslam-fanout-bench-")
    procs = []
    try:
        subprocess.run([SERVICES, "start", state], check=True, stdout=subprocess.DEVNULL)
        postgres = open(os.path.join(state, "postgres.url")).read().strip()
        redis = open(os.path.join(state, "redis.url")).read().strip()
        # B first: a node resumes the sessions left active at its start, so B must predate the session.
        b, port_b = start_server("b", state, postgres, redis, args.particles)
        procs.append(b)
        a, port_a = start_server("a", state, postgres, redis, args.particles)
        procs.append(a)
        in0, out0 = redis_counters(redis)
        t0 = time.monotonic()
        agent = subprocess.Popen([os.path.join(BIN, "pslam-agent"), "--server", f"127.0.0.1:{port_a}", "--source",
                                  "log:" + args.log, "--rate", args.rate, "--max-scans", str(args.scans),
                                  "--spool", os.path.join(state, "spool")],
                                 stdout=subprocess.DEVNULL, stderr=open(os.path.join(state, "agent.log"), "w"))
        procs.append(agent)
        session_id = None
        while session_id is None and time.monotonic() - t0 < 30:
            sessions = json.load(urllib.request.urlopen(f"http://127.0.0.1:{port_a}/api/sessions"))
            sessions = sessions.get("sessions", sessions) if isinstance(sessions, dict) else sessions
            session_id = next((s["id"] if "id" in s else s["session_id"] for s in sessions), None)
            time.sleep(0.05)
        if session_id is None:
            raise RuntimeError("no session on node A")
        on_a, on_b = Viewer(port_a, session_id), Viewer(port_b, session_id)
        on_a.start()
        on_b.start()
        live_since = time.monotonic_ns() + 2_000_000_000  # the tiles of the snapshots on joining do not count
        print(f"session {session_id}: {args.scans} scans of {args.log} at {args.rate}x into node A, viewers on A and B",
              file=sys.stderr)
        agent.wait()
        time.sleep(2.0)  # the last ticks reach both viewers
        seconds = time.monotonic() - t0
        in1, out1 = redis_counters(redis)
        on_a.stop = on_b.stop = True
        after = [k for k, t in on_a.tiles.items() if t > live_since]
        lat = [(on_b.tiles[k] - on_a.tiles[k]) / 1e6 for k in after if k in on_b.tiles]
        print(f"stream: {seconds:.1f} s, distinct tile frames: A {len(on_a.tiles)}, B {len(on_b.tiles)}; "
              f"of A's after joining, {len(lat)} of {len(after)} reached B")
        print(f"tile latency A viewer -> B viewer: p50 {percentile(lat, 50):.1f} ms, p95 {percentile(lat, 95):.1f} ms, "
              f"max {max(lat) if lat else float('nan'):.1f} ms")
        print(f"Redis in (publishes): {(in1 - in0) / seconds / 1024:.1f} KiB/s, out (to subscribers): "
              f"{(out1 - out0) / seconds / 1024:.1f} KiB/s, for one session")
    finally:
        for p in reversed(procs):
            if p.poll() is None:
                p.terminate()
                try:
                    p.wait(60)
                except subprocess.TimeoutExpired:
                    p.kill()
        subprocess.run([SERVICES, "stop", state], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        shutil.rmtree(state, ignore_errors=True)


if __name__ == "__main__":
    main()
