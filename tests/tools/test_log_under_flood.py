# SPDX-License-Identifier: BSD-3-Clause
"""`kinctl log` and `kinctl record` share the network with kinctld: under
the floods that kinctld shrugs off (forged LCM fragments claiming 256 MiB,
garbage on its channels) they keep every setpoint, or say exactly how many
they lost and from which cycles (kinctl.cycles). Checked against what they
wrote: the CSV's and the LCM log's own cycle numbers. And the counter itself
on made-up sequences."""
import csv
import random
import re
import socket
import subprocess
import sys
import threading

from kinctl.cycles import CycleCount
from kinctl.eventlog import read_events
from kinctl_testing import SLOW, flood_fragments, setpoint_t


def test_cycle_count_names_every_gap():
    t = iter(range(100, 200))
    c = CycleCount(clock=lambda: float(next(t)))
    for cycle in [5, 6, 7, 10, 11, 15, 16]:
        c.add(cycle)
    assert (c.count, c.first, c.last, c.span, c.missing) == (7, 5, 16, 12, 5)
    assert [(g[0], g[1]) for g in c.gaps] == [(8, 2), (12, 3)]
    assert c.report().startswith("cycles 5..16: 5 missing in 2 gaps: 2 from cycle 8 (seen ")
    assert "3 from cycle 12" in c.report()
    clean = CycleCount()
    for cycle in range(40, 50):
        clean.add(cycle)
    assert clean.report() == "cycles 40..49: none missing"
    many = CycleCount()
    for cycle in range(0, 40, 2):
        many.add(cycle)
    assert many.missing == 19 and "and 14 more gaps" in many.report()


def garbage(url, prefix, count, seed=3):
    m = re.match(r"udpm://([\d.]+):(\d+)", url)
    rnd = random.Random(seed)
    s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    s.setsockopt(socket.IPPROTO_IP, socket.IP_MULTICAST_TTL, 0)
    for i in range(count):
        head = b"LC02" + i.to_bytes(4, "big") + (prefix + "SETPOINT").encode() + b"\0"
        s.sendto(head + bytes(rnd.randrange(256) for _ in range(rnd.randrange(1, 600))),
                 (m.group(1), int(m.group(2))))
    s.close()


def floods(d):
    """Forged fragments and garbage (some of it on the setpoint channel)."""
    t1 = threading.Thread(target=flood_fragments, args=(d.url, "KINCTL_", 6000))
    t2 = threading.Thread(target=garbage, args=(d.url, "KINCTL_", 3000))
    return t1, t2


def check_report(report, cycles):
    """The report's figures are the file's: first and last cycle, and the
    missing count (none, or exactly how many)."""
    m = re.search(r"cycles (\d+)\.\.(\d+): (none missing|(\d+) missing in (\d+) gaps)", report)
    assert m, report
    assert (int(m.group(1)), int(m.group(2))) == (cycles[0], cycles[-1]), report
    missing = sum(b - a - 1 for a, b in zip(cycles, cycles[1:]))
    gaps = sum(1 for a, b in zip(cycles, cycles[1:]) if b != a + 1)
    if m.group(3) == "none missing":
        assert missing == 0
    else:
        assert (int(m.group(4)), int(m.group(5))) == (missing, gaps), report


def test_log_under_floods_keeps_or_counts_every_setpoint(daemon, tmp_path):
    d = daemon()
    path = tmp_path / "log.csv"
    log = subprocess.Popen([sys.executable, "-m", "kinctl", "--lcm-url", d.url, "log", "--csv", str(path),
                            "--duration", "4"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    for t in floods(d):
        t.start()
        t.join()
    out, err = log.communicate(timeout=60 * SLOW)
    assert log.returncode == 0, err
    with open(path, newline="") as f:
        cycles = [int(r[1]) for r in list(csv.reader(f))[1:]]
    assert len(cycles) > 1000
    check_report(out, cycles)


def test_record_under_floods_keeps_or_counts_every_setpoint(daemon, tmp_path):
    d = daemon()
    path = tmp_path / "run.lcmlog"
    rec = subprocess.Popen([sys.executable, "-m", "kinctl", "--lcm-url", d.url, "record", str(path),
                            "--duration", "4"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    for t in floods(d):
        t.start()
        t.join()
    out, err = rec.communicate(timeout=60 * SLOW)
    assert rec.returncode == 0, err
    cycles = []
    for _, channel, data in read_events(str(path)):
        if channel == "KINCTL_SETPOINT":
            try:
                cycles.append(setpoint_t.decode(data).cycle)
            except ValueError:  # the flood's garbage, recorded as it came
                pass
    assert len(cycles) > 1000
    check_report(out, cycles)
