#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# install.consumer: `cmake --install` of this build into a staging prefix,
# then, from that prefix only:
#   - a consumer program configured and built with CMake against
#     find_package(kinctl) computes FK of puma560 (built-in, and from the
#     installed models/puma560.cfg through kinctl::desc); checked against
#     tests/vectors/fk.json; the same source built as C++ prints the same;
#   - the installed kinctl-calc computes the same pose; kinctld --help runs and
#     kinctld --check accepts the installed example configuration;
#   - neither binary carries an RPATH/RUNPATH, and every library they load
#     resolves outside the build tree and the venv (liblcm is linked in);
#   - the installed wheel (share/kinctl/python) in a fresh venv: `kinctl`
#     and `kinctl_msgs` import from it, `kinctl --help` runs, and `kinctl spy`
#     finds the installed jar beside the kinctld on PATH. The wheel's own
#     dependencies (lcm, tqdm) are the build venv's, named by a .pth file, so
#     the test needs no network.
#
#   test_install.sh BUILD_DIR VECTORS_DIR PYTHON C_COMPILER REAL SANITIZERS
#   (SANITIZERS: the build's -fsanitize= list, or empty)
set -euo pipefail
build=$1 vectors=$2 python=$3 cc=$4 real=$5 sanitizers=${6:-}
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
tmp=$(mktemp -d "${TMPDIR:-/tmp}/kinctl-install.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
prefix=$tmp/prefix

fail() { echo "FAIL: $*" >&2; exit 1; }

cmake --install "$build" --prefix "$prefix" >"$tmp/install.log" 2>&1 || { cat "$tmp/install.log" >&2; fail "cmake --install"; }
for f in bin/kinctld bin/kinctl-calc include/kinctl/kinctl.h include/kinctl/desc.h \
         lib/libkinctl_core_$real.a lib/libkinctl_desc.a lib/cmake/kinctl/kinctlConfig.cmake \
         share/kinctl/models/puma560.cfg lib/systemd/system/kinctld.service \
         share/kinctl/python/kinctl_msgs/setpoint_t.py share/kinctl/python/kinctl-*-py3-none-any.whl; do
    compgen -G "$prefix/$f" >/dev/null || fail "$f not installed"
done
echo "installed into $prefix: $(cd "$prefix" && find . -type f | wc -l) files"

# The consumer, built by a user's CMake against the staging prefix. A
# sanitizer build installs instrumented libraries, so the consumer links the
# sanitizer runtimes too.
# Its C++ build uses the C compiler's sibling (gcc: g++, clang: clang++).
case $(basename "$cc") in
    *clang*) cxx=${cc%clang*}clang++${cc##*clang} ;;
    *gcc*) cxx=${cc%gcc*}g++${cc##*gcc} ;;
    *) cxx=c++ ;;
