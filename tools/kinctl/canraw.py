# SPDX-License-Identifier: BSD-3-Clause
"""Reading a SocketCAN interface through a raw socket: one place for the
receive side of `kinctl candecode --interface`, the vcan suite and the CAN
benchmark.

Each socket gets a large receive buffer (SO_RCVBUFFORCE when root, else as
much SO_RCVBUF as the system allows), the kernel's receive timestamp of
every frame (SO_TIMESTAMPNS: CLOCK_REALTIME in ns; on vcan the moment the
frame was sent) and the count of frames the kernel dropped at this socket's
full queue (SO_RXQ_OVFL). Error frames and extended or remote frames are
skipped: kinctl sends and reads none of them.

A frame costs one system call: the socket blocks, and the kernel's own
receive timeout (SO_RCVTIMEO) ends a wait, not a poll before every read
(in User Mode Linux, where a system call is dear, a reader of every frame
of a 100 Hz bus cycle spent 40-50 % of the CPU with the polls, 2-6 %
without).
"""
import errno
import socket
import struct
import threading
import time

FRAME = struct.Struct("=IB3x8s")  # struct can_frame
CAN_ERR_FLAG, CAN_EFF_FLAG, CAN_RTR_FLAG = 0x20000000, 0x80000000, 0x40000000
SO_RCVBUFFORCE = 33
SO_TIMESTAMPNS = 35
SO_RXQ_OVFL = 40


def size_receive_buffer(s, nbytes):
    """A reader that falls behind loses frames at its own socket: a large
    queue (beyond rmem_max when root)."""
    try:
        s.setsockopt(socket.SOL_SOCKET, SO_RCVBUFFORCE, nbytes)
    except OSError:
        s.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, nbytes)


def receive_timeout(s, timeout):
    """A read on blocking socket s ends after timeout s with EAGAIN
    (SO_RCVTIMEO), with no poll of its own."""
    usec = max(1, int(round(timeout * 1e6)))
    s.setsockopt(socket.SOL_SOCKET, socket.SO_RCVTIMEO, struct.pack("ll", usec // 1_000_000, usec % 1_000_000))


def timed_out(error):
    """True when error is a read's SO_RCVTIMEO or a Python timeout."""
    return isinstance(error, socket.timeout) or getattr(error, "errno", None) in (errno.EAGAIN, errno.EWOULDBLOCK)


def open_raw(interface, rcvbuf=8 << 20, timeout=0.2):
    """A CAN_RAW socket bound to interface (OSError when it cannot be),
    whose reads wait at most timeout s."""
    s = socket.socket(socket.AF_CAN, socket.SOCK_RAW, socket.CAN_RAW)
    try:
        size_receive_buffer(s, rcvbuf)
        s.setsockopt(socket.SOL_SOCKET, SO_TIMESTAMPNS, 1)
        s.setsockopt(socket.SOL_SOCKET, SO_RXQ_OVFL, 1)
        s.bind((interface,))
        receive_timeout(s, timeout)
    except OSError:
        s.close()
        raise
    return s


def receive(s):
    """The next frame as (t_ns, id, data, dropped): dropped is the socket's
    running count of frames the kernel could not queue. None on the
    socket's timeout or for a frame kinctl does not use. OSError when the
    interface is down."""
    try:
        raw, anc, _, _ = s.recvmsg(FRAME.size, 64)
    except OSError as e:
        if timed_out(e):
            return None
        raise
    t, dropped = None, 0
    for level, kind, value in anc:
        if level == socket.SOL_SOCKET and kind == SO_TIMESTAMPNS:
            sec, nsec = struct.unpack("qq", value[:16])
            t = sec * 1_000_000_000 + nsec
        elif level == socket.SOL_SOCKET and kind == SO_RXQ_OVFL:
            dropped = struct.unpack("I", value[:4])[0]
    if t is None:
        t = time.time_ns()
    can_id, dlc, data = FRAME.unpack(raw)
    if can_id & (CAN_ERR_FLAG | CAN_EFF_FLAG | CAN_RTR_FLAG):
        return None
    return t, can_id, bytes(data[:dlc]), dropped


class FrameRecorder:
    """Every frame on an interface, (t_ns, id, data) in order of arrival,
    kept by a thread from construction to close(). An interface that goes
    down is waited for; `lost` counts the frames the kernel dropped at this
    reader's queue."""

    def __init__(self, interface, rcvbuf=8 << 20):
        self.sock = open_raw(interface, rcvbuf, timeout=0.1)
        self.frames = []
        self.lost = 0
        self.lock = threading.Lock()
        self.running = True
        self.thread = threading.Thread(target=self._loop, daemon=True)
        self.thread.start()

    def _loop(self):
        while self.running:
            try:
                got = receive(self.sock)
            except OSError:
                time.sleep(0.02)  # the interface is down
                continue
            if got is not None:
                with self.lock:
                    self.frames.append(got[:3])
                    self.lost = got[3]

    def settle(self, quiet_s=0.3, longest_s=5.0, counted=None):
        """The frames so far, once no frame that counted(id) accepts (every
        frame by default) has arrived for quiet_s, the reader having caught up
        with the bus, or after longest_s."""
        n, since, start = -1, time.monotonic(), time.monotonic()
        while time.monotonic() - since < quiet_s and time.monotonic() - start < longest_s:
            with self.lock:
                m = len(self.frames) if counted is None else sum(1 for f in self.frames if counted(f[1]))
            if m != n:
                n, since = m, time.monotonic()
            time.sleep(0.02)
        with self.lock:
            return list(self.frames)

    def close(self):
        self.running = False
        self.thread.join(2)
        self.sock.close()
