#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Runs C test programs under valgrind memcheck; fails on any error or leak.
The programs, their arguments, environment and working directory are the
ctest tests of BUILD_DIR whose names match REGEX (ctest --show-only), so
each is defined once, in its own CMakeLists.txt. Prints each test's time
under valgrind and the total. The unit tests run the share --share of
their random cases (KINCTL_TEST_SHARE, tests/unit/testutil.h): valgrind
checks the code the cases run, which a share of them runs too; the suites
themselves run every case.
  memcheck.py BUILD_DIR REGEX [--jobs N] [--share S] [--valgrind PATH] [--ctest PATH]"""
import argparse
import concurrent.futures
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

VALGRIND_ARGS = ['--error-exitcode=1', '--leak-check=full', '--quiet']

# The programs that take longest under valgrind, started first (in this
# order) so that those running side by side end near together: of the
# default set's 780 s of CPU, these two took 194 and 116 s; last in
# ctest's order, the set took 441 s two at a time, 390 s being the least.
LONGEST_FIRST = ('unit.ctrl_cartstop.double', 'unit.check_slow.double')


def tests_of(ctest, build, regex, share):
    out = subprocess.run([ctest, '--test-dir', build, '--show-only=json-v1', '-R', regex],
                         check=True, capture_output=True, text=True).stdout
    tests = []
    for t in json.loads(out)['tests']:
        props = {p['name']: p['value'] for p in t.get('properties', [])}
        env = dict(os.environ, KINCTL_TEST_SHARE=str(share))
        for kv in props.get('ENVIRONMENT', []):
            k, _, v = kv.partition('=')
            env[k] = v
        tests.append((t['name'], t['command'], env, props.get('WORKING_DIRECTORY', build)))
    return tests


def run(valgrind, name, command, env, cwd):
    with tempfile.NamedTemporaryFile('w+', prefix='memcheck-', suffix='.log') as log:
        start = time.monotonic()
        p = subprocess.run([valgrind, *VALGRIND_ARGS, f'--log-file={log.name}', *command], env=env, cwd=cwd,
                           stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        took = time.monotonic() - start
        log.seek(0)
        report = log.read()
    return name, p.returncode, took, report, p.stderr


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('build')
    ap.add_argument('regex')
    ap.add_argument('--jobs', type=int, default=2)
    ap.add_argument('--share', type=float, default=0.25,
                    help='share of the unit tests\' random cases to run (0 < S <= 1; default 0.25)')
    ap.add_argument('--valgrind', default='valgrind')
    ap.add_argument('--ctest', default='ctest')
    a = ap.parse_args()
    if not 0.0 < a.share <= 1.0:
        ap.error(f'--share {a.share}: not a share (0 < S <= 1)')
    valgrind = shutil.which(a.valgrind)
    if valgrind is None:
        sys.exit(f'{a.valgrind} not found (scripts/setup.sh installs valgrind)')
    tests = tests_of(a.ctest, a.build, a.regex, a.share)
    if not tests:
        sys.exit(f'no ctest test matches {a.regex!r} in {a.build}')
    tests.sort(key=lambda t: LONGEST_FIRST.index(t[0]) if t[0] in LONGEST_FIRST else len(LONGEST_FIRST))
    failed = []
    start = time.monotonic()
    with concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
        for name, rc, took, report, stderr in pool.map(lambda t: run(valgrind, *t), tests):
            print(f'{name:24s} {took:7.1f} s  {"ok" if rc == 0 and not report.strip() else "FAILED"}', flush=True)
            if rc != 0 or report.strip():
                failed.append(name)
                sys.stdout.write(report + stderr[-4000:])
    print(f'memcheck: {len(tests)} tests, {len(failed)} failed, {time.monotonic() - start:.1f} s '
          f'with {a.jobs} at a time')
    if failed:
        print('failed: ' + ' '.join(failed))
        sys.exit(1)


if __name__ == '__main__':
    main()
