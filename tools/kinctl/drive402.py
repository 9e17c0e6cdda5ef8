# SPDX-License-Identifier: BSD-3-Clause
"""CiA 402 drives in cyclic synchronous position on a real CANopen stack.

Each drive is a python `canopen` LocalNode made from an EDS (by default
data/kinctl-drive.eds beside this file): the stack gives the SDO server, the
NMT slave with its heartbeat producer (0x1017) and the EMCY producer. What
LocalNode does not do, this module does, as CiA 301 and CiA 402 say and as
CANopenNode-based firmware behaves:

  - NMT: boot-up (0x700 + node, 00) into pre-operational at start and after
    reset node / reset communication (which also bring the communication
    objects 0x1000..0x1FFF, and for reset node every object, back to the
    EDS's defaults); PDOs only in operational.
  - SYNC (0x080, COB-ID 0x1005): a SYNC whose length disagrees with 0x1019
    (0: empty, else one counter byte) is not processed and raises EMCY 0x8240
    (as CANopenNode's CO_SYNC). 0x1019 takes 0 or 2..240, and only while the
    communication cycle period 0x1006 is 0 (CiA 301; abort 0x08000022, as
    CANopenNode): a master writes 0x1019 before 0x1006 (0 at power-on and
    after a reset communication). At each SYNC the RPDOs received since the
    last one are applied (synchronous RPDOs, transmission type 0..240), the
    drive moves, and each valid TPDO of transmission type N (1..240) is
    sent at every N-th SYNC, type 0 when its data changed; 254/255 whenever
    its data changed (checked at each SYNC and after each controlword).
  - RPDOs (COB-IDs from 0x1400.., mapping 0x1600..): one shorter than its
    mapping raises EMCY 0x8210, one longer EMCY 0x8220, and is not taken.
  - PDO mapping per CiA 301: 0x1600../0x1A00.. entries only while the PDO is
    invalid (COB-ID bit 31) and sub 0 is 0; sub 0 = n checks that every
    entry exists, is mappable and that they fit 64 bits (abort 0x06040041,
    0x06040042); a valid PDO's COB-ID may only be made invalid (0x06090030).
  - CiA 402 power state machine driven by the controlword (0x6040) alone:
    not ready to switch on, then switch on disabled; shutdown 0x06, switch
    on 0x07, enable operation 0x0F, disable voltage (bit 1 clear), quick
    stop (bit 2 clear; 0x605A 0..4: switch on disabled once stopped, 5..8:
    stay in quick stop active), fault reset on bit 7's rising edge.
    Statusword 0x6041 per the standard's masks, bit 4 voltage enabled, bit 5
    quick stop (set: not active), bit 9 remote, bit 12 in CSP (0x6060 = 8)
    and operation enabled: the drive follows the target, bit 13 following
    error beyond 0x6065. 0x6060 takes only the modes in 0x6502 (CSP).
  - Motion: in operation enabled and mode 8 the actual position (0x6064)
    goes to the target (0x607A) at each SYNC: exactly, or a first-order lag
    of lag_s (the interpolation period 0x60C2 the step). Elsewhere it stays;
    the target follows the actual position while not enabled, so that
    enabling never jumps. A target beyond the software position limits
    (0x607D, where min <= max) is held at the limit, with statusword bit 11
    (internal limit active). The velocity offset (0x60B1, in RPDO2 where
    mapped) is taken and read back, not acted on; 0x1006 (the SYNC period)
    is kept, not watched: a Python process on a loaded machine cannot time
    a 1 ms SYNC without false alarms.
  - Heartbeat consumer 0x1016 (node << 16 | ms): once a watched node's
    heartbeat has been seen, its silence longer than the time is a lost
    master: EMCY 0x8130, then 0x6007's reaction (0 none, 1 fault 0x8130,
    2 disable voltage, 3 quick stop). The silence is timed from the
    heartbeat's receive timestamp and judged only while no received frame
    waits in the socket, so a stall of this process is not taken for one
    of the master.
  - Faults on command: state fault, 0x603F and error register 0x1001 set,
    EMCY with the code; a fault reset clears them and sends EMCY 0x0000.

Power-on values (what the drive's non-volatile memory holds: the EDS's
defaults, or Drives' presets for the period, heartbeat, following-error
window and, with configured=True, the PDOs and mode kinctld's boot writes,
so a master that does not configure the drives (kinctld's `boot = false`)
finds them ready) come back at each reset.

Control (stdin of `kinctl drivesim`, or Drives.command): one command a line,
answered "ok <command>" once applied, or "error <why>":
    fault N [CODE]     node N faults with CODE (hex or decimal; 0x5530)
    silent N | talk N  node N stops or resumes sending anything
    lag N SECONDS      node N's first-order lag (0: none)
    reboot N           node N resets itself (boot-up, pre-operational)
    preop N            node N enters pre-operational on its own, as CiA 301's
                       0x1029 has a drive do on a communication error: no
                       PDO sent or taken until an NMT start
    state N            answers "ok state N <nmt> <cia402 state> <statusword hex> <actual>"
    quit
"""
import os
import select
import sys
import threading
import time

