# SPDX-License-Identifier: BSD-3-Clause
"""kinctl.programs.find: the environment variable, else the checkout's
build/, else PATH; the first executable one."""
import os

import pytest

from kinctl import programs


def executable(path):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write("#!/bin/sh\n")
    os.chmod(path, 0o755)
    return str(path)


@pytest.mark.parametrize("name", sorted(programs.PROGRAMS))
def test_search_order(name, tmp_path, monkeypatch):
    variable, build_dir = programs.PROGRAMS[name]
    checkout, bin_dir = tmp_path / "checkout", tmp_path / "bin"
    monkeypatch.setattr(programs, "SOURCE_DIR", str(checkout))
    monkeypatch.setenv("PATH", str(bin_dir))
    monkeypatch.delenv(variable, raising=False)
    with pytest.raises(FileNotFoundError, match=f"{name} not found: build it .* or set {variable}"):
        programs.find(name)
    on_path = executable(bin_dir / name)
    assert programs.find(name) == on_path
    built = executable(checkout / "build" / build_dir / name)
    assert programs.find(name) == built
    chosen = executable(tmp_path / "elsewhere" / name)
    monkeypatch.setenv(variable, chosen)
    assert programs.find(name) == chosen
    # A variable naming nothing executable is passed over.
    os.chmod(chosen, 0o644)
    assert programs.find(name) == built


def test_the_build_under_test():
    """Under ctest the variables name this build's programs."""
    for name in ("kinctld", "kinctl-calc", "kinctl-replay"):
        variable = programs.PROGRAMS[name][0]
        if not os.environ.get(variable):
            pytest.skip(f"{variable} is not set (run through ctest)")
        assert programs.find(name) == os.environ[variable]
