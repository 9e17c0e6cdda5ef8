# SPDX-License-Identifier: BSD-3-Clause
"""kinctld's CAN frames as a DBC database: kinctld as the CANopen master of
CiA 402 drives (CiA 301 predefined connection set, daemon/README.md).

The repository's kinctl.dbc (beside this file) is `make_dbc()` for drive
nodes 1..16 and the master's default id 127: tests check that the file is
what this writes, and `kinctl candecode --nodes ... --master ...` builds one
for other ids. Byte order little-endian (Intel) throughout, as CANopen.

    NMT                 0x000      Command (0x82 reset communication, 0x01
                                   start, 0x80 pre-operational, 0x02 stop),
                                   Node (0: all)
    SYNC                0x080      Counter 1..240, only where 0x1019 asks
                                   for it: the frame is 0 or 1 byte (the
                                   DBC's MinLength attribute says 0)
    EMCY_NodeN          0x080 + N  ErrorCode_603F, ErrorRegister_1001,
                                   VendorData (40 bits)
    TPDO1_NodeN         0x180 + N  Statusword_6041 (uint16),
                                   PositionActual_6064 (int32 counts)
    RPDO1_NodeN         0x200 + N  Controlword_6040 (uint16),
                                   TargetPosition_607A (int32 counts)
    RPDO2_NodeN         0x300 + N  VelocityOffset_60B1 (int32 counts/s),
                                   with velocity_offset = true
    SDOResponse_NodeN   0x580 + N  Command, Index, Subindex, Data (expedited;
    SDORequest_NodeN    0x600 + N  with Command 0x80, Data is the abort code)
    Heartbeat_NodeN / Heartbeat_Master   0x700 + id   NMTState

A frame shorter than its message decodes only where the message's
MinLength allows it (min_length()): the empty SYNC.
"""

NMT_ID = 0x000
SYNC_ID = 0x080
EMCY_BASE = 0x080
TPDO_BASE = 0x180
RPDO_BASE = 0x200
RPDO2_BASE = 0x300
SDO_RESPONSE_BASE = 0x580
SDO_REQUEST_BASE = 0x600
HEARTBEAT_BASE = 0x700
DEFAULT_NODES = tuple(range(1, 17))
DEFAULT_MASTER = 127
NMT_STATES = ((0, "BootUp"), (4, "Stopped"), (5, "Operational"), (127, "PreOperational"))
NMT_COMMANDS = ((1, "Start"), (2, "Stop"), (128, "EnterPreOperational"), (129, "ResetNode"),
                (130, "ResetCommunication"))
# CiA 301's emergency codes a CANopen drive raises by itself; the drive's
# own (0x2000..0x7FFF, CiA 402) decode as numbers.
EMCY_CODES = ((0x0000, "ErrorReset"), (0x8110, "CanOverrun"), (0x8120, "CanErrorPassive"),
              (0x8130, "HeartbeatError"), (0x8140, "BusOffRecovered"), (0x8210, "PdoLengthShort"),
              (0x8220, "PdoLengthExceeded"), (0x8240, "SyncLengthUnexpected"), (0x8250, "RpdoTimeout"))
SDO_REQUESTS = ((0x23, "Download4"), (0x27, "Download3"), (0x2B, "Download2"), (0x2F, "Download1"),
                (0x40, "UploadRequest"), (0x80, "Abort"))
SDO_RESPONSES = ((0x43, "Upload4"), (0x47, "Upload3"), (0x4B, "Upload2"), (0x4F, "Upload1"),
                 (0x60, "DownloadResponse"), (0x80, "Abort"))
I32 = "[-2147483648|2147483647]"


def _sdo(frame_id, name, sender, receivers):
    return [f"BO_ {frame_id} {name}: 8 {sender}",
            f' SG_ Command : 0|8@1+ (1,0) [0|255] "" {receivers}',
            f' SG_ Index : 8|16@1+ (1,0) [0|65535] "" {receivers}',
            f' SG_ Subindex : 24|8@1+ (1,0) [0|255] "" {receivers}',
            f' SG_ Data : 32|32@1+ (1,0) [0|4294967295] "" {receivers}', ""]