NMT_INITIALISING, NMT_STOPPED, NMT_OPERATIONAL, NMT_PRE_OPERATIONAL = 0x00, 0x04, 0x05, 0x7F
# The control lines (above), for a usage message.
CONTROL_USAGE = "fault N [CODE], silent/talk/reboot/preop/state N, lag N S, quit"
EMCY_HEARTBEAT = 0x8130
EMCY_PDO_LENGTH = 0x8210
EMCY_PDO_LENGTH_EXCEEDED = 0x8220
EMCY_SYNC_LENGTH = 0x8240
EMCY_DEFAULT_FAULT = 0x5530
ERROR_REGISTER_GENERIC = 0x01
ERROR_REGISTER_COMMUNICATION = 0x10
MODE_CSP = 8
SUPPORTED_MODE_BITS = {MODE_CSP: 1 << 7}

# CiA 402 states and their statusword bits 0-3, 5, 6 (the masks' values).
NOT_READY, SWITCH_ON_DISABLED, READY, SWITCHED_ON, ENABLED, QUICK_STOP, FAULT_REACTION, FAULT = (
    "not ready to switch on", "switch on disabled", "ready to switch on", "switched on", "operation enabled",
    "quick stop active", "fault reaction active", "fault")
STATE_BITS = {NOT_READY: 0x0000, SWITCH_ON_DISABLED: 0x0040, READY: 0x0021, SWITCHED_ON: 0x0023, ENABLED: 0x0027,
              QUICK_STOP: 0x0007, FAULT_REACTION: 0x000F, FAULT: 0x0008}
SW_VOLTAGE_ENABLED = 1 << 4
SW_QUICK_STOP = 1 << 5
SW_REMOTE = 1 << 9
SW_INTERNAL_LIMIT = 1 << 11
SW_TARGET_FOLLOWED = 1 << 12
SW_FOLLOWING_ERROR = 1 << 13


def default_eds():
    return os.path.join(os.path.dirname(os.path.abspath(__file__)), "data", "kinctl-drive.eds")


def interpolation_period(period_s):
    """0x60C2's (value, index): period_s = value x 10^index, value 1..255,
    the largest index that holds it exactly to the microsecond; ValueError
    for a period it cannot hold."""
    us = int(round(period_s * 1e6))
    for index in (-3, -4, -5, -6):
        unit = 10 ** (6 + index)  # microseconds per count
        if us % unit == 0 and 1 <= us // unit <= 255:
            return us // unit, index
    raise ValueError(f"period {period_s} s: 0x60C2 holds 1..255 x 10^-3..10^-6 s")


def presets(node_id, period_s=None, heartbeat_ms=None, window=None, configured=False):
    """{(index, subindex): power-on value} of a drive at node_id: the
    interpolation period 0x60C2, the heartbeat
    producer 0x1017, the following-error window 0x6065 where given; with
    configured, what kinctld's boot writes with its defaults (RPDO1 the
    controlword and target position, TPDO1 the statusword and actual
    position, both synchronous every SYNC; mode 8)."""
    out = {}
    if period_s is not None:
        value, index = interpolation_period(period_s)
        out.update({(0x60C2, 1): value, (0x60C2, 2): index})
    if heartbeat_ms is not None:
        out[(0x1017, 0)] = int(heartbeat_ms)
    if window is not None:
        out[(0x6065, 0)] = int(window)
    if configured:
        out.update({(0x1400, 1): 0x200 + node_id, (0x1400, 2): 1,
                    (0x1600, 0): 2, (0x1600, 1): 0x60400010, (0x1600, 2): 0x607A0020,
                    (0x1800, 1): 0x180 + node_id, (0x1800, 2): 1,
                    (0x1A00, 0): 2, (0x1A00, 1): 0x60410010, (0x1A00, 2): 0x60640020,
                    (0x6060, 0): MODE_CSP})
    return out


