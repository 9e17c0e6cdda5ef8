#!/bin/sh
# SPDX-License-Identifier: BSD-3-Clause
# Runs the determinism program on the host and on the board; both must end
# every goal as expected (exit 0) and print the same final hash.
# Usage: compare_hash.sh HOST_PROGRAM QEMU_COMMAND...
set -eu
host=$1
shift
echo "== host (x86 float)"
host_out=$("$host") || { printf '%s\n' "$host_out"; echo "FAIL: the host program failed"; exit 1; }
printf '%s\n' "$host_out"
echo "== board ($*)"
board_out=$("$@") || { printf '%s\n' "$board_out"; echo "FAIL: the board program failed"; exit 1; }
printf '%s\n' "$board_out"
h_host=$(printf '%s\n' "$host_out" | sed -n 's/^hash \([0-9a-f]*\)$/\1/p')
h_board=$(printf '%s\n' "$board_out" | sed -n 's/^hash \([0-9a-f]*\)$/\1/p')
if [ -z "$h_host" ] || [ "$h_host" != "$h_board" ]; then
    echo "FAIL: hashes differ: host '$h_host', board '$h_board'"
    exit 1
fi
echo "ok: host and board hash $h_host"
