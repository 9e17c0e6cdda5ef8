#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# install.deb: `cpack -G DEB` of this build (into a temporary directory, not
# the build tree), then dpkg-deb -c and -f: the package holds what
# `cmake --install` installs, below /usr, and its Depends (dpkg-shlibdeps)
# name the run-time libraries. Exit 77 (skipped) without dpkg-dev.
#
#   test_deb.sh BUILD_DIR REAL
set -euo pipefail
build=$1 real=$2
for tool in dpkg-deb dpkg-shlibdeps; do
    command -v "$tool" >/dev/null || { echo "SKIP: $tool is missing (Debian package dpkg-dev)"; exit 77; }
done
tmp=$(mktemp -d "${TMPDIR:-/tmp}/kinctl-deb.XXXXXX")
trap 'rm -rf "$tmp"' EXIT

fail() { echo "FAIL: $*" >&2; exit 1; }

cpack -G DEB --config "$build/CPackConfig.cmake" -B "$tmp" >"$tmp/cpack.log" 2>&1 ||
    { cat "$tmp/cpack.log" >&2; fail "cpack -G DEB"; }
deb=$(ls "$tmp"/kinctl_*.deb)
echo "built $(basename "$deb") ($(stat -c %s "$deb") bytes)"
dpkg-deb -c "$deb" | awk '{print $6}' | sed 's|^\./|/|' >"$tmp/contents"

expected=(
    /usr/bin/kinctld /usr/bin/kinctl-calc
    /usr/lib/libkinctl_core_$real.a /usr/lib/libkinctl_desc.a
    /usr/include/kinctl/kinctl.h /usr/include/kinctl/real.h /usr/include/kinctl/ctrl.h /usr/include/kinctl/desc.h
    /usr/lib/cmake/kinctl/kinctlConfig.cmake /usr/lib/cmake/kinctl/kinctlConfigVersion.cmake
    /usr/lib/cmake/kinctl/kinctlTargets.cmake
    /usr/lib/systemd/system/kinctld.service
    /usr/share/kinctl/models/puma560.cfg /usr/share/kinctl/models/panda.cfg
    /usr/share/kinctl/lcmtypes/setpoint_t.lcm
    /usr/share/kinctl/python/kinctl_msgs/__init__.py /usr/share/kinctl/python/kinctl_msgs/setpoint_t.py
    /usr/share/doc/kinctl/README.md
    /usr/share/doc/kinctl/LICENSE /usr/share/doc/kinctl/copyright /usr/share/doc/kinctl/LCM-COPYING
    "/usr/share/kinctl/python/kinctl-$(dpkg-deb -f "$deb" Version)-py3-none-any.whl"
)
for f in "${expected[@]}"; do
    grep -qxF "$f" "$tmp/contents" || fail "$f is not in the package"
done
# The jar is built unless KINCTL_LCM_JAVA is off.
if grep -q '^KINCTL_LCM_JAVA:BOOL=ON' "$build/CMakeCache.txt"; then
    grep -qxF /usr/share/kinctl/java/kinctl_lcmtypes.jar "$tmp/contents" || fail "the jar is not in the package"
fi
# Nothing outside /usr, no liblcm copy, no Python caches.
if grep -vE '^/usr(/|$)' "$tmp/contents" | grep -v '^/$'; then
    fail "files outside /usr"
fi
if grep -E 'liblcm|__pycache__|\.pyc$' "$tmp/contents"; then
    fail "unexpected files in the package"
fi
echo "contents: $(grep -vc '/$' "$tmp/contents") files, every expected one present"

# The license: BSD-3-Clause in Debian's copyright format, LCM's LGPL-2.1
# text for the statically linked liblcm.
dpkg-deb --fsys-tarfile "$deb" | tar -xO ./usr/share/doc/kinctl/copyright >"$tmp/copyright"
grep -qx 'License: BSD-3-Clause' "$tmp/copyright" || fail "copyright: no License: BSD-3-Clause"
grep -qx 'License: BSD-3-Clause and LGPL-2.1' "$tmp/copyright" || fail "copyright: kinctld's LGPL-2.1 part"
dpkg-deb --fsys-tarfile "$deb" | tar -xO ./usr/share/doc/kinctl/LCM-COPYING >"$tmp/LCM-COPYING"
grep -q 'GNU LESSER GENERAL PUBLIC LICENSE' "$tmp/LCM-COPYING" && grep -q 'Version 2.1' "$tmp/LCM-COPYING" ||
    fail "LCM-COPYING is not LCM's LGPL-2.1 text"
echo "license: BSD-3-Clause (copyright), LCM's LGPL-2.1 in LCM-COPYING"

depends=$(dpkg-deb -f "$deb" Depends)
echo "Depends: $depends"
for d in libc6 libconfig9 libjansson4 libglib2.0-0; do
    grep -qE "(^|, )$d( |,|$)" <<<"$depends" || fail "Depends lacks $d"
done
[[ $(dpkg-deb -f "$deb" Package) == kinctl ]] || fail "package name"