def next_state(state, cw, prev_cw, quick_stop_option):
    """The CiA 402 transition a controlword makes from state (CiA 402-2,
    device control commands); prev_cw for bit 7's rising edge."""
    c = cw & 0x8F
    if state == FAULT:
        return SWITCH_ON_DISABLED if (cw & 0x80) and not (prev_cw & 0x80) else FAULT
    if state in (NOT_READY, FAULT_REACTION):
        return state
    disable_voltage = not (c & 0x02)
    quick_stop = (c & 0x06) == 0x02
    shutdown = (c & 0x87) == 0x06
    switch_on = (c & 0x8F) == 0x07
    enable = (c & 0x8F) == 0x0F
    if state == SWITCH_ON_DISABLED:
        return READY if shutdown else state
    if state == READY:
        if switch_on or enable:  # 3; enable operation here: 3 now, 4 at the next controlword
            return SWITCHED_ON
        return SWITCH_ON_DISABLED if disable_voltage or quick_stop else state
    if state == SWITCHED_ON:
        if enable:
            return ENABLED
        if shutdown:
            return READY
        return SWITCH_ON_DISABLED if disable_voltage or quick_stop else state
    if state == ENABLED:
        if quick_stop:
            return QUICK_STOP if quick_stop_option != 0 else SWITCH_ON_DISABLED
        if disable_voltage:
            return SWITCH_ON_DISABLED
        if shutdown:
            return READY
        if switch_on:
            return SWITCHED_ON
        return state
    if state == QUICK_STOP:
        if disable_voltage:
            return SWITCH_ON_DISABLED
        if enable and quick_stop_option >= 5:
            return ENABLED  # 16, where the option keeps quick stop active
        return state
    return state


