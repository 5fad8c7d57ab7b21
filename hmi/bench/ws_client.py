#!/usr/bin/env python3
"""A WebSocket client of the ncplc HMI that reads `/ws` at a fixed rate (default 20 Hz), for the
cost measurement in the README ("the HMI open at 20 Hz costs the scan <= 5 %").

Usage: ws_client.py HOST:PORT [--hz 20] [--seconds N]

Standard library only: the HTTP upgrade, then one frame read every 1/hz s. With --ack the client
acknowledges each frame as the page does and the server sends the latest snapshot only then, so
the client skips snapshots; without it the server pushes every snapshot (up to 40 Hz) and a slower
reader falls behind by what the socket buffers hold. Prints the frames
read, the bytes and the last tick seen. Exits 0 when the server closes the connection or on SIGTERM.
"""

import argparse
import base64
import json
import os
import signal
import socket
import sys
import time


def read_exact(sock, n):
    buf = b""
    while len(buf) < n:
        chunk = sock.recv(n - len(buf))
        if not chunk:
            raise EOFError
        buf += chunk
    return buf


def read_frame(sock):
    """One frame: (opcode, payload); server frames are not masked."""
    b0, b1 = read_exact(sock, 2)
    n = b1 & 0x7F
    if n == 126:
        n = int.from_bytes(read_exact(sock, 2), "big")
    elif n == 127:
        n = int.from_bytes(read_exact(sock, 8), "big")
    if b1 & 0x80:
        read_exact(sock, 4)
    return b0 & 0x0F, read_exact(sock, n)


def send_text(sock, data):
    """One masked text frame (clients must mask)."""
    mask = os.urandom(4)
    body = bytes(b ^ mask[i % 4] for i, b in enumerate(data))
    sock.sendall(bytes([0x81, 0x80 | len(data)]) + mask + body)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("addr")
    ap.add_argument("--hz", type=float, default=20.0)
    ap.add_argument("--seconds", type=float, default=0.0, help="0: until the server closes")
    ap.add_argument("--ack", action="store_true", help="paced: acknowledge each frame (as the page does)")
    a = ap.parse_args()
    host, port = a.addr.rsplit(":", 1)
    deadline = time.monotonic() + a.seconds if a.seconds > 0 else None
    while True:
        try:
            sock = socket.create_connection((host, int(port)))
            break
        except OSError:
            if deadline and time.monotonic() > deadline:
                sys.exit("no HMI at " + a.addr)
            time.sleep(0.05)
    key = base64.b64encode(os.urandom(16)).decode()
    sock.sendall(
        (
            f"GET /ws{'?ack=1' if a.ack else ''} HTTP/1.1\r\nHost: {a.addr}\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
            f"Sec-WebSocket-Key: {key}\r\nSec-WebSocket-Version: 13\r\n\r\n"
        ).encode()
    )
    head = b""
    while b"\r\n\r\n" not in head:
        head += read_exact(sock, 1)
    if b" 101 " not in head.split(b"\r\n")[0]:
        sys.exit("no upgrade: " + head.decode(errors="replace"))
    frames, size, tick = 0, 0, None

    def stop(*_):
        raise EOFError

    signal.signal(signal.SIGTERM, stop)
    period = 1.0 / a.hz
    next_read = time.monotonic()
    try:
        while deadline is None or time.monotonic() < deadline:
            op, payload = read_frame(sock)
            if op == 8:
                break
            if op == 1:
                frames += 1
                size += len(payload)
                tick = json.loads(payload).get("tick")
                if a.ack:
                    send_text(sock, b"ack")
            next_read += period
            time.sleep(max(0.0, next_read - time.monotonic()))
    except (EOFError, ConnectionError):
        pass
    print(f"ws_client: {frames} frames, {size} bytes, last tick {tick}")


if __name__ == "__main__":
    main()
