#!/usr/bin/env python3
"""A stand-in for engines/adapter.py in the tests of EngineProcess: the framing of
docs/engine-protocol.md (one JSON line, then little-endian float64 arrays) with no engine.

    fake_adapter.py MODE [N]

Modes:
  echo          replies to every request with its arrays as sent and doubled ("NAME:doubled"),
                and the request's line under "request"
  refuse        refuses "load" (error "refused"), echoes the rest
  die-after N   echoes N requests, then sends half a reply, says why on stderr and exits 7
  garbage       answers the first request with a line that is not JSON
  hang          reads requests and never replies, not even to quit
  noisy-stderr  writes 1 MB to stderr after each request's line (before its payload is read),
                then echoes

In every mode but hang: "quit" replies ok and exits 0; "error" replies an engine_error; "env"
replies {"value": $NAME} for the request's "name"; "bad-shape" replies an array of shape [-1].
The adapter exits 0 at the end of its input and 3 when it breaks off inside a message.
Standard library only.
"""
import array
import json
import os
import sys
import time

IN = sys.stdin.buffer
OUT = sys.stdout.buffer


def log(text):
    sys.stderr.write(text + "\n")
    sys.stderr.flush()


def read_exact(size):
    chunks = []
    while size > 0:
        chunk = IN.read(size)
        if not chunk:
            log("fake adapter: the input broke off inside a message")
            sys.exit(3)
        chunks.append(chunk)
        size -= len(chunk)
    return b"".join(chunks)


def count(shape):
    n = 1
    for extent in shape:
        n *= extent
    return n


def read_message(noisy):
    line = IN.readline()
    if not line:
        return None
    if not line.endswith(b"\n"):
        log("fake adapter: the input broke off inside a line")
        sys.exit(3)
    header = json.loads(line)
    if noisy:
        block = ("x" * 1023 + "\n") * 1024
        sys.stderr.write(block)
        log("noisy: the last line")
    arrays = []
    for listed in header.get("arrays", []):
        data = read_exact(8 * count(listed["shape"]))
        arrays.append((listed["name"], listed["shape"], data))
    return header, arrays


def values(data):
    a = array.array("d")
    a.frombytes(data)
    if sys.byteorder == "big":
        a.byteswap()
    return a


def payload(a):
    if sys.byteorder == "big":
        a = array.array("d", a)
        a.byteswap()
    return a.tobytes()


def send(header, arrays=(), cut=False):
    """arrays: (name, shape, bytes); cut: send half the payload only."""
    header = dict(header)
    if arrays:
        header["arrays"] = [{"name": n, "shape": s} for n, s, _ in arrays]
    body = b"".join(data for _, _, data in arrays)
    if cut:
        body = body[: len(body) // 2]
    OUT.write(json.dumps(header).encode() + b"\n" + body)
    OUT.flush()


def echo(header, arrays):
    replied = []
    for name, shape, data in arrays:
        replied.append((name, shape, data))
        doubled = array.array("d", (2 * x for x in values(data)))
        replied.append((name + ":doubled", shape, payload(doubled)))
    return {"ok": True, "op": header.get("op"), "request": header}, replied


def answer(mode, header, arrays, served):
    op = header.get("op")
    if op == "quit":
        send({"ok": True})
        sys.exit(0)
    if op == "error":
        return send({"ok": False, "error": "engine_error", "message": "ValueError: it broke"})
    if op == "env":
        return send({"ok": True, "value": os.environ.get(header["name"])})
    if op == "bad-shape":
        return send({"ok": True, "arrays": [{"name": "x", "shape": [-1]}]})
    if mode == "refuse" and op == "load":
        return send({"ok": False, "error": "refused",
                     "message": "NotImplementedError: mjSOL_PGS is unsupported."})
    if mode == "garbage":
        OUT.write(b"this is not JSON\n")
        OUT.flush()
        return None
    reply, replied = echo(header, arrays)
    if mode == "die-after" and served >= int(sys.argv[2]):
        send(reply, replied + [("padding", [1024], bytes(8 * 1024))], cut=True)
        log("Traceback (most recent call last):")
        log("RuntimeError: the fake adapter dies after %d requests" % served)
        sys.exit(7)
    return send(reply, replied)


def main():
    mode = sys.argv[1] if len(sys.argv) > 1 else "echo"
    log("fake adapter: mode " + mode)
    served = 0
    while True:
        message = read_message(mode == "noisy-stderr")
        if message is None:
            return 0
        if mode == "hang":
            while True:
                time.sleep(60)
        answer(mode, message[0], message[1], served)
        served += 1


if __name__ == "__main__":
    sys.exit(main())
