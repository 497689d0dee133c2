#!/usr/bin/env python3
"""Where a run's compiling goes: polls /proc every 0.4 s for compiler processes (rustc, or a
wrapper of it, with --crate-name) and, when stopped (SIGTERM or SIGINT), writes one line per
process to OUT: pid, crate, target (wasm or native), working directory, CPU seconds (its own and
its waited-for children's, such as the linker), first and last seen. A process's last fraction
of a second is not counted. docs/performance.md ("CI") sums it by tree:

    python3 tests/scripts/rustc-cpu.py /tmp/rustc.tsv & sampler=$!
    target/debug/deps/workflows-* --nocapture
    kill $sampler
"""
import os
import signal
import sys
import time

out = sys.argv[1]
tick = os.sysconf("SC_CLK_TCK")
seen = {}


def scan():
    for pid in os.listdir("/proc"):
        if not pid.isdigit():
            continue
        try:
            with open(f"/proc/{pid}/cmdline", "rb") as f:
                argv = [a.decode(errors="replace") for a in f.read().split(b"\0")]
            with open(f"/proc/{pid}/stat") as f:
                stat = f.read()
        except OSError:
            continue
        if not argv or not argv[0] or "--crate-name" not in argv:
            continue
        name = argv[argv.index("--crate-name") + 1]
        target = "wasm" if any("wasm32" in a for a in argv) else "native"
        try:
            cwd = os.readlink(f"/proc/{pid}/cwd")
        except OSError:
            cwd = "?"
        fields = stat.rsplit(")", 1)[1].split()
        cpu = sum(int(fields[i]) for i in (11, 12, 13, 14)) / tick
        key = (pid, fields[19])
        first = seen.get(key, (None, None, None, 0, time.time()))[4]
        seen[key] = (name, target, cwd, cpu, first, time.time())


def dump(*_):
    with open(out, "w") as f:
        for (pid, _), (name, target, cwd, cpu, first, last) in seen.items():
            f.write(f"{pid}\t{name}\t{target}\t{cwd}\t{cpu:.2f}\t{first:.1f}\t{last:.1f}\n")
    sys.exit(0)


signal.signal(signal.SIGTERM, dump)
signal.signal(signal.SIGINT, dump)
while True:
    scan()
    time.sleep(0.4)