class Drive:
    """One CiA 402 node on a canopen.Network; its callbacks run on the
    network's receive thread, commands under Drives' lock."""

    def __init__(self, network, node_id, eds, start_counts, lag_s=0.0, power_on=None):
        import canopen
        self._cache = {}
        self.network = network
        self.id = node_id
        self.eds = eds
        od = canopen.import_od(eds, node_id)
        for (index, sub), value in (power_on or {}).items():
            obj = od[index]
            (obj[sub] if hasattr(obj, "subindices") and obj.subindices else obj).default = value
        self.node = canopen.LocalNode(node_id, od)
        self.node.add_read_callback(self._on_read)
        self.node.add_write_callback(self._on_write)
        network.add_node(self.node)
        self.start_counts = int(start_counts)
        self.lag_s = lag_s
        self.silent = False
        self.pos = float(start_counts)
        self.limited = False  # the target is beyond 0x607D: the demand is the limit
        self.sync_count = 0
        self.events = []  # (what, detail) for tests and the log: emcy, sync_error, ...
        self._reset_application()
        self._reset_communication()

    # -- object dictionary ----------------------------------------------------
    def od(self, index, sub=0):
        """The value of index:sub as the SDO server answers it."""
        obj = self.node.object_dictionary[index]
        if not hasattr(obj, "subindices") or not obj.subindices:
            return obj.decode_raw(self.node.get_data(index, sub))
        return obj[sub].decode_raw(self.node.get_data(index, sub))

    def opt(self, index, sub, default):
        """od(index, sub), or default where the EDS has no such object (an
        EDS without the optional objects this drive honours)."""
        obj = self.node.object_dictionary.get(index)
        if obj is None or (hasattr(obj, "subindices") and obj.subindices and sub not in obj.subindices):
            return default
        return self.od(index, sub)

    def _store(self, index, sub, value):
        obj = self.node.object_dictionary[index]
        var = obj[sub] if hasattr(obj, "subindices") and obj.subindices else obj
        self.node.data_store.setdefault(index, {})[sub] = var.encode_raw(value)

    def _reset_application(self):
        for index in [i for i in self.node.data_store if i >= 0x2000]:
            del self.node.data_store[index]
        self.state = NOT_READY
        self.cw = 0
        self.target = int(round(self.pos))
        self.vel_offset = 0
        self.fault_code = 0
        self.error_register = 0
        self.state = SWITCH_ON_DISABLED  # not ready to switch on passes at once

    def cached(self, key, compute):
        """compute() once until the dictionary changes (an SDO write, an
        RPDO into the dictionary, a reset): the PDO layout and the settings
        read at every SYNC."""
        if key not in self._cache:
            self._cache[key] = compute()
        return self._cache[key]

    def _reset_communication(self):
        self._cache = {}
        for index in [i for i in self.node.data_store if 0x1000 <= i < 0x2000]:
            del self.node.data_store[index]
        self.pending = {}  # RPDO number -> data received since the last SYNC
        self.tpdo_last = {}
        self.heard = {}  # watched node -> its last heartbeat's receive timestamp (s, the bus's clock)
        self.master_lost = False
        self.emcy_sent = set()
        self.sync_count = 0

    def _on_read(self, index, subindex, od):
        live = {0x6041: self.statusword, 0x6064: lambda: int(round(self.pos)), 0x603F: lambda: self.fault_code,
                0x1001: lambda: self.error_register, 0x6061: lambda: self.od(0x6060)}
        if index in live and subindex == 0:
            return live[index]()
        if index == 0x6040:
            return self.cw
        if index == 0x607A:
            return self.target
        if index == 0x60B1:
            return self.vel_offset
        return None

    def _on_write(self, index, subindex, od, data):
        from canopen.sdo import SdoAbortedError
        self._cache = {}  # stored after this returns: computed again then
        value = od.decode_raw(data)
        if 0x1600 <= index < 0x1800 or 0x1A00 <= index < 0x1C00:
            comm = index - 0x200
            if self.od(comm, 1) & 0x80000000 == 0:
                raise SdoAbortedError(0x06010000)  # the PDO is valid: no remapping
            if subindex > 0 and self.od(index, 0) != 0:
                raise SdoAbortedError(0x06010000)
            if subindex == 0:
                if value > 8:
                    raise SdoAbortedError(0x06090031)
                bits = 0
                for s in range(1, value + 1):
                    entry = self.od(index, s)
                    obj = self._mappable(entry)
                    if obj is None:
                        raise SdoAbortedError(0x06040041)
                    bits += entry & 0xFF
                if bits > 64:
                    raise SdoAbortedError(0x06040042)
        elif (0x1400 <= index < 0x1600 or 0x1800 <= index < 0x1A00) and subindex == 1:
            old = self.od(index, 1)
            if old & 0x80000000 == 0 and value & 0x80000000 == 0 and value & 0x7FF != old & 0x7FF:
                raise SdoAbortedError(0x06090030)
        elif index == 0x6060:
            if SUPPORTED_MODE_BITS.get(value, 0) & self.opt(0x6502, 0, SUPPORTED_MODE_BITS[MODE_CSP]) == 0:
                raise SdoAbortedError(0x06090030)
        elif index == 0x1019:
            if value == 1 or value > 240:
                raise SdoAbortedError(0x06090030)
            if self.opt(0x1006, 0, 0) != 0:
                raise SdoAbortedError(0x08000022)  # CiA 301: only while 0x1006 is 0
        else:
            self._act_on(index, value)

    def _act_on(self, index, value):
        """What the drive does when one of the objects it acts on is written
        (by SDO or by RPDO): the controlword, the target position, the
        velocity offset. False for any other object."""
        if index == 0x6040:
            self._controlword(value)
        elif index == 0x607A:
            self.target = value
        elif index == 0x60B1:
            self.vel_offset = value
        else:
            return False
        return True

    def _mappable(self, entry):
        index, sub, bits = entry >> 16, (entry >> 8) & 0xFF, entry & 0xFF
        try:
            obj = self.node.object_dictionary[index]
            var = obj[sub] if hasattr(obj, "subindices") and obj.subindices else obj
        except KeyError:
            return None
        if not var.pdo_mappable or len(var) != bits:
            return None
        return var

    # -- CiA 402 -------------------------------------------------------------
    def statusword(self):
        sw = STATE_BITS[self.state] | SW_REMOTE
        if self.state in (READY, SWITCHED_ON, ENABLED, QUICK_STOP):
            sw |= SW_VOLTAGE_ENABLED
        if self.state in (READY, SWITCHED_ON, ENABLED):
            sw |= SW_QUICK_STOP
        if self.limited and self.state == ENABLED:
            sw |= SW_INTERNAL_LIMIT
        if self.state == ENABLED and self.cached(0x6060, lambda: self.od(0x6060)) == MODE_CSP:
            sw |= SW_TARGET_FOLLOWED
            window = self.cached(0x6065, lambda: self.opt(0x6065, 0, 0xFFFFFFFF))
            demand = self.limit(self.target)
            if window != 0xFFFFFFFF and abs(demand - self.pos) > window:
                sw |= SW_FOLLOWING_ERROR
        return sw

    def _controlword(self, cw):
        before = self.state
        quick_stop_option = self.opt(0x605A, 0, 2)
        self.state = next_state(self.state, cw, self.cw, quick_stop_option)
        self.cw = cw
        if self.state == QUICK_STOP and quick_stop_option in (1, 2, 3, 4):
            self.state = SWITCH_ON_DISABLED  # stopped at once, then 0x605A 1..4 say disabled
        if before == FAULT and self.state != FAULT:
            self.fault_code = 0
            self.error_register = 0
            self._emcy(0x0000, 0)
        if self.state != ENABLED:
            self.target = int(round(self.pos))
        self._event_tpdos()

    def fault(self, code=EMCY_DEFAULT_FAULT):
        self.state = FAULT
        self.fault_code = code
        self.error_register |= ERROR_REGISTER_GENERIC
        self.target = int(round(self.pos))
        self._emcy(code, self.error_register)
        self._event_tpdos()

    def _emcy(self, code, register):
        self.events.append(("emcy", code))
        if not self.silent:
            self.node.emcy.send(code, register)

    def _comm_error(self, code):
        """A communication EMCY, once until the condition clears."""
        if code not in self.emcy_sent:
            self.emcy_sent.add(code)
            self.error_register |= ERROR_REGISTER_COMMUNICATION
            self._emcy(code, self.error_register)

    # -- NMT -----------------------------------------------------------------
    @property
    def nmt(self):
        return self.node.nmt._state

    def boot(self):
        """Power on or reset: boot-up, then pre-operational with the EDS's
        heartbeat time."""
        self.node.nmt._state = NMT_INITIALISING
        self.node.nmt.stop_heartbeat()
        if not self.silent:
            self.network.send_message(0x700 + self.id, [0])
        self.node.nmt._state = NMT_PRE_OPERATIONAL
        hb = self.od(0x1017)
        if hb and not self.silent:
            self.node.nmt.start_heartbeat(hb)

    def on_nmt(self, can_id, data, timestamp):
        if len(data) < 2 or data[1] not in (0, self.id):
            return
        if data[0] == 0x81:  # reset node
            self._reset_communication()
            self._reset_application()
            self.boot()
        elif data[0] == 0x82:  # reset communication
            self._reset_communication()
            self.boot()

    # -- PDOs ----------------------------------------------------------------
    def _pdos(self, comm_base, map_base):
        """[(number, cob id, transmission type, [mapping entries])] of the
        valid PDOs."""
        return self.cached(comm_base, lambda: self._read_pdos(comm_base, map_base))

    def _read_pdos(self, comm_base, map_base):
        out = []
        for k in range(2):
            if comm_base + k not in self.node.object_dictionary:
                continue
            cob = self.od(comm_base + k, 1)
            if cob & 0x80000000:
                continue
            n = self.od(map_base + k, 0)
            out.append((k, cob & 0x7FF, self.od(comm_base + k, 2), [self.od(map_base + k, s) for s in range(1, n + 1)]))
        return out

    def on_frame(self, can_id, data, timestamp):
        """Every frame the network hands over (SYNC, RPDOs, heartbeats)."""
        if can_id == self.cached(0x1005, lambda: self.opt(0x1005, 0, 0x80) & 0x7FF):
            self._on_sync(data)
            return
        if 0x700 < can_id < 0x780 and len(data) >= 1:
            self.heard[can_id - 0x700] = timestamp
            return
        if self.nmt != NMT_OPERATIONAL:
            return
        for k, cob, _, entries in self._pdos(0x1400, 0x1600):
            if cob == can_id:
                need = sum(e & 0xFF for e in entries) // 8
                if len(data) < need:
                    self._comm_error(EMCY_PDO_LENGTH)
                elif len(data) > need:
                    self._comm_error(EMCY_PDO_LENGTH_EXCEEDED)
                else:
                    self.pending[k] = bytes(data)

    def _apply_rpdo(self, entries, data):
        at = 0
        for e in entries:
            index, sub, nbytes = e >> 16, (e >> 8) & 0xFF, (e & 0xFF) // 8
            raw = data[at:at + nbytes]
            at += nbytes
            obj = self.node.object_dictionary[index]
            var = obj[sub] if hasattr(obj, "subindices") and obj.subindices else obj
            value = var.decode_raw(raw)
            if not self._act_on(index, value):
                self.node.data_store.setdefault(index, {})[sub] = bytes(raw)
                self._cache = {}

    def _tpdo_data(self, entries):
        out = b""
        for e in entries:
            index, sub = e >> 16, (e >> 8) & 0xFF
            out += self.node.get_data(index, sub)
        return out

    def _send_tpdos(self, at_sync):
        for k, cob, ttype, entries in self._pdos(0x1800, 0x1A00):
            data = self._tpdo_data(entries)
            changed = self.tpdo_last.get(k) != data
            if at_sync and 1 <= ttype <= 240:
                due = self.sync_count % ttype == 0
            elif at_sync and ttype == 0:
                due = changed
            elif ttype >= 254:
                due = changed
            else:
                due = False
            if due:
                self.tpdo_last[k] = data
                if not self.silent:
                    self.network.send_message(cob, data)

    def _event_tpdos(self):
        if self.nmt == NMT_OPERATIONAL:
            self._send_tpdos(at_sync=False)

    def _on_sync(self, data):
        overflow = self.cached(0x1019, lambda: self.opt(0x1019, 0, 0))
        if len(data) != (1 if overflow else 0):
            self.events.append(("sync_error", len(data)))
            self._comm_error(EMCY_SYNC_LENGTH)
            return
        self.sync_count += 1
        if self.nmt != NMT_OPERATIONAL:
            self.pending = {}
            return
        rpdos = {k: entries for k, _, ttype, entries in self._pdos(0x1400, 0x1600) if ttype <= 240}
        for k in sorted(self.pending):
            if k in rpdos:
                self._apply_rpdo(rpdos[k], self.pending[k])
        self.pending = {}
        self._move()
        self._send_tpdos(at_sync=True)

    def limit(self, target):
        """target held within the software position limits (0x607D; none
        where min > max)."""
        lo, hi = self.cached(0x607D, lambda: (self.opt(0x607D, 1, 1), self.opt(0x607D, 2, 0)))
        return min(max(target, lo), hi) if lo <= hi else target

    def _move(self):
        if self.state != ENABLED or self.cached(0x6060, lambda: self.od(0x6060)) != MODE_CSP:
            self.target = int(round(self.pos))
            self.limited = False
            return
        goal = self.limit(self.target)
        self.limited = goal != self.target
        if self.lag_s <= 0:
            self.pos = float(goal)
            return
        period = self.opt(0x60C2, 1, 1) * 10.0 ** self.opt(0x60C2, 2, -3)
        self.pos += (goal - self.pos) * min(1.0, period / self.lag_s)

    # -- heartbeat consumer ----------------------------------------------------
    def check_consumers(self, now):
        """The heartbeat consumer at now (time.time(), the clock of the
        frames' receive timestamps), called only once every frame received
        so far has been handled."""
        n = self.opt(0x1016, 0, 0)
        for s in range(1, n + 1):
            entry = self.od(0x1016, s)
            node, ms = (entry >> 16) & 0x7F, entry & 0xFFFF
            if not node or not ms or node not in self.heard:
                continue
            if now - self.heard[node] > ms / 1000.0:
                if not self.master_lost:
                    self.master_lost = True
                    self.events.append(("master_lost", node))
                    self._lost_master()
            elif self.master_lost:
                self.master_lost = False
                self.emcy_sent.discard(EMCY_HEARTBEAT)

    def _lost_master(self):
        reaction = self.opt(0x6007, 0, 1)  # CiA 402's default: a malfunction (fault)
        if reaction == 1:
            self.emcy_sent.add(EMCY_HEARTBEAT)
            self.fault(EMCY_HEARTBEAT)
            return
        self.error_register |= ERROR_REGISTER_COMMUNICATION
        self._comm_error(EMCY_HEARTBEAT)
        if reaction == 2:
            self._controlword(0x0000)
        elif reaction == 3:
            self._controlword(0x0002)


