# SPDX-License-Identifier: BSD-3-Clause
"""Runs a command (User Mode Linux's `linux`) with PTRACE_GETREGSET of
NT_X86_XSTATE refused (EIO) by a seccomp filter.

Why: UML 6.1 (Debian bookworm's user-mode-linux) saves and restores its
processes' FPU state with PTRACE_GETREGSET/SETREGSET NT_X86_XSTATE in a
buffer of its own fixed size; a host whose XSAVE area is larger (AVX-512,
AMX) refuses the SETREGSET (EFAULT) and UML panics at its first process
("ptrace set fp regs failed, errno = 14"). With the probe refused UML falls
back to PTRACE_GETFPREGS/SETFPREGS (the 512-byte FXSAVE area), which every
x86-64 host accepts. The AVX state beyond it is then not kept across UML's
process switches, so uml_run.sh also tells glibc inside UML not to use AVX
(GLIBC_TUNABLES glibc.cpu.hwcaps).

    python3 uml_seccomp.py linux mem=1G rootfstype=hostfs ...
"""
import ctypes
import os
import platform
import struct
import sys

# struct seccomp_data: nr at 0, arch at 4, args[i] at 16 + 8 i (low word).
BPF_LD_W_ABS, BPF_JEQ_K, BPF_RET_K = 0x20, 0x15, 0x06
SECCOMP_RET_ALLOW, SECCOMP_RET_ERRNO = 0x7FFF0000, 0x00050000
AUDIT_ARCH_X86_64, NR_PTRACE, NR_SECCOMP = 0xC000003E, 101, 317
PTRACE_GETREGSET, NT_X86_XSTATE, EIO = 0x4204, 0x202, 5
PR_SET_NO_NEW_PRIVS, SECCOMP_SET_MODE_FILTER = 38, 1


def stmt(code, k):
    return struct.pack("HBBI", code, 0, 0, k)


def jeq_else_allow(k):
    """if A == k: go on, else allow."""
    return struct.pack("HBBI", BPF_JEQ_K, 1, 0, k) + stmt(BPF_RET_K, SECCOMP_RET_ALLOW)


class SockFprog(ctypes.Structure):
    _fields_ = [("len", ctypes.c_ushort), ("filter", ctypes.c_void_p)]


def main(argv):
    if len(argv) < 2 or argv[1] in ("-h", "--help"):
        print(__doc__)
        return 0 if len(argv) >= 2 else 2
    if platform.machine() != "x86_64":
        os.execvp(argv[1], argv[1:])  # the problem is x86's XSAVE area
    prog = b"".join([stmt(BPF_LD_W_ABS, 4), jeq_else_allow(AUDIT_ARCH_X86_64),
                     stmt(BPF_LD_W_ABS, 0), jeq_else_allow(NR_PTRACE),
                     stmt(BPF_LD_W_ABS, 16), jeq_else_allow(PTRACE_GETREGSET),
                     stmt(BPF_LD_W_ABS, 32), jeq_else_allow(NT_X86_XSTATE),
                     stmt(BPF_RET_K, SECCOMP_RET_ERRNO | EIO)])
    buf = ctypes.create_string_buffer(prog, len(prog))
    fprog = SockFprog(len(prog) // 8, ctypes.addressof(buf))
    libc = ctypes.CDLL(None, use_errno=True)
    if libc.prctl(PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0) != 0 or \
            libc.syscall(NR_SECCOMP, SECCOMP_SET_MODE_FILTER, 0, ctypes.byref(fprog)) != 0:
        err = ctypes.get_errno()
        print(f"uml_seccomp: cannot install the seccomp filter: {os.strerror(err)}", file=sys.stderr)
        return 1
    os.execvp(argv[1], argv[1:])
    return 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
