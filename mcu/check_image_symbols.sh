#!/bin/sh
# SPDX-License-Identifier: BSD-3-Clause
# Proves what the float core costs on a single-precision FPU: in an image
# that holds the whole core and nothing else (core_only.c), every function
# that is not the core's own must be a float libm function (with newlib's
# float kernels), memcpy/memset/memmove, or a libgcc helper for 32-bit
# floats and 64-bit integers. A double helper (__aeabi_d*, __*df*), a double
# libm function (sin, sqrt...) or an allocator (malloc, _sbrk...) fails with
# its name.
# Usage: check_image_symbols.sh NM IMAGE.elf
set -eu
nm=$1
image=$2
"$nm" "$image" >/dev/null
# Functions of the image (thumb code: T/t), minus the core's public kc_ ones.
funcs=$("$nm" --defined-only "$image" | awk '$2 ~ /^[Tt]$/ {print $3}' | sort -u)
core_objects_funcs=$("$nm" --defined-only "$image" | awk '$2 == "T" && $3 ~ /^kc_/ {print $3}' | wc -l)
forbidden='^(__aeabi_d.*|__aeabi_[ul]?[il]?2d|__aeabi_f2d|__.*df[23]|__.*df.i|__extendsfdf2|__truncdfsf2|__fixunssfdi|__fixsfdi|malloc|free|calloc|realloc|_malloc_r|_free_r|_sbrk|_sbrk_r|sin|cos|tan|sqrt|atan|atan2|hypot|fmod|floor|ceil|exp|log|pow|__ieee754_[a-z0-9]*[^f]|__kernel_[a-z]*[^f])$'
# Global functions that are neither the core's nor in this list fail too
# (the linker script's symbols are addresses, not functions; errno lives
# behind newlib's _global_impure_ptr).
allowed='^(kc_.*|__stack_top|end|__end__|memcpy|memset|memmove|__errno|_global_impure_ptr|[a-z0-9]+f|__ieee754_[a-z0-9_]+f|__kernel_[a-z0-9_]+f|__aeabi_f[a-z0-9]*|__aeabi_[u]?[il]2f|__aeabi_[u]?ldivmod|__aeabi_memcpy[48]?|__aeabi_memset[48]?|__[a-z]*sf[23]|__float[u]?n?[sd]isf|__fix[u]?n?sfsi|__[u]?divmoddi4|__udivmoddi4|__aeabi_ldiv0|__aeabi_idiv0|__aeabi_[u]?idiv(mod)?)$'
bad=""
[ "$core_objects_funcs" -gt 0 ] || bad=" (no kc_ function at all)"
for f in $funcs; do
    if printf '%s\n' "$f" | grep -Eq "$forbidden"; then
        bad="$bad $f"
    fi
done
globals=$("$nm" --defined-only "$image" | awk '$2 == "T" {print $3}' | sort -u)
for f in $globals; do
    case "$f" in kc_core_only_reset) continue ;; esac
    printf '%s\n' "$f" | grep -Eq "$allowed" || bad="$bad $f"
done
imported=$(printf '%s\n' $globals | grep -v '^kc_' | tr '\n' ' ')
if [ -n "$bad" ]; then
    echo "FAIL: $image: the core pulls in$bad"
    echo "(everything outside the core: $imported)"
    exit 1
fi
echo "ok: $image: $core_objects_funcs core functions; from newlib and libgcc only float libm and 32-bit float or integer helpers: $imported"