def _values(frame_id, signal, table):
    return f"VAL_ {frame_id} {signal} " + " ".join(f'{v} "{name}"' for v, name in table) + " ;"


def make_dbc(nodes=DEFAULT_NODES, master=DEFAULT_MASTER):
    """The DBC text for drives at `nodes` and the master at `master`."""
    nodes = sorted(set(int(n) for n in nodes))
    for n in nodes + [int(master)]:
        if not 1 <= n <= 127:
            raise ValueError(f"node id {n} is outside 1..127")
    if master in nodes:
        raise ValueError(f"the master's id {master} is also a drive's")
    drives = [f"Drive{n}" for n in nodes]
    everyone = ",".join(drives)
    out = ['VERSION "kinctl 2"', "", "NS_ :", "", "BS_:", "", "BU_: Master " + " ".join(drives), ""]
    out += [f"BO_ {NMT_ID} NMT: 2 Master",
            f' SG_ Command : 0|8@1+ (1,0) [0|255] "" {everyone}',
            f' SG_ Node : 8|8@1+ (1,0) [0|127] "" {everyone}', ""]
    out += [f"BO_ {SYNC_ID} SYNC: 1 Master",
            f' SG_ Counter : 0|8@1+ (1,0) [1|240] "" {everyone}', ""]
    for n in nodes:
        out += [f"BO_ {EMCY_BASE + n} EMCY_Node{n}: 8 Drive{n}",
                ' SG_ ErrorCode_603F : 0|16@1+ (1,0) [0|65535] "" Master',
                ' SG_ ErrorRegister_1001 : 16|8@1+ (1,0) [0|255] "" Master',
                ' SG_ VendorData : 24|40@1+ (1,0) [0|1099511627775] "" Master', ""]
    for n in nodes:
        out += [f"BO_ {TPDO_BASE + n} TPDO1_Node{n}: 6 Drive{n}",
                ' SG_ Statusword_6041 : 0|16@1+ (1,0) [0|65535] "" Master',
                f' SG_ PositionActual_6064 : 16|32@1- (1,0) {I32} "counts" Master', ""]
    for n in nodes:
        out += [f"BO_ {RPDO_BASE + n} RPDO1_Node{n}: 6 Master",
                f' SG_ Controlword_6040 : 0|16@1+ (1,0) [0|65535] "" Drive{n}',
                f' SG_ TargetPosition_607A : 16|32@1- (1,0) {I32} "counts" Drive{n}', ""]
    for n in nodes:
        out += [f"BO_ {RPDO2_BASE + n} RPDO2_Node{n}: 4 Master",
                f' SG_ VelocityOffset_60B1 : 0|32@1- (1,0) {I32} "counts/s" Drive{n}', ""]
    for n in nodes:
        out += _sdo(SDO_RESPONSE_BASE + n, f"SDOResponse_Node{n}", f"Drive{n}", "Master")
    for n in nodes:
        out += _sdo(SDO_REQUEST_BASE + n, f"SDORequest_Node{n}", "Master", f"Drive{n}")
    for n, who in [(n, f"Drive{n}") for n in nodes] + [(master, "Master")]:
        name = "Heartbeat_Master" if who == "Master" else f"Heartbeat_Node{n}"
        out += [f"BO_ {HEARTBEAT_BASE + n} {name}: 1 {who}",
                ' SG_ NMTState : 0|8@1+ (1,0) [0|127] "" ' + ("Master" if who != "Master" else everyone), ""]
    out.append(f'CM_ BO_ {NMT_ID} "CiA 301 NMT from kinctld: reset communication at boot, start, enter '
               'pre-operational or stop at shutdown; Node 0 addresses every node";')
    out.append(f'CM_ BO_ {SYNC_ID} "CiA 301 SYNC from kinctld, one per bus cycle (sync_every cycles): empty '
               '(0 bytes) by default, the counter 1..N with sync_counter = N (0x1019)";')
    for n in nodes:
        out.append(f'CM_ BO_ {EMCY_BASE + n} "CiA 301 emergency of node {n}: error code (0 = error reset), '
                   'error register 0x1001";')
        out.append(f'CM_ SG_ {TPDO_BASE + n} Statusword_6041 "CiA 402: the power state in bits 0-3, 5, 6; '
                   'bit 12 drive follows the target (CSP), bit 13 following error";')
        out.append(f'CM_ BO_ {RPDO_BASE + n} "CiA 402 cyclic synchronous position: controlword and target of '
                   f'node {n}, acted on at the next SYNC";')
        out.append(f'CM_ SG_ {SDO_REQUEST_BASE + n} Data "expedited data (little-endian, the size in Command), '
                   'or the abort code with Command 0x80";')
    out += ['BA_DEF_ BO_ "MinLength" INT 0 8;',
            f'BA_ "MinLength" BO_ {SYNC_ID} 0;']
    out.append(_values(NMT_ID, "Command", NMT_COMMANDS))
    for n in nodes:
        out.append(_values(EMCY_BASE + n, "ErrorCode_603F", EMCY_CODES))
    for n in nodes:
        out.append(_values(SDO_RESPONSE_BASE + n, "Command", SDO_RESPONSES))
        out.append(_values(SDO_REQUEST_BASE + n, "Command", SDO_REQUESTS))
    for n in nodes + [master]:
        out.append(_values(HEARTBEAT_BASE + n, "NMTState", NMT_STATES))
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


