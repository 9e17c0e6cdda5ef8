#!/bin/sh
# SPDX-License-Identifier: BSD-3-Clause
# Proves the fixed-point kinematics integer-only: the objects given (fx.c's
# and fx_interp.c's, for a Cortex-M3 and a Cortex-M4F) import no float or
# double helper and no libm function, and contain no floating-point
# instruction (on the M4F, any VFP mnemonic: vadd, vmul, vmov, vldr...).
# Usage: check_integer_only.sh NM OBJDUMP OBJECT...
set -eu
nm=$1
objdump=$2
shift 2
status=0
for obj in "$@"; do
    "$nm" "$obj" >/dev/null
    bad=$("$nm" -u "$obj" | awk '{print $NF}' |
        grep -E '^(__aeabi_[fd].*|__aeabi_[a-z0-9]*2[fd]|__.*[sd]f[23]|__(fix|float).*[sd]f.*|__extendsfdf2|__truncdfsf2|[a-z0-9]+f?)$' |
        grep -vE '^(memcpy|memset|memmove)$' || true)
    insns=$("$objdump" -d "$obj" | awk -F'\t' 'NF >= 3 && $3 ~ /^v[a-z]/ {print $3}' | sort -u | tr '\n' ' ')
    if [ -n "$bad" ] || [ -n "$insns" ]; then
        echo "FAIL: $obj: imports [$(echo $bad)] floating-point instructions [$insns]"
        status=1
    else
        echo "ok: $obj: integer only (imports: $("$nm" -u "$obj" | awk '{print $NF}' | tr '\n' ' '))"
    fi
done
exit $status