RECEIVE_WAIT_S = 0.1  # the longest a read waits on SocketCAN (python-can's receive thread then looks up)


def survive_link_loss(bus):
    """A powered drive outlives its bus: while the interface is down
    (ENETDOWN and the like) python-can's receive raises, which would end the
    stack's receive thread for good; here it waits and tries again, and a
    frame that cannot go out is lost, as on a real bus.

    On SocketCAN a frame costs one system call each way: the socket blocks
    with the kernel's receive timeout (canraw.receive_timeout) rather than
    python-can's poll before every read, and a frame is written without a
    poll for room first (a full queue loses it). In User Mode Linux, where
    a system call is dear, the drives' receive thread spent 40-50 % of the
    CPU on a 100 Hz bus cycle with the polls, 2-6 % without, and with them
    fell seconds behind the bus (the master's SDO and enable timeouts)."""
    import can
    recv, send = bus._recv_internal, bus.send
    sock = getattr(bus, "socket", None)
    if sock is not None:
        from can.interfaces.socketcan import socketcan
        from kinctl import canraw
        canraw.receive_timeout(sock, RECEIVE_WAIT_S)

        def recv(timeout):
            try:
                return socketcan.capture_message(sock), bus._is_filtered
            except can.CanOperationError as e:
                if canraw.timed_out(e.__cause__):
                    return None, False
                raise

        def send(msg, timeout=None):
            try:
                sock.send(socketcan.build_can_frame(msg))
            except OSError as e:
                raise can.CanOperationError(f"Failed to transmit: {e.strerror}", e.errno) from e

    def recv_surviving(timeout):
        try:
            return recv(timeout)
        except can.CanOperationError:
            time.sleep(timeout if timeout else 0.05)
            return None, False

    def send_surviving(msg, timeout=None):
        try:
            send(msg, timeout)
        except can.CanOperationError:
            pass

    bus._recv_internal = recv_surviving
    bus.send = send_surviving