esac
flags=()
if [[ -n $sanitizers ]]; then
    flags=(-DCMAKE_C_FLAGS="-fsanitize=$sanitizers" -DCMAKE_CXX_FLAGS="-fsanitize=$sanitizers"
           -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=$sanitizers")
fi
cmake -S "$here/consumer" -B "$tmp/consumer" -DCMAKE_C_COMPILER="$cc" -DCMAKE_CXX_COMPILER="$cxx" \
    -DCMAKE_PREFIX_PATH="$prefix" \
    -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF "${flags[@]}" >"$tmp/consumer-configure.log" 2>&1 ||
    { cat "$tmp/consumer-configure.log" >&2; fail "configuring the consumer"; }
grep -- "-- kinctl " "$tmp/consumer-configure.log"
cmake --build "$tmp/consumer" >"$tmp/consumer-build.log" 2>&1 ||
    { cat "$tmp/consumer-build.log" >&2; fail "building the consumer"; }

# One random configuration of puma560 from fk.json and its pose.
read -r -a q < <("$python" -c '
import json, sys
c = json.load(open(sys.argv[1]))["puma560"]["configs"][4]
print(" ".join(repr(v) for v in c["q_rad"]))' "$vectors/fk.json")
qcsv=$(IFS=,; echo "${q[*]}")
"$tmp/consumer/consumer" "$prefix/share/kinctl/models/puma560.cfg" "${q[@]}" >"$tmp/consumer.json" ||
    fail "the consumer failed"
"$tmp/consumer/consumer_cxx" "$prefix/share/kinctl/models/puma560.cfg" "${q[@]}" >"$tmp/consumer_cxx.json" ||
    fail "the consumer built as C++ failed"
cmp -s "$tmp/consumer.json" "$tmp/consumer_cxx.json" ||
    fail "the consumer built as C++ printed $(cat "$tmp/consumer_cxx.json"), in C $(cat "$tmp/consumer.json")"
echo "the consumer built as C++ ($(basename "$cxx")) prints what it does in C"
"$prefix/bin/kinctl-calc" fk --model-file "$prefix/share/kinctl/models/puma560.cfg" --q "$qcsv" >"$tmp/calc.json" ||
    fail "installed kinctl-calc fk failed"
"$python" - "$vectors/fk.json" "$tmp/consumer.json" "$tmp/calc.json" "$real" <<'PY'
import json, sys
vec, got, calc, real = json.load(open(sys.argv[1])), json.load(open(sys.argv[2])), json.load(open(sys.argv[3])), sys.argv[4]
T = vec["puma560"]["configs"][4]["T"]
want = [T[i][j] for i in range(3) for j in range(3)] + [T[i][3] for i in range(3)]
tol = 1e-12 if real == "double" else 2e-5
assert got["real"] == real, f"consumer built for {got['real']}, the library is {real}"
for name, vals in (("consumer, built-in", got["builtin"]), ("consumer, models/puma560.cfg", got["file"]),
                   ("kinctl-calc fk", [calc["pose"][i][j] for i in range(3) for j in range(3)] +
                                      [calc["pose"][i][3] for i in range(3)])):
    err = max(abs(a - b) for a, b in zip(vals, want))
    assert err <= tol, f"{name}: pose differs from fk.json by {err:g} (tolerance {tol:g})"
    print(f"{name}: pose within {err:.1e} of fk.json puma560 config 4 (x = {vals[9]:.6f} m)")
PY

# The installed binaries run from the staging prefix on system libraries only.
"$prefix/bin/kinctld" --help >"$tmp/help.txt" || fail "installed kinctld --help failed"
head -1 "$tmp/help.txt"
"$prefix/bin/kinctld" --config "$prefix/share/kinctl/models/puma560.cfg" --check >"$tmp/check.txt" 2>&1 ||
    { cat "$tmp/check.txt" >&2; fail "installed kinctld --check rejects the installed puma560.cfg"; }
for b in kinctld kinctl-calc; do
    if readelf -d "$prefix/bin/$b" | grep -E 'R(UN)?PATH'; then
        fail "installed $b carries an rpath"
    fi
    libs=$(ldd "$prefix/bin/$b")
    if grep -q "not found" <<<"$libs"; then
        echo "$libs" >&2
        fail "installed $b: a library is not found"
    fi
    if grep -qE "$root|/\.venv/|site-packages" <<<"$libs"; then
        echo "$libs" >&2
        fail "installed $b loads a library from the build tree or a venv"
    fi
done
echo "installed kinctld and kinctl-calc run from $prefix with no rpath"

# The Python tools from the installed wheel, in a fresh venv.
wheel=$(ls "$prefix"/share/kinctl/python/kinctl-*-py3-none-any.whl)
"$python" -m venv "$tmp/venv"
"$python" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])' \
    >"$("$tmp/venv/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')/build-venv-deps.pth"
"$tmp/venv/bin/python" -m pip install -q --no-deps --no-index "$wheel" >"$tmp/pip.log" 2>&1 ||
    { cat "$tmp/pip.log" >&2; fail "pip install $(basename "$wheel")"; }
"$tmp/venv/bin/python" - "$tmp/venv" <<'PY' || fail "kinctl or kinctl_msgs does not come from the wheel"
import sys, kinctl, kinctl_msgs
for m in (kinctl, kinctl_msgs):
    assert m.__file__.startswith(sys.argv[1] + "/"), f"{m.__name__} from {m.__file__}"
    print(f"{m.__name__}: {m.__file__}")
PY
"$tmp/venv/bin/kinctl" --help >"$tmp/kinctl-help.txt" || fail "kinctl --help from the wheel"
head -1 "$tmp/kinctl-help.txt"
spy=$(env -u KINCTL_JAR PATH="$prefix/bin:$(dirname "$python"):$PATH" "$tmp/venv/bin/kinctl" spy --print) ||
    fail "kinctl spy --print from the wheel"
if grep -q '^KINCTL_LCM_JAVA:BOOL=ON' "$build/CMakeCache.txt"; then
    grep -q "^CLASSPATH=$prefix/share/kinctl/java/kinctl_lcmtypes.jar" <<<"$spy" ||
        fail "kinctl spy does not find the installed jar: $spy"
    echo "kinctl spy: $(head -1 <<<"$spy")"
fi
