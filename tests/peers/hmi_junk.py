#!/usr/bin/python3
"""Junk for the web HMI at a steady rate, to measure the scan's timing under a flood.

  hmi_junk.py ADDR RATE SECONDS

Sends RATE requests per second for SECONDS, each on a new connection, cycling through: no token,
a foreign Host, a foreign Origin on a force, a body over the limit, a malformed request line, an
unknown path, a WebSocket upgrade without token, a valid-looking token that is wrong. Prints one
JSON line: how many were sent and the status codes seen.
"""
import json, socket, sys, threading, time
from collections import Counter

JUNK = [
    "GET /api/status HTTP/1.1\r\nHost: {a}\r\n\r\n",
    "GET /api/status HTTP/1.1\r\nHost: attacker.example\r\n\r\n",
    "POST /api/force HTTP/1.1\r\nHost: {a}\r\nOrigin: http://attacker.example\r\nContent-Length: 27\r\n\r\n"
    '{{"signal":"I0A3","value":1}}',
    "POST /api/write HTTP/1.1\r\nHost: {a}\r\nContent-Length: 100000\r\n\r\n" + "x" * 1000,
    "GARBAGE \x00\x01\x02 nothing\r\n\r\n",
    "GET /%2e%2e/%2e%2e/etc/passwd HTTP/1.1\r\nHost: {a}\r\n\r\n",
    "GET /ws HTTP/1.1\r\nHost: {a}\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
    "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n",
    "GET /api/status HTTP/1.1\r\nHost: {a}\r\nAuthorization: Bearer wrong-token-0123456789\r\n\r\n",
]


def one(addr, text, seen, lock):
    host, port = addr.rsplit(":", 1)
    try:
        with socket.create_connection((host, int(port)), timeout=2) as s:
            s.sendall(text.format(a=addr).encode("latin-1"))
            s.shutdown(socket.SHUT_WR)
            head = s.recv(64).decode("latin-1", "replace")
        code = head.split(" ")[1] if head.startswith("HTTP/1.1 ") else "closed"
    except OSError as e:
        code = type(e).__name__
    with lock:
        seen[code] += 1


def main(addr, rate, seconds):
    seen, lock = Counter(), threading.Lock()
    start, sent = time.monotonic(), 0
    while time.monotonic() - start < seconds:
        due = start + sent / rate
        now = time.monotonic()
        if due > now:
            time.sleep(due - now)
        threading.Thread(target=one, args=(addr, JUNK[sent % len(JUNK)], seen, lock), daemon=True).start()
        sent += 1
    time.sleep(2)
    print(json.dumps({"sent": sent, "seconds": seconds, "codes": dict(seen)}, sort_keys=True), flush=True)


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    main(sys.argv[1], float(sys.argv[2]), float(sys.argv[3]))