class Drives:
    """Drives at node ids on a SocketCAN interface, one canopen.Network."""

    def __init__(self, channel, nodes, eds=None, start_counts=None, lag_s=0.0, tick_s=0.005, interface="socketcan",
                 **preset_args):
        """preset_args: presets()'s power-on values (period_s, heartbeat_ms,
        window, configured)."""
        import canopen
        self.network = canopen.Network()
        self.network.connect(interface=interface, channel=channel, receive_own_messages=False)
        survive_link_loss(self.network.bus)
        sock = getattr(self.network.bus, "socket", None)
        if sock is not None:
            # A busy host (or an emulated one) must find the frames waiting,
            # not dropped by the kernel: 8 MiB, as kinctld's own socket
            # (beyond rmem_max when root).
            from kinctl import canraw
            canraw.size_receive_buffer(sock, 8 << 20)
        self.lock = threading.RLock()
        eds = eds or default_eds()
        starts = start_counts or {}
        self.drives = {n: Drive(self.network, n, eds, starts.get(n, 1000 * n + 123), lag_s, presets(n, **preset_args))
                       for n in nodes}
        for cid in range(0x000, 0x800):
            if cid == 0 or cid >= 0x080 and not 0x580 <= cid < 0x680:
                self.network.subscribe(cid, self._dispatch)
        self.tick_s = tick_s
        self.running = True
        self.thread = threading.Thread(target=self._tick, daemon=True)
        self.thread.start()
        with self.lock:
            for d in self.drives.values():
                d.boot()

    def _dispatch(self, can_id, data, timestamp):
        with self.lock:
            for d in self.drives.values():
                if can_id == 0:
                    d.on_nmt(can_id, data, timestamp)
                elif can_id != 0x700 + d.id:
                    d.on_frame(can_id, data, timestamp)

    def _caught_up(self):
        """True when no received frame waits in the socket: a heartbeat
        that came in while this process was stalled (a loaded machine,
        User Mode Linux) is then handled, so a silence is the master's and
        not this process's own. Always true on a bus without a socket."""
        sock = getattr(self.network.bus, "socket", None)
        if sock is None:
            return True
        try:
            return not select.select([sock], [], [], 0)[0]
        except (OSError, ValueError):
            return True

    def _tick(self):
        while self.running:
            time.sleep(self.tick_s)
            with self.lock:
                if not self._caught_up():
                    continue
                now = time.time()
                for d in self.drives.values():
                    d.check_consumers(now)

    def command(self, line):
        """One control line (the module's text); returns the reply.
        ValueError for a bad line."""
        verb, args, d = control_line(self, line, ("fault", "silent", "talk", "lag", "reboot", "preop", "state"),
                                     CONTROL_USAGE)
        if d is None:
            return "ok quit"
        with self.lock:
            if verb == "fault":
                d.fault(int(args[1], 0) if len(args) > 1 else EMCY_DEFAULT_FAULT)
            elif verb == "silent":
                d.silent = True
                d.node.nmt.stop_heartbeat()
            elif verb == "talk":
                d.silent = False
                if d.od(0x1017):
                    d.node.nmt.start_heartbeat(d.od(0x1017))
            elif verb == "lag":
                if len(args) != 2 or not float(args[1]) >= 0:
                    raise ValueError("lag needs a node id and seconds >= 0")
                d.lag_s = float(args[1])
            elif verb == "preop":
                d.node.nmt.state = "PRE-OPERATIONAL"
            elif verb == "reboot":
                d._reset_communication()
                d._reset_application()
                d.boot()
            else:
                return (f"ok state {d.id} {d.nmt} {d.state.replace(' ', '_')} 0x{d.statusword():04x} "
                        f"{int(round(d.pos))}")
        return "ok " + " ".join(line.split())

    def close(self):
        self.running = False
        self.thread.join(1)
        for d in self.drives.values():
            d.node.nmt.stop_heartbeat()
        self.network.disconnect()


