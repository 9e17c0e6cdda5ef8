# SPDX-License-Identifier: BSD-3-Clause
"""kinctld's CAN frames (daemon/can_io.h) as a DBC database.

The repository's kinctl.dbc (beside this file) is `make_dbc()` for drive
nodes 1..16 and the master's default id 127: tests check that the file is
what this writes, and `kinctl candecode --nodes ... --master ...` builds one
for other ids. Byte order little-endian (Intel) throughout, as CANopen.

    SYNC          0x080        Counter (1..240)
    RPDO1_NodeN   0x200 + N    TargetPosition_607A (int32 counts),
                               VelocityOffset_60B1 (int32 counts/s)
    TPDO1_NodeN   0x180 + N    PositionActual_6064 (int32 counts),
                               Statusword_6041 (uint16; bit 3 fault,
                               bit 12 drive follows the target, bit 13
                               following error)
    Heartbeat_NodeN / Heartbeat_Master   0x700 + id   NMTState
"""

SYNC_ID = 0x080
RPDO_BASE = 0x200
TPDO_BASE = 0x180
HEARTBEAT_BASE = 0x700
DEFAULT_NODES = tuple(range(1, 17))
DEFAULT_MASTER = 127
NMT_STATES = ((0, "BootUp"), (4, "Stopped"), (5, "Operational"), (127, "PreOperational"))
I32 = "[-2147483648|2147483647]"


def make_dbc(nodes=DEFAULT_NODES, master=DEFAULT_MASTER):
    """The DBC text for drives at `nodes` and the master at `master`."""
    nodes = sorted(set(int(n) for n in nodes))
    for n in nodes + [int(master)]:
        if not 1 <= n <= 127:
            raise ValueError(f"node id {n} is outside 1..127")
    if master in nodes:
        raise ValueError(f"the master's id {master} is also a drive's")
    drives = [f"Drive{n}" for n in nodes]
    out = ['VERSION "kinctl 1"', "", "NS_ :", "", "BS_:", "", "BU_: Master " + " ".join(drives), ""]
    out += [f"BO_ {SYNC_ID} SYNC: 1 Master",
            ' SG_ Counter : 0|8@1+ (1,0) [1|240] "" ' + ",".join(drives), ""]
    for n in nodes:
        out += [f"BO_ {RPDO_BASE + n} RPDO1_Node{n}: 8 Master",
                f' SG_ TargetPosition_607A : 0|32@1- (1,0) {I32} "counts" Drive{n}',
                f' SG_ VelocityOffset_60B1 : 32|32@1- (1,0) {I32} "counts/s" Drive{n}', ""]
    for n in nodes:
        out += [f"BO_ {TPDO_BASE + n} TPDO1_Node{n}: 6 Drive{n}",
                f' SG_ PositionActual_6064 : 0|32@1- (1,0) {I32} "counts" Master',
                ' SG_ Statusword_6041 : 32|16@1+ (1,0) [0|65535] "" Master', ""]
    for n, who in [(n, f"Drive{n}") for n in nodes] + [(master, "Master")]:
        name = "Heartbeat_Master" if who == "Master" else f"Heartbeat_Node{n}"
        out += [f"BO_ {HEARTBEAT_BASE + n} {name}: 1 {who}",
                ' SG_ NMTState : 0|8@1+ (1,0) [0|127] "" ' + ("Master" if who != "Master" else ",".join(drives)),
                ""]
    out.append(f'CM_ BO_ {SYNC_ID} "CiA 301 SYNC from kinctld, one per bus cycle (sync_every cycles); '
               'the counter is (bus cycle mod 240) + 1";')
    for n in nodes:
        out.append(f'CM_ BO_ {RPDO_BASE + n} "CiA 402 cyclic synchronous position: the target of node {n}, '
                   'acted on at the next SYNC";')
        out.append(f'CM_ SG_ {TPDO_BASE + n} Statusword_6041 "bit 3 fault, bit 12 drive follows the target, '
                   'bit 13 following error";')
    values = " ".join(f'{v} "{name}"' for v, name in NMT_STATES)
    for n in nodes + [master]:
        out.append(f"VAL_ {HEARTBEAT_BASE + n} NMTState {values} ;")
    return "\n".join(out) + "\n"


def repo_dbc_path():
    """The DBC shipped with the package (make_dbc() with the defaults)."""
    import os
    return os.path.join(os.path.dirname(os.path.abspath(__file__)), "kinctl.dbc")


def load(path=None, nodes=None, master=None):
    """A cantools database: the shipped file, another file, or one made for
    the given node ids."""
    import cantools
    if nodes is not None or master is not None:
        return cantools.database.load_string(make_dbc(nodes or DEFAULT_NODES, master or DEFAULT_MASTER), "dbc")
    return cantools.database.load_file(path or repo_dbc_path())


# CiA 402-2's statusword masks: (mask, value, state), the first that matches.
STATUSWORD_STATES = ((0x4F, 0x00, "not_ready_to_switch_on"), (0x4F, 0x40, "switch_on_disabled"),
                     (0x6F, 0x21, "ready_to_switch_on"), (0x6F, 0x23, "switched_on"),
                     (0x6F, 0x27, "operation_enabled"), (0x6F, 0x07, "quick_stop_active"),
                     (0x4F, 0x0F, "fault_reaction_active"), (0x4F, 0x08, "fault"))


def statusword_state(sw):
    """The CiA 402 power state a statusword shows ('operation_enabled'),
    or None for a pattern the standard does not define."""
    for mask, value, name in STATUSWORD_STATES:
        if sw & mask == value:
            return name
    return None


STATUSWORD_BITS = ((3, "fault"), (12, "follows"), (13, "following_error"))


def statusword_text(sw):
    """'0x1237 follows' etc.: the bits kinctld acts on, named."""
    names = [name for bit, name in STATUSWORD_BITS if sw & (1 << bit)]
    return f"0x{sw:04x}" + ("" if not names else " " + ",".join(names))
