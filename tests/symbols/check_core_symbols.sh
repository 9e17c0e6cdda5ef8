#!/bin/sh
# SPDX-License-Identifier: BSD-3-Clause
# Proves "libm only" for the core: every undefined symbol of the static
# library must be a libm function or memcpy/memset/memmove. Anything else
# (malloc, printf, pthread_*, clock_gettime...) fails with its name.
# Usage: check_core_symbols.sh LIBRARY.a [ALLOWED_PREFIX...]
set -eu
lib=$1
shift
allowed='^(memcpy|memset|memmove|sqrtf?|sinf?|cosf?|sincosf?|atan2f?|fabsf?|hypotf?|cbrtf?|fmodf?|floorf?|acosf?|asinf?|atanf?|expf?|logf?|powf?|ceilf?|roundf?|truncf?)$'
# Undefined in some member and defined in none: what the library imports.
defined=$(nm --defined-only --format=posix "$lib" | awk 'NF >= 2 && $2 != "" {print $1}' | sort -u)
undefined=$(nm -u --format=posix "$lib" | awk '$2 == "U" {print $1}' | sort -u | grep -vxF "$defined" || true)
bad=""
for sym in $undefined; do
    if printf '%s\n' "$sym" | grep -Eq "$allowed"; then
        continue
    fi
    ok=0
    for prefix in "$@"; do
        case "$sym" in "$prefix"*) ok=1 ;; esac
    done
    [ "$ok" = 1 ] || bad="$bad $sym"
done
count=$(printf '%s\n' "$undefined" | grep -c . || true)
if [ -n "$bad" ]; then
    echo "FAIL: $lib imports symbols outside libm and memcpy/memset/memmove:$bad"
    exit 1
fi
echo "ok: $lib imports only libm and memory primitives ($count symbols: $(echo $undefined))"