def parse_starts(text, nodes):
    """'1=1000,2=-5000' -> {1: 1000, 2: -5000}; ValueError otherwise."""
    out = {}
    for part in filter(None, (p.strip() for p in (text or "").split(","))):
        node, _, counts = part.partition("=")
        try:
            out[int(node)] = int(counts, 0)
        except ValueError:
            raise ValueError(f"--start {text!r}: expected NODE=COUNTS,... e.g. 1=1000,2=-5000") from None
    unknown = sorted(set(out) - set(nodes))
    if unknown:
        raise ValueError(f"--start names nodes {unknown} that are not in --nodes")
    return out


def control_line(sim, line, verbs, usage):
    """One control line: (verb, arguments, drive) for one of verbs followed
    by the node id of one of sim.drives, or ("quit", [], None) once quit has
    stopped sim (sim.running). ValueError otherwise; usage lists the
    commands."""
    words = line.split()
    if not words:
        raise ValueError("empty command")
    verb, args = words[0], words[1:]
    if verb == "quit":
        sim.running = False
        return verb, args, None
    if verb not in verbs or not args:
        raise ValueError(f"unknown command {line!r} ({usage})")
    node = int(args[0])
    if node not in sim.drives:
        raise ValueError(f"no drive with node id {node}")
    return verb, args, sim.drives[node]