def min_length(msg):
    """The fewest bytes a frame of the cantools message msg may carry: its
    MinLength attribute (the empty SYNC), else its length."""
    attrs = msg.dbc.attributes if msg.dbc is not None else {}
    return attrs["MinLength"].value if "MinLength" in attrs else msg.length


# CiA 402-2's statusword masks: (mask, value, state), the first that matches.
STATUSWORD_STATES = ((0x4F, 0x00, "not_ready_to_switch_on"), (0x4F, 0x40, "switch_on_disabled"),
                     (0x6F, 0x21, "ready_to_switch_on"), (0x6F, 0x23, "switched_on"),
                     (0x6F, 0x27, "operation_enabled"), (0x6F, 0x07, "quick_stop_active"),
                     (0x4F, 0x0F, "fault_reaction_active"), (0x4F, 0x08, "fault"))
# CiA 402-2's device control commands: (mask, value, command), the first
# that matches (bit 7's rising edge is the fault reset).
CONTROLWORD_COMMANDS = ((0x80, 0x80, "fault_reset"), (0x87, 0x06, "shutdown"), (0x8F, 0x07, "switch_on"),
                        (0x8F, 0x0F, "enable_operation"), (0x82, 0x00, "disable_voltage"),
                        (0x86, 0x02, "quick_stop"))
STATUSWORD_BITS = ((11, "internal_limit"), (12, "follows"), (13, "following_error"))


def statusword_state(sw):
    """The CiA 402 power state a statusword shows ('operation_enabled'),
    or None for a pattern the standard does not define."""
    for mask, value, name in STATUSWORD_STATES:
        if sw & mask == value:
            return name
    return None


def statusword_text(sw):
    """'0x1237 operation_enabled follows': the power state and the bits
    kinctld acts on, named."""
    names = [name for bit, name in STATUSWORD_BITS if sw & (1 << bit)]
    return " ".join([f"0x{sw:04x}", statusword_state(sw) or "?"] + ([",".join(names)] if names else []))


def controlword_text(cw):
    """'0x000f enable_operation': the CiA 402 command a controlword gives."""
    for mask, value, name in CONTROLWORD_COMMANDS:
        if cw & mask == value:
            return f"0x{cw:04x} {name}"
    return f"0x{cw:04x}"