def serve_control(sim, no_stdin, alive):
    """Answers control lines on stdin with sim.command's replies (or
    "error ...") until quit or the end of input; with no_stdin, waits while
    alive() holds instead."""
    if no_stdin:
        while alive():
            time.sleep(0.5)
        return
    for line in sys.stdin:
        line = line.strip()
        if not line:
            continue
        try:
            print(sim.command(line), flush=True)
        except ValueError as e:
            print(f"error {e}", flush=True)
        if not sim.running:
            break


def run(args):
    """`kinctl drivesim` (registered by kinctl.cancmds): serve until stdin
    says quit or closes, or SIGINT."""
    from kinctl.argtypes import parse_nodes
    nodes = parse_nodes(args.nodes)
    starts = parse_starts(args.start, nodes)
    period_s = None if args.period_ms is None else args.period_ms / 1000.0
    if period_s is not None:
        interpolation_period(period_s)  # ValueError (exit 2) before the bus is opened
    try:
        sim = Drives(args.interface, nodes, eds=args.eds, start_counts=starts, lag_s=args.lag, period_s=period_s,
                     heartbeat_ms=args.heartbeat_ms, window=args.window, configured=args.configured)
    except OSError as e:
        raise OSError(f"cannot open CAN interface {args.interface!r}: {e}") from e
    print(f"ready {args.interface} nodes {args.nodes}", flush=True)
    try:
        serve_control(sim, args.no_stdin, lambda: sim.running)
    finally:
        sim.close()
    return 0
